//! Isotropic remeshing beside pymeshlab's isotropic explicit remeshing on
//! the same meshes (Hausdorff distance by pymeshlab's own measure, minimum
//! angle, edge-length spread), trimesh's watertightness, and closed-form
//! checks: features of a cube, borders of a grid, adaptive sizes,
//! attributes, determinism, cancellation and bad parameters.

mod common;
use common::*;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{
    primitives, AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, TypeInfo,
};
use geode_model::remesh::{remesh, RemeshOptions, Sizing};
use geode_model::ModelError;

fn uniform(length: f32) -> RemeshOptions<'static> {
    RemeshOptions {
        sizing: Sizing::Uniform { length },
        relative: false,
        ..RemeshOptions::default()
    }
}

/// Edge lengths of every triangle edge, each edge once.
fn edge_lengths(g: &Geometry) -> Vec<f32> {
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for k in 0..g.num_prims() {
        let p = g.prim_points(k);
        for j in 0..p.len() {
            let (a, b) = (p[j], p[(j + 1) % p.len()]);
            if seen.insert((a.min(b), a.max(b))) {
                out.push((g.positions()[a as usize] - g.positions()[b as usize]).length());
            }
        }
    }
    out
}

/// Mean and standard deviation over mean of the edge lengths.
fn spread(g: &Geometry) -> (f32, f32) {
    let l = edge_lengths(g);
    let mean = l.iter().sum::<f32>() / l.len() as f32;
    let var = l.iter().map(|x| (x - mean) * (x - mean)).sum::<f32>() / l.len() as f32;
    (mean, var.sqrt() / mean)
}

/// Each triangle's smallest angle, degrees.
fn smallest_angles(g: &Geometry) -> Vec<f32> {
    (0..g.num_prims())
        .map(|k| {
            let p = g.prim_points(k);
            let q: Vec<Vec3> = p.iter().map(|&i| g.positions()[i as usize]).collect();
            (0..3)
                .map(|j| {
                    let (a, b, c) = (q[j], q[(j + 1) % 3], q[(j + 2) % 3]);
                    (b - a).angle_between(c - a).to_degrees()
                })
                .fold(180.0f32, f32::min)
        })
        .collect()
}

/// The smallest angle of any triangle, degrees.
fn min_angle(g: &Geometry) -> f32 {
    smallest_angles(g).into_iter().fold(180.0, f32::min)
}

/// pymeshlab's isotropic explicit remeshing of `orig` at `length` (10
/// iterations, 30° features), and the same measures of both results:
/// Hausdorff distance to the original (pymeshlab's, symmetric, sampled),
/// minimum angle, edge-length mean and spread, trimesh watertightness.
const BESIDE_PYMESHLAB: &str = r#"
import json, sys
import numpy as np
import pymeshlab as ml
import trimesh
d = json.load(sys.stdin)
def arr(m):
    return np.array(m["v"], dtype=float), np.array(m["f"], dtype=np.int64)
ov, of = arr(d["orig"])
ms = ml.MeshSet()
ms.add_mesh(ml.Mesh(ov, of), "orig")
ms.add_mesh(ml.Mesh(ov, of), "theirs")
ms.set_current_mesh(1)
ms.meshing_isotropic_explicit_remeshing(iterations=10, targetlen=ml.PureValue(d["len"]), featuredeg=30.0)
theirs = ms.current_mesh()
tv, tf = theirs.vertex_matrix(), theirs.face_matrix()
ours_v, ours_f = arr(d["ours"])
ms.add_mesh(ml.Mesh(ours_v, ours_f), "ours")
ours_id = ms.current_mesh_id()
def hausdorff(k):
    n = 200000
    a = ms.get_hausdorff_distance(sampledmesh=k, targetmesh=0, samplevert=True, sampleface=True, samplenum=n, maxdist=ml.PureValue(10.0))
    b = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=k, samplevert=True, sampleface=True, samplenum=n, maxdist=ml.PureValue(10.0))
    return max(a["max"], b["max"])
def measures(v, f, k):
    t = trimesh.Trimesh(v, f, process=False)
    e = np.linalg.norm(v[t.edges_unique[:, 0]] - v[t.edges_unique[:, 1]], axis=1)
    ang = np.degrees(t.face_angles.min())
    return {"hausdorff": hausdorff(k), "min_angle": float(ang), "mean": float(e.mean()),
            "spread": float(e.std() / e.mean()), "watertight": bool(t.is_watertight),
            "euler": int(t.euler_number), "faces": len(f)}
print(json.dumps({"theirs": measures(tv, tf, 1), "ours": measures(ours_v, ours_f, ours_id), "ids": [ours_id]}))
"#;

/// How close to pymeshlab's result ours must come: its spread of edge
/// lengths and Hausdorff distance at most these multiples of pymeshlab's;
/// its minimum angle at least pymeshlab's when `min_angle` is set.
struct Bounds {
    spread: f64,
    hausdorff: f64,
    min_angle: bool,
}

/// Ours beside pymeshlab's on `g`, by pymeshlab's and trimesh's measures.
fn beside_pymeshlab(name: &str, g: &Geometry, length: f32, bounds: Bounds) {
    let ours = remesh(g, &uniform(length), &|| false).unwrap();
    let input = serde_json::json!({
        "orig": mesh_json(g),
        "ours": mesh_json(&ours),
        "len": length,
    });
    let Some(r) = oracle(BESIDE_PYMESHLAB, &input) else {
        return;
    };
    eprintln!("{name}: {r}");
    let (o, t) = (&r["ours"], &r["theirs"]);
    let f = |m: &serde_json::Value, k: &str| m[k].as_f64().unwrap();
    if bounds.min_angle {
        assert!(
            f(o, "min_angle") >= f(t, "min_angle"),
            "{name}: min angle {r}"
        );
    }
    assert!(
        f(o, "spread") <= bounds.spread * f(t, "spread"),
        "{name}: spread {r}"
    );
    assert!(
        f(o, "hausdorff") <= bounds.hausdorff * f(t, "hausdorff"),
        "{name}: hausdorff {r}"
    );
    assert!(
        (f(o, "mean") - length as f64).abs() < 0.05 * length as f64,
        "{name}: mean {r}"
    );
    assert_eq!(o["watertight"], t["watertight"], "{name}: {r}");
    assert_eq!(o["euler"], t["euler"], "{name}: {r}");
}

// Measured (sphere, torus, car): our minimum angle is 34° and 33°
// against pymeshlab's 27° and 29°; our spread of edge lengths 0.124,
// 0.103, 0.185 against their 0.132, 0.105, 0.187; our mean edge +1%,
// -3%, -4% of the target (theirs +4%, +2%, 0%); our Hausdorff distance
// 1.2 (since the sphere's quarter turns are exact: theirs fell from
// 0.0020 to 0.0018, ours stayed 0.0022), 0.9 and 1.55 times theirs.

#[test]
fn a_sphere_beside_pymeshlab() {
    let bounds = Bounds {
        spread: 1.0,
        hausdorff: 1.3,
        min_angle: true,
    };
    beside_pymeshlab("sphere", &primitives::uv_sphere(1.0, 64, 32), 0.05, bounds);
}

#[test]
fn a_torus_beside_pymeshlab() {
    let bounds = Bounds {
        spread: 1.0,
        hausdorff: 1.0,
        min_angle: true,
    };
    beside_pymeshlab("torus", &primitives::torus(1.0, 0.35, 64, 24), 0.04, bounds);
}

fn the_car() -> (Geometry, f32) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/catmark_car.obj");
    let car =
        geode_io::read(std::path::Path::new(path), &geode_io::NoProgress).expect("the car reads");
    let diag = geode_geo::ops::bounds(&car).unwrap().size().length();
    (car, diag)
}

/// The car cage: open, creased, with near-degenerate quads. Ours keeps
/// one zero-area triangle of 30,000 where two crease lines of the input
/// run a thousandth of the target apart (pymeshlab's worst is 3°), and
/// its Hausdorff distance is 1.55 times pymeshlab's: known weaknesses,
/// recorded here.
#[test]
fn the_opensubdiv_car_beside_pymeshlab() {
    let (car, diag) = the_car();
    let bounds = Bounds {
        spread: 1.0,
        hausdorff: 1.7,
        min_angle: false,
    };
    beside_pymeshlab("car", &car, 0.01 * diag, bounds);
}

/// Crease lines closer than a tenth of the target join instead of
/// pinching triangles between them: under 1° the car had 24 triangles
/// (9 of no area) before they did, 6 (1) after.
#[test]
fn near_creases_join_instead_of_pinching_slivers() {
    let (car, diag) = the_car();
    let out = remesh(&car, &uniform(0.01 * diag), &|| false).unwrap();
    let slivers = smallest_angles(&out).iter().filter(|&&a| a < 1.0).count();
    assert!(slivers <= 8, "{slivers} triangles under 1 degree");
}

#[test]
fn a_closed_mesh_stays_closed_with_its_genus() {
    for (g, euler) in [
        (primitives::uv_sphere(1.0, 48, 24), 2),
        (primitives::torus(1.0, 0.3, 48, 16), 0),
    ] {
        let out = remesh(&g, &uniform(0.08), &|| false).unwrap();
        assert_eq!(euler_and_closed(&out), (euler, true));
        assert!(out.prim_kinds().iter().all(|k| *k == PrimKind::Polygon));
        assert!((0..out.num_prims()).all(|k| out.prim_points(k).len() == 3));
        assert!(min_angle(&out) > 25.0, "{}", min_angle(&out));
    }
}

/// Whether `p` lies on an edge of the axis-aligned cube of half size `h`.
fn on_cube_edge(p: Vec3, h: f32) -> bool {
    p.to_array()
        .iter()
        .filter(|c| (c.abs() - h).abs() < 1e-5)
        .count()
        >= 2
}

#[test]
fn a_cube_keeps_its_sharp_edges_and_corners() {
    let cube = primitives::cube(1.0);
    let out = remesh(&cube, &uniform(0.1), &|| false).unwrap();
    assert_eq!(euler_and_closed(&out), (2, true));
    // Every corner is there exactly.
    for x in [-0.5f32, 0.5] {
        for y in [-0.5f32, 0.5] {
            for z in [-0.5f32, 0.5] {
                let c = Vec3::new(x, y, z);
                assert!(out.positions().contains(&c), "corner {c}");
            }
        }
    }
    // Every point is on the cube; the sharp edges (dihedral beyond 30°)
    // are exactly the cube's twelve edges, whole.
    for p in out.positions() {
        assert!((p.abs().max_element() - 0.5).abs() < 1e-5, "{p}");
    }
    let normal = |k: usize| {
        let q: Vec<Vec3> = out
            .prim_points(k)
            .iter()
            .map(|&i| out.positions()[i as usize])
            .collect();
        (q[1] - q[0]).cross(q[2] - q[0]).normalize()
    };
    let mut faces_of = std::collections::HashMap::new();
    for k in 0..out.num_prims() {
        let p = out.prim_points(k);
        for j in 0..3 {
            let (a, b) = (p[j], p[(j + 1) % 3]);
            faces_of
                .entry((a.min(b), a.max(b)))
                .or_insert_with(Vec::new)
                .push(k);
        }
    }
    let mut sharp_length = 0.0;
    for ((a, b), f) in &faces_of {
        let (pa, pb) = (out.positions()[*a as usize], out.positions()[*b as usize]);
        let sharp = normal(f[0]).dot(normal(f[1])) < 30f32.to_radians().cos();
        let along =
            on_cube_edge(pa, 0.5) && on_cube_edge(pb, 0.5) && on_cube_edge((pa + pb) * 0.5, 0.5);
        assert_eq!(sharp, along, "edge {pa} {pb}");
        if sharp {
            sharp_length += (pa - pb).length();
        }
    }
    assert!((sharp_length - 12.0).abs() < 1e-4, "{sharp_length}");
    let (mean, _) = spread(&out);
    assert!((mean - 0.1).abs() < 0.01, "{mean}");
}

#[test]
fn an_open_grid_keeps_its_border_and_its_uvs() {
    let grid = primitives::grid(Vec2::new(2.0, 1.0), 7, 5);
    let out = remesh(&grid, &uniform(0.05), &|| false).unwrap();
    let mut count = std::collections::HashMap::new();
    for k in 0..out.num_prims() {
        let p = out.prim_points(k);
        for j in 0..3 {
            let (a, b) = (p[j], p[(j + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let on_border = |p: Vec3| (p.x.abs() - 1.0).abs() < 1e-6 || (p.z.abs() - 0.5).abs() < 1e-6;
    let mut border_length = 0.0;
    for ((a, b), n) in count {
        let (pa, pb) = (out.positions()[a as usize], out.positions()[b as usize]);
        if n == 1 {
            assert!(
                on_border(pa) && on_border(pb) && on_border((pa + pb) * 0.5),
                "{pa} {pb}"
            );
            border_length += (pa - pb).length();
        }
    }
    assert!((border_length - 6.0).abs() < 1e-4, "{border_length}");
    for c in [Vec3::new(-1.0, 0.0, -0.5), Vec3::new(1.0, 0.0, 0.5)] {
        assert!(out.positions().contains(&c), "corner {c}");
    }
    // uv is linear in position on the grid: interpolation is exact.
    let Some(AttribData::Vec2(uv)) = out.attrib(AttribClass::Point, "uv").map(|a| a.data()) else {
        panic!("uv carried");
    };
    for (p, uv) in out.positions().iter().zip(uv) {
        assert!(p.y.abs() < 1e-6);
        let want = Vec2::new(p.x / 2.0 + 0.5, 0.5 - p.z);
        assert!((*uv - want).length() < 1e-5, "{p} {uv} {want}");
    }
    assert!((spread(&out).0 - 0.05).abs() < 0.005);
}

#[test]
fn adaptive_edges_are_shorter_where_the_surface_bends() {
    // An ellipsoid 4 long and 1 across: its ends bend 16 times more than
    // its waist bends along its length.
    let mut g = primitives::uv_sphere(1.0, 96, 48);
    for p in g.positions_mut() {
        *p *= Vec3::new(2.0, 0.5, 0.5);
    }
    let opts = RemeshOptions {
        sizing: Sizing::Adaptive {
            min: 0.01,
            max: 0.2,
            tolerance: 0.001,
            gradation: 0.5,
        },
        relative: false,
        ..RemeshOptions::default()
    };
    let out = remesh(&g, &opts, &|| false).unwrap();
    assert_eq!(euler_and_closed(&out), (2, true));
    let mut ends = (0.0, 0);
    let mut waist = (0.0, 0);
    for k in 0..out.num_prims() {
        let p = out.prim_points(k);
        for j in 0..3 {
            let (a, b) = (
                out.positions()[p[j] as usize],
                out.positions()[p[(j + 1) % 3] as usize],
            );
            let x = ((a + b) * 0.5).x.abs();
            let l = (a - b).length();
            if x > 1.9 {
                ends = (ends.0 + l, ends.1 + 1);
            } else if x < 0.3 {
                waist = (waist.0 + l, waist.1 + 1);
            }
        }
    }
    let (ends, waist) = (ends.0 / ends.1 as f32, waist.0 / waist.1 as f32);
    eprintln!("ends {ends}, waist {waist}, {} triangles", out.num_prims());
    assert!(ends < 0.6 * waist, "ends {ends}, waist {waist}");
}

#[test]
fn attributes_and_groups_come_from_the_original() {
    let mut g = primitives::uv_sphere(1.0, 32, 16);
    let cd: Vec<Vec3> = g
        .positions()
        .iter()
        .map(|p| *p * 0.5 + Vec3::splat(0.5))
        .collect();
    g.set_attrib(
        AttribClass::Point,
        "Cd",
        Attribute::from_data(AttribData::Vec3(cd), TypeInfo::Color),
    )
    .unwrap();
    let corners: Vec<f32> = (0..g.num_vertices())
        .map(|v| g.positions()[g.vertex_points()[v] as usize].y)
        .collect();
    g.set_attrib(
        AttribClass::Vertex,
        "h",
        Attribute::from_data(AttribData::Float(corners), TypeInfo::None),
    )
    .unwrap();
    let ids: Vec<i32> = (0..g.num_prims() as i32).collect();
    g.set_attrib(
        AttribClass::Primitive,
        "id",
        Attribute::from_data(AttribData::Int(ids), TypeInfo::None),
    )
    .unwrap();
    let centre = |g: &Geometry, k: usize| {
        let p = g.prim_points(k);
        p.iter().map(|&i| g.positions()[i as usize]).sum::<Vec3>() / p.len() as f32
    };
    let top = Group::from_flags((0..g.num_prims()).map(|k| centre(&g, k).y > 0.0));
    g.set_prim_group("top", top).unwrap();
    let north = Group::from_flags(g.positions().iter().map(|p| p.x > 0.0));
    g.set_point_group("east", north).unwrap();
    let out = remesh(&g, &uniform(0.1), &|| false).unwrap();
    let Some(AttribData::Vec3(cd)) = out.attrib(AttribClass::Point, "Cd").map(|a| a.data()) else {
        panic!("Cd carried");
    };
    // Linear in position, and each point lies on an original triangle.
    for (p, c) in out.positions().iter().zip(cd) {
        assert!((*c - (*p * 0.5 + Vec3::splat(0.5))).length() < 1e-5);
    }
    let Some(AttribData::Float(h)) = out.attrib(AttribClass::Vertex, "h").map(|a| a.data()) else {
        panic!("h carried");
    };
    // Exact where the corner's point lies on its face's source polygon;
    // across polygons, clamped onto the face's source triangle.
    let mut exact = 0;
    for (v, h) in h.iter().enumerate() {
        let p = out.positions()[out.vertex_points()[v] as usize];
        assert!((h - p.y).abs() < 0.1, "{h} at {p}");
        exact += ((h - p.y).abs() < 1e-5) as usize;
    }
    assert!(exact * 2 > h.len(), "{exact} of {}", h.len());
    let Some(AttribData::Int(id)) = out.attrib(AttribClass::Primitive, "id").map(|a| a.data())
    else {
        panic!("id carried");
    };
    let top = &out.prim_groups()["top"];
    for (k, &source) in id.iter().enumerate() {
        // The source face is near: within a face's size of this one.
        let c = centre(&out, k);
        assert!(
            (centre(&g, source as usize) - c).length() < 0.25,
            "face {k}"
        );
        assert_eq!(top.contains(k), centre(&g, source as usize).y > 0.0);
    }
    let east = &out.point_groups()["east"];
    for (i, p) in out.positions().iter().enumerate() {
        if p.x.abs() > 0.1 {
            assert_eq!(east.contains(i), p.x > 0.0, "{p}");
        }
    }
}

#[test]
fn a_feature_group_is_kept() {
    // A flat grid with a line of grouped points across it: the line stays.
    let g = primitives::grid(Vec2::new(2.0, 2.0), 10, 10);
    let line = Group::from_flags(g.positions().iter().map(|p| p.x.abs() < 1e-6));
    let opts = RemeshOptions {
        feature_points: Some(&line),
        ..uniform(0.07)
    };
    let out = remesh(&g, &opts, &|| false).unwrap();
    let on_line = out.positions().iter().filter(|p| p.x.abs() < 1e-6).count();
    // The line (length 2) is cut into edges near the target length.
    assert!(on_line >= 25, "{on_line} points on the line");
}

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let g = primitives::torus(1.0, 0.3, 64, 24);
    let cube = primitives::cube(1.0);
    let in_pool = |n: usize, g: &Geometry, opts: &RemeshOptions| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| remesh(g, opts, &|| false).unwrap().content_hash())
    };
    let adaptive = RemeshOptions {
        sizing: Sizing::Adaptive {
            min: 0.01,
            max: 0.2,
            tolerance: 0.002,
            gradation: 0.3,
        },
        relative: false,
        ..RemeshOptions::default()
    };
    for opts in [uniform(0.05), adaptive] {
        assert_eq!(in_pool(1, &g, &opts), in_pool(2, &g, &opts));
        assert_eq!(in_pool(1, &cube, &opts), in_pool(2, &cube, &opts));
    }
}

#[test]
fn cancellation_stops_it() {
    let g = primitives::uv_sphere(1.0, 64, 32);
    let calls = std::sync::atomic::AtomicUsize::new(0);
    let cancel = || calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) > 5;
    assert!(matches!(
        remesh(&g, &uniform(0.02), &cancel),
        Err(ModelError::Cancelled)
    ));
}

#[test]
fn bad_parameters_and_inputs_are_clear_errors() {
    let g = primitives::uv_sphere(1.0, 16, 8);
    let err = |opts: RemeshOptions| match remesh(&g, &opts, &|| false) {
        Err(ModelError::Invalid(why)) => why,
        other => panic!("expected an error, got {:?}", other.map(|g| g.num_prims())),
    };
    assert!(err(uniform(0.0)).contains("target length"));
    assert!(err(uniform(f32::NAN)).contains("target length"));
    let swapped = RemeshOptions {
        sizing: Sizing::Adaptive {
            min: 0.2,
            max: 0.1,
            tolerance: 0.01,
            gradation: 0.5,
        },
        ..RemeshOptions::default()
    };
    assert!(err(swapped).contains("exceeds"));
    let crease = RemeshOptions {
        crease_angle: 200.0,
        ..uniform(0.1)
    };
    assert!(err(crease).contains("crease angle"));
    let short = Group::from_flags([true, false]);
    let grouped = RemeshOptions {
        feature_points: Some(&short),
        ..uniform(0.1)
    };
    assert!(err(grouped).contains("feature group"));
    // Three triangles on one edge.
    let fin = Geometry::from_triangles(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, -Vec3::Y],
        &[[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    )
    .unwrap();
    assert!(
        matches!(remesh(&fin, &uniform(0.1), &|| false), Err(ModelError::Invalid(w)) if w.contains("manifold"))
    );
    let curve = Geometry::from_prims(
        vec![Vec3::ZERO, Vec3::X],
        vec![0, 1],
        &[2],
        vec![PrimKind::Polyline],
    )
    .unwrap();
    assert!(
        matches!(remesh(&curve, &uniform(0.1), &|| false), Err(ModelError::Invalid(w)) if w.contains("polygons"))
    );
    // Nothing in, nothing out.
    assert_eq!(
        remesh(&Geometry::default(), &uniform(0.1), &|| false)
            .unwrap()
            .num_prims(),
        0
    );
}

/// A target longer than the model (a slider dragged too far) leaves a
/// coarse closed solid on the shape, not a speck.
#[test]
fn a_target_longer_than_the_model_leaves_a_coarse_solid() {
    let g = geode_geo::ops::triangulate(&primitives::uv_sphere(1.0, 32, 16), None);
    for length in [3.0, 1e3] {
        let out = remesh(&g, &uniform(length), &|| false).unwrap();
        assert_eq!(euler_and_closed(&out), (2, true));
        let v = volume(&out);
        assert!(v > 0.1 * volume(&g), "volume {v} of {}", out.num_prims());
        let b = geode_geo::ops::bounds(&out).unwrap();
        assert!(b.size().min_element() > 0.5, "{:?}", b.size());
    }
}
