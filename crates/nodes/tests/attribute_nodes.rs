//! The attribute and piece nodes through the engine: promote, rename,
//! delete, connectivity, split, and group patterns in every node that takes
//! a group (with errors at the column).

mod common;

use common::{err, geo};
use geode_geo::{AttribClass, AttribData, AttribValue};

const PIECES: &str = r#""b": {"type": "box", "params": {"size": [1, 1, 1]}},
    "s": {"type": "sphere", "params": {"radius": 0.5, "center": [3, 0, 0]}},
    "t": {"type": "torus", "params": {"center": [6, 0, 0]}},
    "m": {"type": "merge", "inputs": ["b", "s", "t"]}"#;

fn ints(g: &geode_geo::Geometry, c: AttribClass, name: &str) -> Vec<i32> {
    match g.attrib(c, name).map(|a| a.data()) {
        Some(AttribData::Int(v)) => v.clone(),
        other => panic!("no int {name}: {other:?}"),
    }
}

#[test]
fn connectivity_counts_the_merged_shapes() {
    let g = geo(
        &format!(r#"{PIECES}, "c": {{"type": "connectivity", "inputs": ["m"]}}"#),
        "c",
    );
    let class = ints(&g, AttribClass::Primitive, "class");
    assert_eq!(class.iter().max(), Some(&2));
    assert_eq!(class[0], 0);
    let g = geo(
        &format!(
            r#"{PIECES}, "c": {{"type": "connectivity", "inputs": ["m"], "params": {{"class": "point", "attribute": "piece"}}}}"#
        ),
        "c",
    );
    assert_eq!(ints(&g, AttribClass::Point, "piece").iter().max(), Some(&2));
    // A point attribute cannot part pieces that meet at points: said so.
    let e = err(
        r#""g": {"type": "grid"}, "c": {"type": "connectivity", "inputs": ["g"], "params": {"by_attribute": "uv"}}"#,
        "c",
    );
    assert!(
        e.contains("`uv` is a point attribute") && e.contains("by_attribute"),
        "{e}"
    );
}

#[test]
fn split_and_blast_take_patterns() {
    let nodes = format!(
        r#"{PIECES}, "c": {{"type": "connectivity", "inputs": ["m"]}},
        "in": {{"type": "split", "inputs": ["c"], "params": {{"group": "@class==1"}}}},
        "out": {{"type": "split", "inputs": ["c"], "params": {{"group": "@class==1", "side": "rest"}}}},
        "bl": {{"type": "blast", "inputs": ["c"], "params": {{"group": "@class=1 0-1"}}}}"#
    );
    let whole = geo(PIECES, "m");
    let sphere = geo(PIECES, "s");
    let inside = geo(&nodes, "in");
    let outside = geo(&nodes, "out");
    assert_eq!(inside.num_prims(), sphere.num_prims());
    assert_eq!(inside.num_points(), sphere.num_points());
    assert_eq!(outside.num_prims(), whole.num_prims() - sphere.num_prims());
    let blasted = geo(&nodes, "bl");
    assert_eq!(
        blasted.num_prims(),
        whole.num_prims() - sphere.num_prims() - 2
    );
}

#[test]
fn a_bad_pattern_names_the_parameter_and_column() {
    let e = err(
        r#""b": {"type": "box"}, "d": {"type": "delete", "inputs": ["b"], "params": {"group": "0-2 3-x"}}"#,
        "d",
    );
    assert!(e.contains("group") && e.contains("column 7"), "{e}");
    let e = err(
        r#""b": {"type": "box"}, "d": {"type": "delete", "inputs": ["b"], "params": {"group": "@Cd.x>0.5"}}"#,
        "d",
    );
    assert!(
        e.contains("column 2") && e.contains("no primitive attribute `Cd`"),
        "{e}"
    );
    let e = err(
        r#""b": {"type": "box"}, "d": {"type": "delete", "inputs": ["b"], "params": {"group": "tpo"}}"#,
        "d",
    );
    assert!(e.contains("no primitive group `tpo`"), "{e}");
}

#[test]
fn a_wrangle_group_takes_the_same_patterns() {
    let g = geo(
        r#""g": {"type": "grid", "params": {"rows": 3, "columns": 3}},
           "w": {"type": "wrangle", "inputs": ["g"], "params": {"group": "0-15:5 ^5", "snippet": "@P.y = 1;"}}"#,
        "w",
    );
    let raised: Vec<usize> = g
        .positions()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.y == 1.0)
        .map(|(i, _)| i)
        .collect();
    assert_eq!(raised, [0, 10, 15]);
}

#[test]
fn promote_moves_and_renames() {
    let g = geo(
        r#""b": {"type": "box"},
           "r": {"type": "attribute_create", "inputs": ["b"], "params": {"name": "w", "class": "point", "type": "float", "value": [2, 0, 0, 0]}},
           "p": {"type": "attribute_promote", "inputs": ["r"], "params": {"name": "w", "from": "point", "to": "detail", "method": "sum"}}"#,
        "p",
    );
    assert!(
        g.attrib(AttribClass::Point, "w").is_none(),
        "deleted from points"
    );
    assert_eq!(
        g.attrib(AttribClass::Detail, "w").unwrap().data().get(0),
        AttribValue::Float(16.0)
    );
    let e = err(
        r#""b": {"type": "box"},
           "p": {"type": "attribute_promote", "inputs": ["b"], "params": {"name": "Cdd", "from": "point", "to": "detail"}}"#,
        "p",
    );
    assert!(e.contains("no point attribute `Cdd`"), "{e}");
}

#[test]
fn rename_and_delete_by_pattern() {
    let nodes = r#""b": {"type": "box"},
        "a1": {"type": "attribute_create", "inputs": ["b"], "params": {"name": "uv1", "class": "point"}},
        "a2": {"type": "attribute_create", "inputs": ["a1"], "params": {"name": "uv2", "class": "point"}},
        "a3": {"type": "attribute_create", "inputs": ["a2"], "params": {"name": "keep", "class": "point"}},
        "rn": {"type": "attribute_rename", "inputs": ["a3"], "params": {"class": "point", "renames": [{"from": "keep", "to": "kept"}]}},
        "d": {"type": "attribute_delete", "inputs": ["rn"], "params": {"point": "uv* ^uv2"}},
        "inv": {"type": "attribute_delete", "inputs": ["rn"], "params": {"point": "kept", "invert": true}}"#;
    let names = |out: &str| {
        let g = geo(nodes, out);
        let mut n: Vec<String> = g
            .attribs(AttribClass::Point)
            .names()
            .map(str::to_owned)
            .collect();
        n.sort();
        n
    };
    assert_eq!(names("d"), ["P", "kept", "uv2"]);
    assert_eq!(names("inv"), ["P", "kept"]);
    let e = err(
        r#""b": {"type": "box"}, "rn": {"type": "attribute_rename", "inputs": ["b"], "params": {"renames": [{"from": "nope", "to": "x"}]}}"#,
        "rn",
    );
    assert!(e.contains("renames") && e.contains("nope"), "{e}");
}

#[path = "../../model/tests/common/oracle.rs"]
mod oracle;

/// Rays straight down from a grid above a triangulated torus, first and
/// farthest hits, against trimesh's ray casting on the same triangles.
#[test]
fn ray_hits_match_trimesh() {
    let nodes = r#""t": {"type": "torus", "params": {"major_radius": 1.0, "minor_radius": 0.4, "rows": 24, "columns": 48}},
        "tri": {"type": "triangulate", "inputs": ["t"]},
        "g": {"type": "grid", "params": {"size": [3.2, 3.2], "rows": 30, "columns": 30, "center": [0.013, 2.0, -0.007]}},
        "first": {"type": "ray", "inputs": ["g", "tri"], "params": {"direction_from": "vector", "direction": [0, -1, 0], "transform": false}},
        "last": {"type": "ray", "inputs": ["g", "tri"], "params": {"direction_from": "vector", "direction": [0, -1, 0], "transform": false, "hit": "farthest", "limit": true, "max_distance": 10}}"#;
    let torus = geo(nodes, "tri");
    let grid = geo(nodes, "g");
    let script = r#"
import json, sys
import numpy as np, trimesh
d = json.load(sys.stdin)
m = trimesh.Trimesh(vertices=np.array(d["v"]), faces=np.array(d["f"]), process=False)
o = np.array(d["o"]); dirs = np.tile([0.0, -1.0, 0.0], (len(o), 1))
loc, ray, tri = m.ray.intersects_location(o, dirs, multiple_hits=True)
first = [[-1, -1.0] for _ in o]; last = [[-1, -1.0] for _ in o]
for l, r, t in zip(loc, ray, tri):
    dist = float(np.linalg.norm(l - o[r]))
    if first[r][0] < 0 or dist < first[r][1]: first[r] = [int(t), dist]
    if last[r][0] < 0 or dist > last[r][1]: last[r] = [int(t), dist]
print(json.dumps({"first": first, "last": last}))
"#;
    let mut input = oracle::mesh_json(&torus);
    input["o"] = serde_json::json!(grid
        .positions()
        .iter()
        .map(|p| p.to_array())
        .collect::<Vec<_>>());
    let Some(want) = oracle::oracle(script, &input) else {
        return;
    };
    for (out, key) in [("first", "first"), ("last", "last")] {
        let g = geo(nodes, out);
        let prims = ints(&g, AttribClass::Point, "hitprim");
        let AttribData::Float(dist) = g.attrib(AttribClass::Point, "dist").unwrap().data() else {
            panic!()
        };
        let mut hits = 0;
        for (i, w) in want[key].as_array().unwrap().iter().enumerate() {
            let (tri, d) = (w[0].as_i64().unwrap(), w[1].as_f64().unwrap());
            assert_eq!(
                prims[i] < 0,
                tri < 0,
                "{key} ray {i}: geode {} trimesh {tri}",
                prims[i]
            );
            if tri >= 0 {
                hits += 1;
                assert!(
                    (f64::from(dist[i]) - d).abs() < 1e-4,
                    "{key} ray {i}: {} against {d}",
                    dist[i]
                );
                // The same triangle, unless the ray passes through an edge.
                if i64::from(prims[i]) != tri {
                    assert!((f64::from(dist[i]) - d).abs() < 1e-6, "{key} ray {i}");
                }
            }
        }
        assert!(hits > 300, "{key}: {hits} hits");
    }
}

#[test]
fn ray_minimum_distance_lands_on_the_sphere() {
    let g = geo(
        r#""s": {"type": "sphere", "params": {"radius": 1.0, "rows": 64, "columns": 128}},
           "p": {"type": "box", "params": {"size": [3, 3, 3]}},
           "r": {"type": "ray", "inputs": ["p", "s"], "params": {"method": "minimum"}}"#,
        "r",
    );
    for q in g.positions() {
        assert!((q.length() - 1.0).abs() < 2e-3, "{q}");
    }
}

#[test]
fn sort_orders_stably_reverses_and_shifts() {
    let nodes = r#""g": {"type": "grid", "params": {"rows": 3, "columns": 3}},
        "x": {"type": "sort", "inputs": ["g"], "params": {"key": "x"}},
        "rx": {"type": "sort", "inputs": ["g"], "params": {"key": "x", "reverse": true, "offset": 1}},
        "r1": {"type": "sort", "inputs": ["g"], "params": {"key": "random", "seed": 4}},
        "r2": {"type": "sort", "inputs": ["g"], "params": {"key": "random", "seed": 4}},
        "pr": {"type": "sort", "inputs": ["g"], "params": {"class": "primitive", "key": "proximity", "point": [10, 0, 10]}}"#;
    let g = geo(nodes, "g");
    let x = geo(nodes, "x");
    let xs: Vec<f32> = x.positions().iter().map(|p| p.x).collect();
    assert!(xs.windows(2).all(|w| w[0] <= w[1]));
    // Stable: equal x keep their input order (ascending z as the grid has them).
    let col: Vec<f32> = x.positions().iter().take(4).map(|p| p.z).collect();
    let input_col: Vec<f32> = g
        .positions()
        .iter()
        .filter(|p| p.x == xs[0])
        .map(|p| p.z)
        .collect();
    assert_eq!(col, input_col);
    // Reversed then shifted by one: the first is the one that was last.
    let rx = geo(nodes, "rx");
    assert_eq!(rx.positions()[0], x.positions()[0]);
    assert_eq!(rx.positions()[1], *x.positions().last().unwrap());
    assert_eq!(
        geo(nodes, "r1").content_hash(),
        geo(nodes, "r2").content_hash()
    );
    assert_ne!(geo(nodes, "r1").positions(), g.positions());
    // The primitive nearest (10, 0, 10) comes first; the shape is unchanged.
    let pr = geo(nodes, "pr");
    let c0: Vec<_> = pr
        .prim_points(0)
        .iter()
        .map(|&p| pr.positions()[p as usize])
        .collect();
    assert!(c0.iter().all(|p| p.x > 0.0 && p.z > 0.0), "{c0:?}");
    assert_eq!(pr.num_prims(), g.num_prims());
}

#[test]
fn measure_areas_pieces_and_curvature() {
    let nodes = r#""b": {"type": "box", "params": {"size": [1, 2, 3]}},
        "s": {"type": "sphere", "params": {"radius": 2, "center": [5, 0, 0], "rows": 48, "columns": 96}},
        "m": {"type": "merge", "inputs": ["b", "s"]},
        "area": {"type": "measure", "inputs": ["b"]},
        "tot": {"type": "measure", "inputs": ["b"], "params": {"accumulate": "total", "measure": "volume"}},
        "vol": {"type": "measure", "inputs": ["m"], "params": {"accumulate": "piece", "measure": "volume", "name": "v"}},
        "h": {"type": "measure", "inputs": ["s"], "params": {"measure": "mean_curvature"}}"#;
    let a = geo(nodes, "area");
    let AttribData::Float(areas) = a.attrib(AttribClass::Primitive, "area").unwrap().data() else {
        panic!()
    };
    assert!((areas.iter().sum::<f32>() - 22.0).abs() < 1e-5);
    let t = geo(nodes, "tot");
    assert!(
        matches!(t.attrib(AttribClass::Detail, "volume").unwrap().data().get(0), AttribValue::Float(v) if (v - 6.0).abs() < 1e-5)
    );
    let v = geo(nodes, "vol");
    let AttribData::Float(vols) = v.attrib(AttribClass::Primitive, "v").unwrap().data() else {
        panic!()
    };
    assert!((vols[0] - 6.0).abs() < 1e-4);
    let sphere = 4.0 / 3.0 * std::f32::consts::PI * 8.0;
    assert!((vols.last().unwrap() / sphere - 1.0).abs() < 0.01);
    let h = geo(nodes, "h");
    let AttribData::Float(hs) = h.attrib(AttribClass::Point, "curvature").unwrap().data() else {
        panic!()
    };
    let mid: Vec<f32> = hs
        .iter()
        .zip(h.positions())
        .filter(|(_, p)| p.y.abs() < 1.0)
        .map(|(h, _)| *h)
        .collect();
    assert!(
        mid.iter().all(|h| (h - 0.5).abs() < 0.01),
        "{:?}",
        &mid[..4]
    );
}

#[test]
fn noise_is_seeded_bounded_animated_and_thread_independent() {
    let nodes = |extra: &str| {
        format!(
            r#""s": {{"type": "sphere", "params": {{"rows": 32, "columns": 64}}}},
        "n": {{"type": "attribute_noise", "inputs": ["s"], "params": {{"element_size": 0.3 {extra}}}}}"#
        )
    };
    let a = common::cook_on(1, &nodes(""), "n");
    let b = common::cook_on(3, &nodes(""), "n");
    assert_eq!(a.content_hash(), b.content_hash());
    let AttribData::Vec3(cd) = a.attrib(AttribClass::Point, "Cd").unwrap().data() else {
        panic!()
    };
    assert!(cd
        .iter()
        .all(|c| c.min_element() >= 0.0 && c.max_element() <= 1.0));
    assert!(
        cd.iter().any(|c| (c.x - c.y).abs() > 0.05),
        "channels are independent"
    );
    let seeded = geo(&nodes(r#", "seed": 3"#), "n");
    assert_ne!(seeded.content_hash(), a.content_hash());
    // Animated: frames differ when it moves, not when it does not.
    let moving = nodes(r#", "speed": [0.1, 0, 0]"#);
    let f1 = common::cook_at(&moving, "n", 1.0).unwrap();
    let f2 = common::cook_at(&moving, "n", 2.0).unwrap();
    assert_ne!(
        f1.as_geometry().unwrap().content_hash(),
        f2.as_geometry().unwrap().content_hash()
    );
    let still1 = common::cook_at(&nodes(""), "n", 1.0).unwrap();
    let still2 = common::cook_at(&nodes(""), "n", 2.0).unwrap();
    assert_eq!(
        still1.as_geometry().unwrap().content_hash(),
        still2.as_geometry().unwrap().content_hash()
    );
    // Float, zero-centred: negative values appear.
    let f = geo(
        &nodes(r#", "name": "n", "type": "float", "range": "zero_centered""#),
        "n",
    );
    let AttribData::Float(v) = f.attrib(AttribClass::Point, "n").unwrap().data() else {
        panic!()
    };
    assert!(v.iter().any(|x| *x < -0.05) && v.iter().any(|x| *x > 0.05));
}

#[test]
fn curl_noise_is_divergence_free() {
    // Seven points: a centre and its neighbours h apart along each axis.
    let h = 1e-3f32;
    let mut pts = vec![[0.3f32, 0.2, 0.1]];
    for axis in 0..3 {
        for s in [-1.0f32, 1.0] {
            let mut q = pts[0];
            q[axis] += s * h;
            pts.push(q);
        }
    }
    let points: Vec<String> = pts
        .iter()
        .map(|q| format!("set({}, {}, {})", q[0], q[1], q[2]))
        .collect();
    let g = geo(
        &format!(
            r#""p": {{"type": "curve_line", "params": {{"points": 2}}}},
            "w": {{"type": "wrangle", "inputs": ["p"], "params": {{"run_over": "detail", "snippet": "removeprim(0, 0, 1); vector q[] = array({}); foreach (vector x; q) addpoint(0, x);"}}}},
            "n": {{"type": "attribute_noise", "inputs": ["w"], "params": {{"noise": "curl", "name": "v", "octaves": 1, "element_size": 0.5}}}}"#,
            points.join(", ")
        ),
        "n",
    );
    let AttribData::Vec3(v) = g.attrib(AttribClass::Point, "v").unwrap().data() else {
        panic!()
    };
    assert_eq!(v.len(), 7);
    let div = (v[2].x - v[1].x + v[4].y - v[3].y + v[6].z - v[5].z) / (2.0 * h);
    let grad = (v[2] - v[1]).length() / (2.0 * h);
    assert!(grad > 0.1, "the field varies: {grad}");
    assert!(
        div.abs() < 0.05 * grad,
        "divergence {div} against gradient {grad}"
    );
}

#[test]
fn transfer_and_blur_through_the_nodes() {
    let nodes = r#""src": {"type": "sphere", "params": {"rows": 16, "columns": 32}},
        "col": {"type": "attribute_noise", "inputs": ["src"], "params": {"element_size": 0.5}},
        "dst": {"type": "sphere", "params": {"rows": 24, "columns": 48, "radius": 1.01}},
        "t": {"type": "attribute_transfer", "inputs": ["dst", "col"]},
        "far": {"type": "attribute_transfer", "inputs": ["dst", "col"], "params": {"use_threshold": true, "threshold": 0.001}},
        "b": {"type": "attribute_blur", "inputs": ["t"], "params": {"name": "Cd", "iterations": 20}},
        "bp": {"type": "attribute_blur", "inputs": ["t"], "params": {"name": "Cd", "method": "proximity", "radius": 0.3, "iterations": 5}}"#;
    let t = geo(nodes, "t");
    let AttribData::Vec3(cd) = t.attrib(AttribClass::Point, "Cd").unwrap().data() else {
        panic!()
    };
    assert!(cd.iter().any(|c| *c != cd[0]));
    // Beyond the threshold nothing is taken: the default (zero).
    let far = geo(nodes, "far");
    let AttribData::Vec3(none) = far.attrib(AttribClass::Point, "Cd").unwrap().data() else {
        panic!()
    };
    assert!(none.iter().all(|c| *c == geode_geo::glam::Vec3::ZERO));
    let spread = |v: &[geode_geo::glam::Vec3]| {
        let m = v.iter().copied().sum::<geode_geo::glam::Vec3>() / v.len() as f32;
        v.iter().map(|c| (*c - m).length_squared()).sum::<f32>()
    };
    for out in ["b", "bp"] {
        let b = geo(nodes, out);
        let AttribData::Vec3(bl) = b.attrib(AttribClass::Point, "Cd").unwrap().data() else {
            panic!()
        };
        assert!(spread(bl) < 0.5 * spread(cd), "{out} smooths");
    }
}
