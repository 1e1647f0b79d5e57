//! frep_from_mesh against trimesh: the field's value at 100,000 random
//! points is trimesh's exact closest-point distance (to 1e-5 of the part's
//! bounding box) with libigl's exact winding number, inside where its
//! magnitude passes one half (and trimesh's
//! `contains` where the part does not overlap itself) for its sign, and
//! meshing the field at depth 8 gives the part back (Hausdorff both ways,
//! measured by trimesh). Parts: three machined STLs
//! (`examples/parts`, trimesh's own models) and OpenSubdiv's car cage
//! closed by polyfill.

#[path = "../../model/tests/common/oracle.rs"]
mod oracle;

mod common;

use geode_geo::glam::Vec3;

const PARTS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/parts");
const CAR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../model/tests/data/catmark_car.obj"
);

/// trimesh on the part (read from `path`, or given as JSON triangles):
/// distances and sides at the points, then both one-sided distances
/// between the part and a mesh of it.
const ORACLE: &str = r#"
import json, sys
import numpy as np
import trimesh
a = json.load(sys.stdin)
if a["path"]:
    part = trimesh.load(a["path"], force="mesh")
else:
    part = trimesh.Trimesh(np.array(a["part"]["v"]), np.array(a["part"]["f"]), process=True)
pts = np.array(a["points"], dtype=np.float64)
_, dist, _ = trimesh.proximity.closest_point(part, pts)
inside = part.contains(pts)
import igl
winding = igl.winding_number(np.array(part.vertices, dtype=np.float64), np.array(part.faces, dtype=np.int64), pts)
out = trimesh.Trimesh(np.array(a["mesh"]["v"]), np.array(a["mesh"]["f"]), process=False)
# Mesh to part: every vertex of the mesh. Part to mesh: the part's corners
# and 20,000 points on its surface (seeded), those on the solid's boundary:
# where the part overlaps itself, surface inside the solid is not meshed.
_, to_part, _ = trimesh.proximity.closest_point(part, out.vertices)
on_part, faces = trimesh.sample.sample_surface(part, 20000, seed=7)
corner_faces = [np.where((part.faces == i).any(axis=1))[0][0] for i in range(len(part.vertices))]
probe = np.vstack([part.vertices, on_part])
normals = part.face_normals[np.concatenate([corner_faces, faces])]
eps = 1e-4 * np.linalg.norm(part.extents)
V, F = np.array(part.vertices, dtype=np.float64), np.array(part.faces, dtype=np.int64)
w_out = igl.winding_number(V, F, probe + eps * normals)
w_in = igl.winding_number(V, F, probe - eps * normals)
boundary = (np.abs(w_out) > 0.5) != (np.abs(w_in) > 0.5)
_, to_mesh, _ = trimesh.proximity.closest_point(out, probe[boundary])
print(json.dumps({
    "dist": dist.tolist(),
    "inside": inside.tolist(),
    "winding": winding.tolist(),
    "mesh_to_part": float(to_part.max()),
    "part_to_mesh": float(to_mesh.max()),
    "watertight": bool(out.is_watertight),
}))
"#;

/// 100,000 seeded points in the box grown by a tenth on every side.
fn points(lo: Vec3, hi: Vec3) -> Vec<Vec3> {
    let mut s = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    let size = hi - lo;
    (0..100_000)
        .map(|_| lo - 0.1 * size + Vec3::new(next(), next(), next()) * size * 1.2)
        .collect()
}

/// The part (`source` node entries ending in a node `part`), its field,
/// and its mesh at depth 8 over its box grown by 4 cells, which must come
/// within `part_to_mesh` cells of every point of the part's boundary
/// (`None`: measured and printed only).
fn check(source: &str, path: Option<&str>, name: &str, part_to_mesh: Option<f64>) {
    let part = common::geo(source, "part");
    let b = geode_geo::ops::bounds(&part).unwrap();
    let nodes = format!(r#"{source}, "solid": {{"type": "frep_from_mesh", "inputs": ["part"]}}"#);
    let field = common::cook_at(&nodes, "solid", 1.0)
        .unwrap_or_else(|e| panic!("{e}"))
        .as_field()
        .unwrap()
        .clone();
    let size = b.max - b.min;
    let cell = size.max_element() as f64 * 1.1 / 256.0;
    let (lo, hi) = (
        b.min.as_dvec3() - 4.0 * cell,
        b.min.as_dvec3() + 252.0 * cell,
    );
    let mesh_nodes = format!(
        r#"{nodes}, "mesh": {{"type": "polygonise", "inputs": ["solid"], "params": {{"depth": 8, "min": [{}, {}, {}], "max": [{}, {}, {}]}}}}"#,
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
    );
    let mesh = common::geo(&mesh_nodes, "mesh");
    let at = points(b.min, b.max);
    let values = geode_mesher::sample(&field, &at);
    let input = serde_json::json!({
        "path": path,
        "part": oracle::mesh_json(&part),
        "points": at.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
        "mesh": oracle::mesh_json(&mesh),
    });
    let Some(want) = oracle::oracle(ORACLE, &input) else {
        return;
    };
    let diagonal = size.length() as f64;
    let dist: Vec<f64> = serde_json::from_value(want["dist"].clone()).unwrap();
    let inside: Vec<bool> = serde_json::from_value(want["inside"].clone()).unwrap();
    let winding: Vec<f64> = serde_json::from_value(want["winding"].clone()).unwrap();
    let mut worst: f64 = 0.0;
    let (mut against_igl, mut against_trimesh, mut overlapped) = (0, 0, 0);
    for i in 0..at.len() {
        let v = values[i] as f64;
        worst = worst.max((v.abs() - dist[i]).abs());
        // A point within a millionth of the box of the surface may go
        // either way (f32 positions).
        if dist[i] <= 1e-6 * diagonal {
            continue;
        }
        // Inside where the winding number passes one half in magnitude
        // (the car's cage has a few pockets wound inside out: -1).
        if (v > 0.0) != (winding[i].abs() > 0.5) {
            against_igl += 1;
        }
        // trimesh's `contains` counts crossings of a ray, so where the
        // part overlaps itself (winding number 2: the car's wheel arches
        // through its body) it answers outside; compare it elsewhere.
        if (winding[i] - winding[i].round()).abs() < 0.1
            && (0.0..=1.0).contains(&winding[i].round())
        {
            if (v > 0.0) != inside[i] {
                against_trimesh += 1;
            }
        } else {
            overlapped += 1;
        }
    }
    assert!(
        worst <= 1e-5 * diagonal,
        "{name}: distance off by {worst} (box {diagonal})"
    );
    assert_eq!(
        (against_igl, against_trimesh),
        (0, 0),
        "{name}: points on the other side than libigl's winding number, trimesh's contains"
    );
    let (to_part, to_mesh) = (
        want["mesh_to_part"].as_f64().unwrap(),
        want["part_to_mesh"].as_f64().unwrap(),
    );
    eprintln!(
        "{name}: {} triangles, worst distance error {:.2e} of the box, {overlapped} points where it overlaps itself or is wound inside out; Hausdorff mesh->part {:.3} cell, part->mesh {:.3} cell",
        part.num_prims(),
        worst / diagonal,
        to_part / cell,
        to_mesh / cell
    );
    assert!(
        to_part <= 0.5 * cell,
        "{name}: mesh strays {to_part} (cell {cell})"
    );
    if let Some(bound) = part_to_mesh {
        assert!(
            to_mesh <= bound * cell,
            "{name}: part missed by {to_mesh} (cell {cell})"
        );
    }
    assert!(
        want["watertight"].as_bool().unwrap(),
        "{name}: mesh not closed"
    );
}

fn stl(name: &str) {
    let path = format!("{PARTS}/{name}");
    let source = format!(r#""part": {{"type": "file", "params": {{"file": "{path}"}}}}"#);
    // The corners where a faceted hole meets a face (facets a few degrees
    // apart, about a cell long) are cut by up to three quarters of a cell
    // today: curved creases are the mesher's open work (issue 37, item 3).
    check(&source, Some(&path), name, Some(0.8));
}

#[test]
fn featuretype_is_its_distance_and_meshes_back() {
    stl("featuretype.stl");
}

#[test]
fn idler_riser_is_its_distance_and_meshes_back() {
    stl("idler_riser.stl");
}

#[test]
fn plate_holes_is_its_distance_and_meshes_back() {
    stl("plate_holes.stl");
}

#[test]
fn the_car_closed_by_polyfill_is_its_distance_and_meshes_back() {
    let source = format!(
        r#""cage": {{"type": "file", "params": {{"file": "{CAR}"}}}},
        "closed": {{"type": "polyfill", "inputs": ["cage"]}},
        "part": {{"type": "triangulate", "inputs": ["closed"]}}"#
    );
    // The roof is a sheet 0.4 cell thick at depth 8, which the mesher
    // loses today (issue 37, item 4: thin walls), so the part-to-mesh side
    // is printed, not bounded.
    check(&source, None, "catmark_car", None);
}

#[test]
fn an_open_mesh_warns_and_an_empty_one_is_refused() {
    let w = common::warnings(
        r#""g": {"type": "grid"}, "s": {"type": "frep_from_mesh", "inputs": ["g"]}"#,
        "/s",
    );
    assert!(
        w.iter()
            .any(|w| w.contains("not closed") && w.contains("edges bound one polygon")),
        "{w:?}"
    );
    let e = common::err(
        r#""g": {"type": "curve_line"}, "s": {"type": "frep_from_mesh", "inputs": ["g"]}"#,
        "s",
    );
    assert!(e.contains("/s") && e.contains("no polygons"), "{e}");
    let e = common::err(
        r#""g": {"type": "box"}, "s": {"type": "frep_from_mesh", "inputs": ["g"], "params": {"group": "nothing_here"}}"#,
        "s",
    );
    assert!(e.contains("group") && e.contains("nothing_here"), "{e}");
}

/// The volume of `output`'s closed mesh.
fn volume(nodes: &str) -> f64 {
    let g = common::geo(nodes, "mesh");
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    geode_geo::ops::signed_volume(&g) as f64
}

/// A mesh's field is a field like any other: CSG with a native sphere, and
/// offsets in both measures (its value already is a distance), mesh to
/// the analytic volumes.
#[test]
fn a_mesh_field_combines_with_native_fields() {
    let pi = std::f64::consts::PI;
    let cube = r#""cube": {"type": "box"}, "solid": {"type": "frep_from_mesh", "inputs": ["cube"]},
        "ball": {"type": "frep_sphere", "params": {"radius": 0.5, "center": [0.5, 0.5, 0.5]}}"#;
    let mesh = r#""mesh": {"type": "polygonise", "inputs": ["s"], "params": {"min": [-0.9, -0.9, -0.9], "max": [0.9, 0.9, 0.9], "depth": 7}}"#;
    let cut = format!(
        r#"{cube}, "s": {{"type": "frep_csg", "inputs": ["solid", "ball"], "params": {{"operation": "subtraction"}}}}, {mesh}"#
    );
    let want = 1.0 - pi / 48.0;
    let got = volume(&cut);
    assert!((got - want).abs() / want < 3e-3, "cut: {got} vs {want}");
    for measure in ["field", "distance"] {
        let grown = format!(
            r#"{cube}, "s": {{"type": "frep_offset", "inputs": ["solid"], "params": {{"distance": 0.1, "measure": "{measure}"}}}}, {mesh}"#
        );
        let want = 1.0 + 6.0 * 0.1 + 3.0 * pi * 0.01 + 4.0 / 3.0 * pi * 0.001;
        let got = volume(&grown);
        assert!(
            (got - want).abs() / want < 3e-3,
            "offset ({measure}): {got} vs {want}"
        );
    }
    // A 0.1 wall inside the unit cube: 1 - 0.8^3.
    let shell = format!(
        r#"{cube}, "s": {{"type": "frep_shell", "inputs": ["solid"], "params": {{"thickness": 0.1, "side": "inside"}}}}, {mesh}"#
    );
    let (got, want) = (volume(&shell), 1.0 - 0.8f64.powi(3));
    assert!((got - want).abs() / want < 5e-3, "shell: {got} vs {want}");
    // Two copies on points 0.8 apart, half size: a quarter of the cube.
    let copies = r#""cube": {"type": "box"}, "solid": {"type": "frep_from_mesh", "inputs": ["cube"]},
        "pts": {"type": "curve_line", "params": {"start": [-0.4, 0, 0], "end": [0.4, 0, 0], "points": 2}},
        "sized": {"type": "attribute_create", "inputs": ["pts"], "params": {"name": "pscale", "value": [0.5, 0, 0, 0]}},
        "s": {"type": "frep_instance", "inputs": ["solid", "sized"]},
        "mesh": {"type": "polygonise", "inputs": ["s"], "params": {"min": [-0.9, -0.9, -0.9], "max": [0.9, 0.9, 0.9], "depth": 7}}"#;
    let got = volume(copies);
    assert!((got - 0.25).abs() / 0.25 < 3e-3, "instances: {got}");
    // A blend with the sphere adds a fillet to the union's volume.
    let union =
        format!(r#"{cube}, "s": {{"type": "frep_csg", "inputs": ["solid", "ball"]}}, {mesh}"#);
    let blended = format!(
        r#"{cube}, "s": {{"type": "frep_blend", "inputs": ["solid", "ball"], "params": {{"a0": 0.2, "a1": 0.2, "a2": 0.2}}}}, {mesh}"#
    );
    let (u, b) = (volume(&union), volume(&blended));
    assert!(b > u * 1.01 && b < u * 1.5, "union {u}, blend {b}");
}

/// Node entries reading `part` (in `examples/parts`) as a field and
/// meshing it over `min`..`max` at `depth`, as node `mesh`.
fn meshed_part(part: &str, min: [f64; 3], max: [f64; 3], depth: u32) -> String {
    format!(
        r#""part": {{"type": "file", "params": {{"file": "{PARTS}/{part}"}}}},
        "solid": {{"type": "frep_from_mesh", "inputs": ["part"]}},
        "mesh": {{"type": "polygonise", "inputs": ["solid"], "params": {{"min": {min:?}, "max": {max:?}, "depth": {depth}}}}}"#
    )
}

/// Faces lying exactly on grid planes (a part's faces at whole cells from
/// the box's corner): points on them read as on the surface, never on a
/// side picked by rounding, so the mesh is closed and manifold (it had
/// sheets meeting at edges along featuretype's bottom and side).
#[test]
fn faces_on_grid_planes_mesh_closed() {
    let nodes = meshed_part(
        "featuretype.stl",
        [-2.6, -1.35, -0.1],
        [2.6, 1.35, 1.475],
        7,
    );
    let g = common::geo(&nodes, "mesh");
    let report = g.topology().manifold_report(&g);
    assert!(report.is_closed_manifold(), "{report:?}");
    let cube = r#""cube": {"type": "box"}, "solid": {"type": "frep_from_mesh", "inputs": ["cube"]},
        "mesh": {"type": "polygonise", "inputs": ["solid"], "params": {"min": [-1, -1, -1], "max": [1, 1, 1], "depth": 5}}"#;
    let v = volume(cube);
    assert!((v - 1.0).abs() < 1e-4, "{v}");
}

/// The same part meshes to the same bytes on 1 and 4 threads (the sides
/// each thread remembers are hints that never change an answer).
#[test]
fn meshing_a_mesh_field_is_deterministic() {
    let nodes = meshed_part("idler_riser.stl", [-0.2, -0.1, -0.1], [2.7, 3.0, 0.7], 6);
    let one = common::cook_on(1, &nodes, "mesh");
    let four = common::cook_on(4, &nodes, "mesh");
    assert!(one.num_prims() > 1000);
    assert_eq!(one.content_hash(), four.content_hash());
}

/// What makes an inside unclear is said, and what can still be read is:
/// a box wound inside out is the same solid (with a warning), half a box's
/// faces reversed is named, and an open sheet encloses nothing but
/// thickens into a plate with a centred shell.
#[test]
fn unclear_insides_are_named_and_read_where_they_can_be() {
    let mesh = r#""mesh": {"type": "polygonise", "inputs": ["s"], "params": {"min": [-0.9, -0.9, -0.9], "max": [0.9, 0.9, 0.9], "depth": 6}}"#;
    let inverted = format!(
        r#""cube": {{"type": "box"}}, "flipped": {{"type": "reverse", "inputs": ["cube"]}},
        "s": {{"type": "frep_from_mesh", "inputs": ["flipped"]}}, {mesh}"#
    );
    let w = common::warnings(&inverted, "/s");
    assert!(w.iter().any(|w| w.contains("point inward")), "{w:?}");
    let v = volume(&inverted);
    assert!((v - 1.0).abs() < 1e-4, "inside out: {v}");
    let half = r#""cube": {"type": "box"},
        "kept": {"type": "blast", "inputs": ["cube"], "params": {"group": "0-2", "keep_points": true}},
        "odd": {"type": "blast", "inputs": ["cube"], "params": {"group": "0-2", "invert": true, "keep_points": true}},
        "turned": {"type": "reverse", "inputs": ["odd"]},
        "joined": {"type": "merge", "inputs": ["kept", "turned"]},
        "welded": {"type": "fuse", "inputs": ["joined"]},
        "s": {"type": "frep_from_mesh", "inputs": ["welded"]}"#;
    let w = common::warnings(half, "/s");
    assert!(
        w.iter().any(|w| w.contains("facing opposite ways")),
        "{w:?}"
    );
    let sheet = format!(
        r#""g": {{"type": "grid", "params": {{"size": [1, 1]}}}}, "f": {{"type": "frep_from_mesh", "inputs": ["g"]}},
        "s": {{"type": "frep_shell", "inputs": ["f"], "params": {{"thickness": 0.1, "side": "centered"}}}}, {mesh}"#
    );
    let w = common::warnings(&sheet, "/f");
    assert!(w.iter().any(|w| w.contains("encloses no volume")), "{w:?}");
    // A 1 x 1 plate 0.1 thick with rounded rims: 0.1 + the rims' half
    // cylinders (4 x 1 x pi 0.05^2 / 2) + corners.
    let v = volume(&sheet);
    let want =
        0.1 + 2.0 * std::f64::consts::PI * 0.0025 + 4.0 / 3.0 * std::f64::consts::PI * 1.25e-4;
    assert!((v - want).abs() / want < 0.03, "plate {v} vs {want}");
}
