//! Promotion between every pair of classes by every numeric combination
//! against the same sums, minima, maxima and area weights computed by numpy
//! (np.add.at and friends over the vertex relation), on a mesh of quads and
//! triangles with a point no primitive uses.

#[path = "../../model/tests/common/oracle.rs"]
mod oracle;

use geode_attrib::promote::{promote, Combine};
use geode_geo::glam::Vec3;
use geode_geo::primitives::{box_mesh, uv_sphere};
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, TypeInfo};

const CLASSES: [(AttribClass, &str); 4] = [
    (AttribClass::Point, "point"),
    (AttribClass::Vertex, "vertex"),
    (AttribClass::Primitive, "primitive"),
    (AttribClass::Detail, "detail"),
];

fn values(n: usize, seed: u32) -> Vec<f32> {
    let mut s = seed.wrapping_mul(747796405).max(1);
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            (s % 1000) as f32 / 100.0 - 5.0
        })
        .collect()
}

fn mesh() -> Geometry {
    let b = box_mesh(Vec3::new(1.0, 2.0, 3.0), [2, 3, 1]);
    let mut s = uv_sphere(1.5, 12, 6);
    for p in s.positions_mut() {
        *p += Vec3::X * 4.0;
    }
    let mut g = ops::merge(&[&b, &s]).unwrap();
    g.add_point(Vec3::splat(9.0));
    g
}

fn count(g: &Geometry, c: AttribClass) -> usize {
    geode_attrib::relation::count(g, c)
}

const SCRIPT: &str = r#"
import json, sys
import numpy as np
d = json.load(sys.stdin)
P = np.array(d["P"]); vp = np.array(d["vp"]); off = np.array(d["offsets"])
nv, nprim, npt = len(vp), len(off) - 1, len(P)
pov = np.repeat(np.arange(nprim), np.diff(off))
# Polygon areas by Newell's normal.
area = np.zeros(nprim)
for i in range(nprim):
    pts = P[vp[off[i]:off[i+1]]]
    area[i] = 0.5 * np.linalg.norm(np.cross(pts, np.roll(pts, -1, axis=0)).sum(axis=0))
varea = area[pov] / np.diff(off)[pov]
parea = np.zeros(npt); np.add.at(parea, vp, varea)
n = {"point": npt, "vertex": nv, "primitive": nprim, "detail": 1}
w = {"point": parea, "vertex": varea, "primitive": area, "detail": np.array([area.sum()])}
def pairs(f, t):
    if t == "detail": return np.zeros(n[f], int), np.arange(n[f])
    if f == "detail": return np.arange(n[t]), np.zeros(n[t], int)
    idx = {"point": vp, "vertex": np.arange(nv), "primitive": pov}
    return idx[t], idx[f]
out = {}
for f, t, how in d["requests"]:
    x = np.array(d["values"][f], dtype=np.float64)
    tgt, src = pairs(f, t)
    m = n[t]
    cnt = np.zeros(m); np.add.at(cnt, tgt, 1)
    if how == "sum":
        r = np.zeros(m); np.add.at(r, tgt, x[src])
    elif how == "average":
        r = np.zeros(m); np.add.at(r, tgt, x[src]); r = np.where(cnt > 0, r / np.maximum(cnt, 1), 0)
    elif how == "min":
        r = np.full(m, np.inf); np.minimum.at(r, tgt, x[src])
    elif how == "max":
        r = np.full(m, -np.inf); np.maximum.at(r, tgt, x[src])
    elif how == "area_average":
        ws = w[f][src]
        r = np.zeros(m); np.add.at(r, tgt, ws * x[src])
        tw = np.zeros(m); np.add.at(tw, tgt, ws)
        r = np.where(tw > 0, r / np.where(tw > 0, tw, 1), 0)
    elif how in ("first", "last"):
        r = np.zeros(m); seen = np.zeros(m, bool)
        order = range(len(tgt)) if how == "first" else reversed(range(len(tgt)))
        for k in order:
            if not seen[tgt[k]]:
                r[tgt[k]] = x[src[k]]; seen[tgt[k]] = True
    r = np.where(cnt > 0, r, 0.0)
    out[f"{f}>{t}>{how}"] = r.tolist()
print(json.dumps(out))
"#;

#[test]
fn every_promotion_matches_numpy() {
    let g = mesh();
    let mut attrs = Vec::new();
    let mut inputs = serde_json::Map::new();
    for (k, (c, name)) in CLASSES.iter().enumerate() {
        let v = values(count(&g, *c), k as u32 + 1);
        inputs.insert(name.to_string(), serde_json::json!(v));
        attrs.push(Attribute::from_data(AttribData::Float(v), TypeInfo::None));
    }
    let hows = [
        "average",
        "min",
        "max",
        "sum",
        "area_average",
        "first",
        "last",
    ];
    let mut requests = Vec::new();
    for (f, fname) in CLASSES {
        for (t, tname) in CLASSES {
            if f != t {
                for how in hows {
                    requests.push((f, t, fname, tname, how));
                }
            }
        }
    }
    let input = serde_json::json!({
        "P": g.positions().iter().map(|p| p.to_array()).collect::<Vec<_>>(),
        "vp": g.vertex_points(),
        "offsets": g.prim_offsets(),
        "values": inputs,
        "requests": requests.iter().map(|r| [r.2, r.3, r.4]).collect::<Vec<_>>(),
    });
    let Some(want) = oracle::oracle(SCRIPT, &input) else {
        return;
    };
    for (f, t, fname, tname, how) in requests {
        let attr = &attrs[CLASSES.iter().position(|c| c.0 == f).unwrap()];
        let got = promote(&g, attr, f, t, Combine::from_name(how).unwrap(), &|| false).unwrap();
        let AttribData::Float(got) = got.data() else {
            panic!("float stays float")
        };
        let key = format!("{fname}>{tname}>{how}");
        let want = want[&key].as_array().unwrap();
        assert_eq!(got.len(), want.len(), "{key}");
        for (i, (a, b)) in got.iter().zip(want).enumerate() {
            let b = b.as_f64().unwrap();
            assert!(
                (f64::from(*a) - b).abs() <= 1e-4 * (1.0 + b.abs()),
                "{key} element {i}: geode {a}, numpy {b}"
            );
        }
    }
}

#[test]
fn modes_strings_and_integers() {
    // A strip of three quads: points 0..8, prims 0..3.
    let mut g = geode_geo::primitives::grid(geode_geo::glam::Vec2::new(3.0, 1.0), 3, 1);
    // Primitive ints 2, 7, 7: the mode is 7; their average 5.33 rounds to 5.
    let ints = Attribute::from_data(AttribData::Int(vec![2, 7, 7]), TypeInfo::None);
    let prim = AttribClass::Primitive;
    let det = AttribClass::Detail;
    let none = &|| false;
    let at = |a: Attribute| a.data().get(0);
    assert_eq!(
        at(promote(&g, &ints, prim, det, Combine::Mode, none).unwrap()),
        geode_geo::AttribValue::Int(7)
    );
    assert_eq!(
        at(promote(&g, &ints, prim, det, Combine::Average, none).unwrap()),
        geode_geo::AttribValue::Int(5)
    );
    // Strings: first, last, mode, min, max by text; averaging them is an error.
    let names = geode_geo::StringColumn {
        table: vec!["b".into(), "a".into(), "c".into()],
        indices: vec![0, 2, 2],
    };
    let s = Attribute::from_data(AttribData::String(names), TypeInfo::None);
    let text = |how| match promote(&g, &s, prim, det, how, none).unwrap().data().get(0) {
        geode_geo::AttribValue::String(t) => t,
        v => panic!("{v:?}"),
    };
    assert_eq!(text(Combine::First), "b");
    assert_eq!(text(Combine::Last), "c");
    assert_eq!(text(Combine::Mode), "c");
    assert_eq!(text(Combine::Min), "b");
    assert_eq!(text(Combine::Max), "c");
    assert!(promote(&g, &s, prim, det, Combine::Average, none).is_err());
    // Same class is refused; cancellation is honoured.
    assert!(promote(&g, &ints, prim, prim, Combine::Sum, none).is_err());
    let big = Attribute::from_data(AttribData::Float(vec![1.0; g.num_points()]), TypeInfo::None);
    assert_eq!(
        promote(&g, &big, AttribClass::Point, prim, Combine::Sum, &|| true).unwrap_err(),
        geode_attrib::AttribError::Cancelled
    );
    g.add_point(Vec3::ONE);
}
