//! Every GLB geode writes passes the Khronos glTF validator with zero errors;
//! every USDA opens in Pixar's usd-core with the expected contents.
//! The tools are installed by `tools/test.sh`; a missing one fails the test
//! unless GEODE_SKIP_ORACLES=1.

mod common;

use std::process::Command;

use common::*;
use geode_geo::glam::Vec3;
use geode_geo::{ops, primitives, Geometry};
use geode_io::{write, NoProgress};

fn samples() -> Vec<(&'static str, Geometry)> {
    let mut lines = Geometry::new();
    lines.add_points(&[Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y * 3.0]);
    lines.add_polyline(&[0, 1, 2, 3]).unwrap();
    let mut cloud = Geometry::new();
    cloud.add_points(&[Vec3::ZERO, Vec3::ONE, Vec3::X]);
    let mut nested = Geometry::new();
    let inner = std::sync::Arc::new(instanced_scene(4));
    let p = nested.add_point(Vec3::Y * 5.0);
    nested
        .add_packed(p, inner, geode_geo::glam::Mat4::from_rotation_x(0.5))
        .unwrap();
    let mut bad_normals = primitives::cube(1.0);
    bad_normals
        .set_attrib(
            geode_geo::AttribClass::Point,
            "N",
            geode_geo::Attribute::new(
                geode_geo::AttribValue::Vec3(Vec3::ZERO),
                geode_geo::TypeInfo::Normal,
                8,
            ),
        )
        .unwrap();
    vec![
        ("torus", attributed_torus()),
        ("cube_vertex_attrs", vertex_attributed_cube()),
        (
            "concave",
            ops::triangulate(&primitives::tube(1.0, 1.0, 7, 2, true), None),
        ),
        ("instances", instanced_scene(100)),
        ("mixed_instances", mixed_instances()),
        ("nested", nested),
        ("lines", lines),
        ("cloud", cloud),
        ("empty", Geometry::new()),
        ("zero_normals", bad_normals),
        ("custom_attributes", instancing_torus()),
    ]
}

#[test]
fn glb_passes_khronos_validator() {
    let dir = tempfile::tempdir().unwrap();
    let mut cmd = Command::new("node");
    cmd.arg(repo_root().join("tools/gltf_validate.mjs"));
    for (name, g) in samples() {
        let path = dir.path().join(format!("{name}.glb"));
        write(&g, &path, &NoProgress).unwrap();
        cmd.arg(path);
    }
    if let Some(report) = run_validator(cmd, "gltf-validator (npm, in tools/)") {
        for line in report.lines() {
            assert!(line.contains("\"errors\":0"), "{line}");
        }
        assert_eq!(report.lines().count(), samples().len());
    }
}

#[test]
fn usda_opens_in_usd_core() {
    let dir = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(std::env::var("GEODE_PYTHON").unwrap_or_else(|_| "python3".into()));
    cmd.arg(repo_root().join("tools/usd_check.py"));
    for (name, g) in samples() {
        let path = dir.path().join(format!("{name}.usda"));
        write(&g, &path, &NoProgress).unwrap();
        cmd.arg(path);
        let polys = g
            .prim_kinds()
            .iter()
            .filter(|k| **k == geode_geo::PrimKind::Polygon)
            .count();
        let curves = g
            .prim_kinds()
            .iter()
            .filter(|k| **k == geode_geo::PrimKind::Polyline)
            .count();
        let instances = g
            .prim_kinds()
            .iter()
            .filter(|k| matches!(k, geode_geo::PrimKind::Packed(_)))
            .count();
        // Only the top level's faces are counted by traversal (prototypes sit
        // under an abstract class); instances are counted at every level.
        let nested_instances: usize = g
            .packed_instances()
            .iter()
            .map(|i| i.source.packed_instances().len())
            .sum();
        cmd.arg(format!(
            "{{\"faces\": {polys}, \"curves\": {curves}, \"instances\": {}}}",
            instances + nested_instances
        ));
    }
    if let Some(report) = run_validator(cmd, "usd-core (pip)") {
        assert_eq!(
            report
                .lines()
                .filter(|l| l.contains("\"ok\": true"))
                .count(),
            samples().len(),
            "{report}"
        );
    }
}

/// geode's manifold report and volume agree with trimesh on written STL files.
#[test]
fn manifold_report_agrees_with_trimesh() {
    let dir = tempfile::tempdir().unwrap();
    let mut open_grid = primitives::grid(geode_geo::glam::Vec2::splat(1.0), 4, 4);
    open_grid
        .remove_attrib(geode_geo::AttribClass::Point, "uv")
        .unwrap();
    let cases = vec![
        ("sphere", primitives::uv_sphere(1.0, 32, 16)),
        ("torus", primitives::torus(1.0, 0.25, 48, 16)),
        (
            "box",
            primitives::box_mesh(Vec3::new(1.0, 2.0, 3.0), [3, 2, 1]),
        ),
        ("grid", open_grid),
    ];
    let mut cmd = Command::new(std::env::var("GEODE_PYTHON").unwrap_or_else(|_| "python3".into()));
    cmd.arg(repo_root().join("tools/mesh_check.py"));
    for (name, g) in &cases {
        let path = dir.path().join(format!("{name}.stl"));
        write(g, &path, &NoProgress).unwrap();
        cmd.arg(path);
    }
    let Some(report) = run_validator(cmd, "trimesh (pip)") else {
        return;
    };
    for ((name, g), line) in cases.iter().zip(report.lines()) {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        let ours = g.topology().manifold_report(g).is_closed_manifold();
        assert_eq!(v["watertight"].as_bool(), Some(ours), "{name}: {line}");
        assert_eq!(v["winding_consistent"].as_bool(), Some(true), "{name}");
        if ours {
            let vol = ops::signed_volume(g) as f64;
            assert!(
                (v["volume"].as_f64().unwrap() - vol).abs() < 1e-4 * vol.abs().max(1.0),
                "{name}: {line} vs {vol}"
            );
        }
    }
}

/// A bilinear-by-quadratic patch on a 2 x 3 grid with one weight off 1:
/// its centre, known by hand, tells a transposed grid from a right one.
fn patch_sample() -> (Geometry, Vec3) {
    use geode_geo::{AttribClass, AttribData, Attribute, KnotVector, PatchBasis, TypeInfo};
    let mut g = Geometry::new();
    let pts = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::new(3.0, 2.0, 1.0),
        Vec3::new(3.0, 0.0, 2.0),
    ];
    g.add_points(&pts);
    let weights = vec![1.0, 2.0, 1.0, 1.0, 2.0, 1.0];
    g.set_attrib(
        AttribClass::Point,
        geode_geo::WEIGHT,
        Attribute::from_data(AttribData::Float(weights.clone()), TypeInfo::None),
    )
    .unwrap();
    g.add_patch(
        &[0, 1, 2, 3, 4, 5],
        PatchBasis {
            u: KnotVector {
                order: 2,
                knots: vec![0.0, 0.0, 1.0, 1.0],
            },
            v: KnotVector {
                order: 3,
                knots: vec![0.0, 0.0, 0.0, 2.0, 2.0, 2.0],
            },
        },
    )
    .unwrap();
    // Centre: half of each row; each row a rational quadratic at 1/2 with
    // Bernstein weights 1/4, 1/2, 1/4.
    let row = |k: usize| {
        let b = [0.25, 0.5, 0.25];
        let mut acc = Vec3::ZERO;
        let mut w = 0.0;
        for j in 0..3 {
            acc += pts[3 * k + j] * (b[j] * weights[3 * k + j]);
            w += b[j] * weights[3 * k + j];
        }
        (acc, w)
    };
    let ((a, wa), (b, wb)) = (row(0), row(1));
    (g, (a * 0.5 + b * 0.5) / (0.5 * wa + 0.5 * wb))
}

#[test]
fn usda_keeps_spline_patches_and_mesh_formats_refuse_them_clearly() {
    let (g, centre) = patch_sample();
    let dir = tempfile::tempdir().unwrap();
    for ext in ["glb", "obj", "stl", "ply"] {
        let path = dir.path().join(format!("patch.{ext}"));
        let e = write(&g, &path, &NoProgress).unwrap_err().to_string();
        assert!(e.contains("patch.") && e.contains("convert"), "{e}");
        assert!(!path.exists());
    }
    let path = dir.path().join("patch.usda");
    write(&g, &path, &NoProgress).unwrap();
    let mut cmd = Command::new(std::env::var("GEODE_PYTHON").unwrap_or_else(|_| "python3".into()));
    cmd.arg(repo_root().join("tools/usd_check.py"))
        .arg(&path)
        .arg("{\"patches\": 1, \"faces\": 0}");
    if let Some(report) = run_validator(cmd, "usd-core (pip)") {
        let line: serde_json::Value = serde_json::from_str(report.lines().next().unwrap()).unwrap();
        let c = &line["patch_centres"][0];
        let got = Vec3::new(
            c[0].as_f64().unwrap() as f32,
            c[1].as_f64().unwrap() as f32,
            c[2].as_f64().unwrap() as f32,
        );
        assert!(
            got.distance(centre) < 1e-5,
            "usd-core's centre {got} vs {centre}"
        );
    }
}

/// Every attribute reaches USD as a primvar with the interpolation of its
/// class and the role of its type info, as usd-core reads it back.
#[test]
fn usda_primvars_keep_attributes_with_interpolation_and_role() {
    let dir = tempfile::tempdir().unwrap();
    let curves_path = dir.path().join("curves.usda");
    let warnings = Warnings::default();
    write(&framed_curves(), &curves_path, &warnings).unwrap();
    let dropped = warnings.0.lock().unwrap().clone();
    assert_eq!(
        dropped,
        vec![format!(
            "{}: USD cannot hold point `tags` (int array); not written",
            curves_path.display()
        )]
    );
    let cube_path = dir.path().join("cube.usda");
    write(&vertex_attributed_cube(), &cube_path, &NoProgress).unwrap();
    let torus_path = dir.path().join("torus.usda");
    write(&attributed_torus(), &torus_path, &NoProgress).unwrap();
    let mut cmd = Command::new(std::env::var("GEODE_PYTHON").unwrap_or_else(|_| "python3".into()));
    cmd.arg(repo_root().join("tools/usd_check.py"));
    cmd.args([&curves_path, &cube_path, &torus_path]);
    let Some(report) = run_validator(cmd, "usd-core (pip)") else {
        return;
    };
    let files: Vec<serde_json::Value> = report
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let pv = |file: usize, key: &str| -> serde_json::Value { files[file]["primvars"][key].clone() };
    let expect = |file: usize, key: &str, ty: &str, interp: &str, count: u64| {
        let v = pv(file, key);
        assert_eq!(v["type"], ty, "{key}: {v}");
        assert_eq!(v["interpolation"], interp, "{key}: {v}");
        assert_eq!(v["count"], count, "{key}: {v}");
    };
    // Curves: 8 curve vertices, 2 curves.
    expect(0, "/geode/curves.orient", "quatf[]", "vertex", 8);
    expect(0, "/geode/curves.T", "vector3f[]", "vertex", 8);
    expect(0, "/geode/curves.B", "vector3f[]", "vertex", 8);
    expect(0, "/geode/curves.pscale", "float[]", "vertex", 8);
    expect(0, "/geode/curves.displayColor", "color3f[]", "vertex", 8);
    expect(0, "/geode/curves.id", "int[]", "uniform", 2);
    expect(0, "/geode/curves.name", "string", "constant", 1);
    assert_eq!(pv(0, "/geode/curves.T")["role"], "Vector");
    assert_eq!(pv(0, "/geode/curves.displayColor")["role"], "Color");
    // The fourth curve vertex is point 3 again (start of the second curve is
    // the fifth): orient of point 0 is the identity, real part first.
    assert_eq!(
        pv(0, "/geode/curves.orient")["first"],
        serde_json::json!([1.0, 0.0, 0.0, 0.0])
    );
    assert_eq!(pv(0, "/geode/curves.id")["first"], 7);
    assert_eq!(pv(0, "/geode/curves.name")["first"], "chain");
    // A cube's corner uvs are face-varying, the torus' point attributes vertex, its primitive ones uniform.
    expect(1, "/geode/mesh.st", "texCoord2f[]", "faceVarying", 24);
    expect(2, "/geode/mesh.st", "texCoord2f[]", "vertex", 24 * 12);
    expect(
        2,
        "/geode/mesh.displayColor",
        "color3f[]",
        "vertex",
        24 * 12,
    );
    expect(2, "/geode/mesh.weight", "float[]", "uniform", 24 * 12);
    assert!(files.iter().all(|f| f["ok"] == true), "{report}");
}

/// Texture coordinates reach trimesh from a GLB: their primitives carry the
/// default material (trimesh keeps coordinates only with one), and the v
/// flip of glTF's top-left origin comes back out.
#[test]
fn glb_texture_coordinates_reach_trimesh() {
    let dir = tempfile::tempdir().unwrap();
    let g = primitives::grid(geode_geo::glam::Vec2::new(2.0, 1.0), 3, 4);
    let path = dir.path().join("grid.glb");
    write(&g, &path, &NoProgress).unwrap();
    let mut cmd = Command::new(std::env::var("GEODE_PYTHON").unwrap_or_else(|_| "python3".into()));
    cmd.args([
        "-c",
        "import sys, json, trimesh\n\
         m = trimesh.load(sys.argv[1], force='mesh', process=False)\n\
         uv = getattr(m.visual, 'uv', None)\n\
         print(json.dumps({'uv': None if uv is None else uv.tolist(), 'v': m.vertices.tolist()}))",
    ]);
    cmd.arg(&path);
    let Some(report) = run_validator(cmd, "trimesh (pip)") else {
        return;
    };
    let v: serde_json::Value = serde_json::from_str(report.lines().last().unwrap()).unwrap();
    let uv = v["uv"]
        .as_array()
        .expect("trimesh found no texture coordinates");
    let theirs_pos = v["v"].as_array().unwrap();
    let Some(geode_geo::AttribData::Vec2(ours)) = g
        .attrib(geode_geo::AttribClass::Point, "uv")
        .map(|a| a.data())
    else {
        panic!("the grid has two-float uv");
    };
    assert_eq!(uv.len(), theirs_pos.len());
    // Match by position: each of trimesh's vertices is one of the grid's points.
    for (t, p) in uv.iter().zip(theirs_pos) {
        let p = Vec3::new(
            p[0].as_f64().unwrap() as f32,
            p[1].as_f64().unwrap() as f32,
            p[2].as_f64().unwrap() as f32,
        );
        let i = g
            .positions()
            .iter()
            .position(|q| (*q - p).length() < 1e-6)
            .unwrap_or_else(|| panic!("{p} not in {:?}", g.positions()));
        for k in 0..2 {
            assert!(
                (t[k].as_f64().unwrap() as f32 - ours[i][k]).abs() < 1e-6,
                "{t:?} vs {}",
                ours[i]
            );
        }
    }
}
