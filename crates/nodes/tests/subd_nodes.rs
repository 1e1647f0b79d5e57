//! The subdivide node on OpenSubdiv-tagged OBJ files, through the engine.

mod common;

use common::{err, geo};
use geode_geo::AttribClass;

#[test]
fn subdividing_a_creased_box_keeps_its_creases_and_closes() {
    let path = format!(
        "{}/../../examples/assets/creased_box.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let nodes = format!(
        r#""box": {{"type": "file", "params": {{"file": "{path}"}}}},
            "smooth": {{"type": "subdivide", "inputs": ["box"], "params": {{"levels": 3, "limit": true}}}}"#
    );
    let g = geo(&nodes, "smooth");
    let base = geo(&nodes, "box");
    assert_eq!(g.num_prims(), 64 * base.num_prims());
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    assert!(g.attrib(AttribClass::Point, "N").is_some());
    // Chaikin differs from uniform decay where semi-sharp creases meet.
    let shape = format!(
        "{}/../../corpus/opensubdiv/catmark_chaikin1.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let chaikin = |method: &str| {
        geo(
            &format!(
                r#""m": {{"type": "file", "params": {{"file": "{shape}"}}}}, "s": {{"type": "subdivide", "inputs": ["m"], "params": {{"levels": 2, "crease_method": "{method}"}}}}"#
            ),
            "s",
        )
    };
    assert!(
        chaikin("chaikin").positions() != chaikin("uniform").positions(),
        "the crease method is applied"
    );
    assert!(
        chaikin("from_geometry").positions() == chaikin("chaikin").positions(),
        "the shape's own tag says chaikin"
    );
    let e = err(
        r#""l": {"type": "curve_line"}, "s": {"type": "subdivide", "inputs": ["l"]}"#,
        "s",
    );
    assert!(e.contains("/s") && e.contains("not a polygon"), "{e}");
}

#[test]
fn nurbs_surfaces_are_exact_and_patches_interpolate_their_corners() {
    let s = geo(
        r#""s": {"type": "nurbs_surface", "params": {"radius": 1.5, "samples": [20, 40]}}"#,
        "s",
    );
    assert_eq!(s.num_points(), 800);
    let n = s
        .attrib(AttribClass::Point, "N")
        .unwrap()
        .as_vec3()
        .unwrap();
    for (p, n) in s.positions().iter().zip(n) {
        assert!((p.length() - 1.5).abs() < 1e-5);
        assert!(
            n.dot(*p / 1.5) > 0.9999,
            "outward radial normals, poles included: {n} at {p}"
        );
    }
    let nodes = r#""g": {"type": "grid", "params": {"size": [3, 3], "rows": 3, "columns": 3}},
        "patch": {"type": "nurbs_surface", "inputs": ["g"], "params": {"shape": "patch", "rows": 4, "columns": 4, "samples": [9, 9]}}"#;
    let grid = geo(nodes, "g");
    let patch = geo(nodes, "patch");
    for corner in [grid.positions()[0], grid.positions()[15]] {
        assert!(
            patch
                .positions()
                .iter()
                .any(|p| (*p - corner).length() < 1e-6),
            "clamped: passes through {corner}"
        );
    }
    let e = err(
        r#""g": {"type": "grid"}, "p": {"type": "nurbs_surface", "inputs": ["g"], "params": {"shape": "patch", "rows": 3, "columns": 3}}"#,
        "p",
    );
    assert!(
        e.contains("/p") && e.contains("rows") && e.contains("121 points"),
        "{e}"
    );
}

#[test]
fn hspline_edits_are_keyframable_symmetric_and_checked() {
    let nodes = r#""h": {"type": "hspline", "params": {"levels": 2, "samples": [21, 21], "symmetric": true,
        "edit_level": 2, "edit_vertex": [6, 8],
        "edit_move": [0, {"keys": [{"frame": 1, "value": 0}, {"frame": 10, "value": 0.5, "interp": "linear"}]}, 0]}}"#;
    let flat = common::cook_at(nodes, "h", 1.0).unwrap();
    let raised = common::cook_at(nodes, "h", 10.0).unwrap();
    let (flat, raised) = (flat.as_geometry().unwrap(), raised.as_geometry().unwrap());
    assert!(
        flat.positions().iter().all(|p| p.y.abs() < 1e-6),
        "no edit at frame 1: the plane"
    );
    let top = raised
        .positions()
        .iter()
        .map(|p| p.y)
        .fold(0.0f32, f32::max);
    assert!(top > 0.05, "the edit raises the surface at frame 10: {top}");
    // Symmetric across X = 0: every raised point has a mirror twin.
    for p in raised.positions().iter().filter(|p| p.y > 1e-3) {
        assert!(
            raised.positions().iter().any(|q| (q.x + p.x).abs() < 1e-4
                && (q.y - p.y).abs() < 1e-4
                && (q.z - p.z).abs() < 1e-4),
            "{p}"
        );
    }
    let e = err(
        r#""h": {"type": "hspline", "params": {"levels": 1, "region": [2, 5, 2, 5], "edits": "2 0 0 0 1 0"}}"#,
        "h",
    );
    assert!(e.contains("edits") && e.contains("not movable"), "{e}");
    let e = err(
        r#""h": {"type": "hspline", "params": {"edits": "1 2 x 0 0 0"}}"#,
        "h",
    );
    assert!(e.contains("edit 1 `1 2 x 0 0 0`"), "{e}");
}

#[test]
fn an_hspline_saved_to_hs_loads_back_to_the_same_surface() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("edited.hs");
    let f = file.to_str().unwrap();
    let saved = geo(
        &format!(
            r#""h": {{"type": "hspline", "params": {{"topology": "torus", "levels": 2, "edits": "2 10 12 0.2 0 0; 1 3 4 0 0.1 0", "save": "{f}"}}}}"#
        ),
        "h",
    );
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        text.starts_with("hspline 2\ntopology torus\n")
            && text.lines().filter(|l| l.starts_with("o ")).count() == 2,
        "{text}"
    );
    let loaded = geo(
        &format!(r#""h": {{"type": "hspline", "params": {{"levels": 0, "load": "{f}"}}}}"#),
        "h",
    );
    assert_eq!(loaded.positions(), saved.positions());
    std::fs::write(&file, "hspline 1\ntopology torus\nbase 4 x\n").unwrap();
    let e = err(
        &format!(r#""h": {{"type": "hspline", "params": {{"load": "{f}"}}}}"#),
        "h",
    );
    assert!(e.contains("load") && e.contains("line 3"), "{e}");
}

#[test]
fn hspline_enveloping_bends_with_the_skeleton_and_names_bad_joints() {
    let arm = |bend: f64, level: i64| {
        geo(
            &format!(
                r#""h": {{"type": "hspline", "params": {{"topology": "cylinder", "rows": 8, "columns": 12, "size": [0.4, 2.0], "levels": 2,
                    "envelope": "dual_quaternion", "envelope_level": {level},
                    "skeleton": "shoulder - 0 -1 0; elbow shoulder 0 0 0; wrist elbow 0 1 0", "bend_joint": "elbow", "bend": [0, 0, {bend}]}}}}"#
            ),
            "h",
        )
    };
    let straight = arm(0.0, 1);
    let bent = arm(90.0, 1);
    let top = |g: &geode_geo::Geometry| g.positions().iter().map(|p| p.y).fold(f32::MIN, f32::max);
    assert!(
        (top(&straight) - top(&arm(0.0, 2))).abs() < 1e-6,
        "at rest the level does not matter"
    );
    assert!(
        top(&bent) < top(&straight) - 0.3,
        "the forearm swings down: {} vs {}",
        top(&bent),
        top(&straight)
    );
    let e = err(
        r#""h": {"type": "hspline", "params": {"envelope": "linear", "skeleton": "a - 0 0 0; b c 0 1 0"}}"#,
        "h",
    );
    assert_eq!(
        e,
        "/h (parameter `skeleton[1].parent`): `c` is not an earlier joint"
    );
}

#[test]
fn an_enveloped_hspline_saves_its_skeleton_and_weights_and_bends_alike_when_loaded() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("arm.hs");
    let f = file.to_str().unwrap();
    let skeleton = "shoulder - 0 -1 0; elbow shoulder 0 0 0; wrist elbow 0 1 0";
    let saved = geo(
        &format!(
            r#""h": {{"type": "hspline", "params": {{"topology": "cylinder", "rows": 8, "columns": 12, "size": [0.4, 2.0], "levels": 2,
                "edits": "2 11 0 0.06 0 0", "envelope": "linear", "envelope_level": 1,
                "skeleton": "{skeleton}", "bend_joint": "elbow", "bend": [0, 0, 70], "save": "{f}"}}}}"#
        ),
        "h",
    );
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(
        text.contains("envelope level 1 method linear") && text.contains("joint wrist elbow 0 1 0"),
        "{text}"
    );
    // Loaded with the file's envelope, posed by the same bend: the same arm.
    let loaded = |bend: f64| {
        geo(
            &format!(
                r#""h": {{"type": "hspline", "params": {{"levels": 0, "load": "{f}", "envelope": "from_file", "bend_joint": "elbow", "bend": [0, 0, {bend}]}}}}"#
            ),
            "h",
        )
    };
    assert_eq!(loaded(70.0).positions(), saved.positions());
    assert_ne!(loaded(0.0).positions(), saved.positions());
    let e = err(
        r#""h": {"type": "hspline", "params": {"envelope": "from_file"}}"#,
        "h",
    );
    assert!(
        e.contains("envelope") && e.contains("needs a loaded .hs file"),
        "{e}"
    );
}

#[test]
fn skin_bends_a_mesh_at_its_elbow_with_automatic_or_given_weights() {
    let skeleton = "shoulder - 0 0 0; elbow shoulder 0 1 0; wrist elbow 0 2 0";
    let nodes = format!(
        r#""t": {{"type": "tube", "params": {{"radius": 0.15, "height": 2, "rows": 40, "columns": 16}}}},
            "auto": {{"type": "skin", "inputs": ["t"], "params": {{"skeleton": "{skeleton}", "bend_joint": "elbow", "bend": [0, 0, 90]}}}},
            "w": {{"type": "attribute_create", "inputs": ["t"], "params": {{"name": "w_elbow", "type": "float", "value": [1, 0, 0, 0]}}}},
            "given": {{"type": "skin", "inputs": ["w"], "params": {{"skeleton": "{skeleton}", "bend_joint": "elbow", "bend": [0, 0, 90], "method": "linear"}}}}"#
    );
    let tube = geo(&nodes, "t");
    let bent = geo(&nodes, "auto");
    // The top ring (y = 2) swings about the elbow (0, 1, 0) to x = -1, y = 1.
    let top: Vec<usize> = (0..tube.num_points())
        .filter(|&i| (tube.positions()[i].y - 2.0).abs() < 1e-5)
        .collect();
    let centre = top
        .iter()
        .map(|&i| bent.positions()[i])
        .sum::<geode_geo::glam::Vec3>()
        / top.len() as f32;
    assert!(
        (centre - geode_geo::glam::Vec3::new(-1.0, 1.0, 0.0)).length() < 0.05,
        "{centre}"
    );
    // The bottom ring stays.
    let bottom = (0..tube.num_points()).filter(|&i| tube.positions()[i].y.abs() < 1e-5);
    assert!(bottom
        .into_iter()
        .all(|i| (bent.positions()[i] - tube.positions()[i]).length() < 0.01));
    // Every point weighted fully to the elbow: the whole tube turns rigidly about it.
    let given = geo(&nodes, "given");
    for (a, b) in tube.positions().iter().zip(given.positions()) {
        let want = geode_geo::glam::Vec3::new(-(a.y - 1.0), 1.0 + a.x, a.z);
        assert!((*b - want).length() < 1e-5, "{a} -> {b}, want {want}");
    }
}

#[test]
fn symmetric_edits_mirror_across_x_on_wrapped_surfaces_too() {
    let g = geo(
        r#""h": {"type": "hspline", "params": {"topology": "torus", "rows": 8, "columns": 12, "size": [3, 1], "levels": 1,
            "symmetric": true, "edits": "1 4 3 0.1 0.3 0.05", "samples": [32, 48]}}"#,
        "h",
    );
    // Above the plain torus (tube radius 0.5): only the bump and its mirror.
    let bumped: Vec<_> = g.positions().iter().filter(|p| p.y > 0.52).collect();
    assert!(!bumped.is_empty());
    for p in bumped {
        assert!(
            g.positions().iter().any(|q| (q.x + p.x).abs() < 1e-4
                && (q.y - p.y).abs() < 1e-4
                && (q.z - p.z).abs() < 1e-4),
            "{p} has no mirror"
        );
    }
}

#[test]
fn nurbs_patches_stay_exact_through_transforms_and_merges_until_converted() {
    // A unit sphere as one rational patch, squashed to an ellipsoid and
    // merged with a box, then converted: the quads lie on the ellipsoid.
    let nodes = r#""s": {"type": "nurbs_surface", "params": {"output": "patch"}},
        "squash": {"type": "transform", "inputs": ["s"], "params": {"scale": [2, 0.5, 1], "translate": [0, 1, 0]}},
        "b": {"type": "box"},
        "both": {"type": "merge", "inputs": ["b", "squash"]},
        "mesh": {"type": "convert", "inputs": ["both"], "params": {"level_of_detail": 6}}"#;
    let merged = geo(nodes, "both");
    assert!(merged.has_patches());
    assert_eq!(
        merged.prim_kind(merged.num_prims() - 1),
        geode_geo::PrimKind::Patch(0)
    );
    let mesh = geo(nodes, "mesh");
    assert!(!mesh.has_patches());
    let box_points = geo(nodes, "b").num_points();
    let on = mesh.positions()[box_points..]
        .iter()
        .map(|p| {
            let q = geode_geo::glam::Vec3::new(p.x / 2.0, (p.y - 1.0) / 0.5, p.z);
            (q.length() - 1.0).abs()
        })
        .fold(0.0f32, f32::max);
    assert!(on < 1e-5, "off the ellipsoid by {on}");
    // The sphere's knots have 2 spans along u and 4 around: 6 quads a span.
    assert_eq!(mesh.num_prims(), 6 + (2 * 6) * (4 * 6));
}

#[test]
fn uv_interpolation_follows_opensubdivs_face_varying_options() {
    let shape = format!(
        "{}/../../corpus/opensubdiv/catmark_fvar_bound0.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    let uvs_at = |mode: &str, limit: bool| -> Vec<[f32; 2]> {
        let g = geo(
            &format!(
                r#""m": {{"type": "file", "params": {{"file": "{shape}"}}}}, "s": {{"type": "subdivide", "inputs": ["m"], "params": {{"levels": 2, "uv_interpolation": "{mode}", "limit": {limit}}}}}"#
            ),
            "s",
        );
        g.attrib(AttribClass::Vertex, "uv")
            .and_then(|a| a.as_vec2())
            .unwrap()
            .iter()
            .map(|v| [v.x, v.y])
            .collect()
    };
    let uvs = |mode: &str| uvs_at(mode, false);
    let (none, boundaries, all) = (uvs("none"), uvs("boundaries"), uvs("all"));
    // With `limit` smooth uvs move to their limit; bilinear ones stay.
    assert_ne!(uvs_at("none", true), none);
    assert_eq!(uvs_at("all", true), all);
    assert_ne!(none, boundaries);
    assert_ne!(boundaries, all);
    // Pinned boundaries keep the corners of the uv square; smooth ones
    // round them off.
    let corners = [[0.0f32, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    for c in corners {
        assert!(boundaries.contains(&c) && all.contains(&c), "{c:?} pinned");
    }
    assert!(
        corners.iter().any(|c| !none.contains(c)),
        "smooth boundaries move corners"
    );
    // The default, without a tag, is `boundaries`.
    assert_eq!(uvs("from_geometry"), boundaries);
}

#[test]
fn an_hspline_as_a_patch_converts_to_its_own_surface() {
    let nodes = r#""h": {"type": "hspline", "params": {"topology": "torus", "levels": 1, "edits": "1 3 4 0.2 0 0", "output": "patch"}},
        "c": {"type": "convert", "inputs": ["h"], "params": {"level_of_detail": 4}}"#;
    let patch = geo(nodes, "h");
    assert_eq!(patch.prim_kind(0), geode_geo::PrimKind::Patch(0));
    // A wrapped side closes on the same points: no more points than the grid.
    assert_eq!(patch.num_points(), 12 * 12);
    let mesh = geo(nodes, "c");
    assert!(!mesh.has_patches());
    // 12 spans a side at 4 quads each samples k / 48 of the domain, as
    // the hspline's own tessellation at 48 x 48 does: the same points.
    let tess = geo(
        r#""h": {"type": "hspline", "params": {"topology": "torus", "levels": 1, "edits": "1 3 4 0.2 0 0", "samples": [48, 48]}}"#,
        "h",
    );
    let near = |p: geode_geo::glam::Vec3| {
        tess.positions()
            .iter()
            .map(|q| q.distance(p))
            .fold(f32::INFINITY, f32::min)
    };
    let worst = mesh
        .positions()
        .iter()
        .map(|&p| near(p))
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-5,
        "patch samples off the hspline surface by {worst}"
    );
}
