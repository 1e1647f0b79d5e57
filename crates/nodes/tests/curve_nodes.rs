//! Curves, frames, sweeps, copy to points, scatter and space colonization
//! through the engine, against analytic answers.

mod common;

use common::{cook_at, err, geo};
use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass};

fn attr3<'a>(g: &'a geode_geo::Geometry, name: &str) -> &'a [Vec3] {
    g.attrib(AttribClass::Point, name)
        .unwrap()
        .as_vec3()
        .unwrap()
}

#[test]
fn polyframe_writes_orthonormal_frames_and_orient() {
    let g = geo(
        r#""h": {"type": "curve_helix", "params": {"points": 300}},
            "f": {"type": "polyframe", "inputs": ["h"]}"#,
        "f",
    );
    let (t, n, b) = (attr3(&g, "T"), attr3(&g, "N"), attr3(&g, "B"));
    let o = g
        .attrib(AttribClass::Point, "orient")
        .unwrap()
        .as_quat()
        .unwrap();
    for i in 0..g.num_points() {
        assert!(t[i].dot(n[i]).abs() < 1e-5 && (n[i].length() - 1.0).abs() < 1e-5);
        assert!((n[i].cross(t[i]) - b[i]).length() < 1e-5);
        assert!((o[i] * Vec3::Z - t[i]).length() < 1e-5);
        assert!((o[i] * Vec3::Y - n[i]).length() < 1e-5);
    }
}

#[test]
fn the_chain_alternates_links_a_quarter_turn_about_the_curve() {
    let nodes = r#""knot": {"type": "curve_knot", "params": {"points": 400}},
        "even": {"type": "resample", "inputs": ["knot"], "params": {"mode": "count", "count": 60}},
        "frames": {"type": "polyframe", "inputs": ["even"], "params": {"roll_per_point": 90}},
        "link": {"type": "torus", "params": {"major_radius": 0.06, "minor_radius": 0.015}},
        "chain": {"type": "copy_to_points", "inputs": ["link", "frames"]}"#;
    let frames = geo(nodes, "frames");
    let chain = geo(nodes, "chain");
    assert_eq!(frames.num_points(), 60);
    assert_eq!(chain.num_prims(), 60, "one packed link per point");
    let o = frames
        .attrib(AttribClass::Point, "orient")
        .unwrap()
        .as_quat()
        .unwrap();
    let t = attr3(&frames, "T");
    for i in 1..60 {
        // Link i's +Y is the previous link's +Y turned about the tangent by
        // about 90 degrees (the frames themselves barely turn per step).
        let (a, b) = (o[i - 1] * Vec3::Y, o[i] * Vec3::Y);
        assert!(a.dot(b).abs() < 0.25, "{i}: {}", a.dot(b));
        assert!((o[i] * Vec3::Z - t[i]).length() < 1e-5);
    }
    let unpacked = ops::unpack(&chain).unwrap();
    assert_eq!(unpacked.num_prims(), 60 * 24 * 12);
}

#[test]
fn capped_sweeps_are_closed_and_face_out() {
    let g = geo(
        r#""h": {"type": "curve_helix", "params": {"points": 200, "turns": 2}},
            "tube": {"type": "sweep", "inputs": ["h"], "params": {"radius": 0.1, "sides": 16, "ramp": "0 1, 1 0.5"}}"#,
        "tube",
    );
    assert!(g.topology().manifold_report(&g).is_closed_manifold());
    assert!(ops::signed_volume(&g) > 0.0);
    assert!(g.attrib(AttribClass::Vertex, "uv").is_some());
    let e = err(
        r#""h": {"type": "curve_helix"}, "s": {"type": "sweep", "inputs": ["h"], "params": {"ramp": "0 1, x"}}"#,
        "s",
    );
    assert!(
        e.contains("/s") && e.contains("ramp") && e.contains("key 2"),
        "{e}"
    );
}

/// Winding number by solid angles (Van Oosterom and Strackee), brute force:
/// an independent check of the scatter node's inside test.
fn winding(g: &geode_geo::Geometry, q: Vec3) -> f64 {
    let p = g.positions();
    let mut total = 0.0f64;
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        for k in 1..pts.len() - 1 {
            let [a, b, c] = [pts[0], pts[k], pts[k + 1]].map(|i| (p[i as usize] - q).as_dvec3());
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let num = a.dot(b.cross(c));
            let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
            total += 2.0 * num.atan2(den);
        }
    }
    total / (4.0 * std::f64::consts::PI)
}

#[test]
fn scatter_inside_is_inside_exact_and_seeded() {
    let mesh = r#""t": {"type": "torus", "params": {"major_radius": 1, "minor_radius": 0.4, "rows": 12, "columns": 24}}"#;
    let pts = |seed: i64, relax: bool| {
        geo(
            &format!(
                r#"{mesh}, "s": {{"type": "scatter", "inputs": ["t"], "params": {{"count": 500, "seed": {seed}, "relax": {relax}}}}}"#
            ),
            "s",
        )
    };
    let torus = geo(mesh, "t");
    let a = pts(1, false);
    assert_eq!(a.num_points(), 500);
    for q in a.positions() {
        assert!(
            (winding(&torus, *q) - 1.0).abs() < 1e-6,
            "{q} is not inside the mesh"
        );
    }
    assert_eq!(a.positions(), pts(1, false).positions());
    assert_ne!(a.positions(), pts(2, false).positions());
    let blue = pts(1, true);
    assert_eq!(blue.num_points(), 500);
    assert!(blue
        .positions()
        .iter()
        .all(|q| (winding(&torus, *q) - 1.0).abs() < 1e-6));
    // Analytic solids through fields: every point satisfies the inequality.
    for (field, inside) in [
        (
            r#""f": {"type": "frep_sphere", "params": {"radius": 0.8}}"#,
            Box::new(|q: Vec3| q.length() <= 0.8) as Box<dyn Fn(Vec3) -> bool>,
        ),
        (
            r#""f": {"type": "frep_torus", "params": {"major_radius": 1, "minor_radius": 0.3}}"#,
            Box::new(|q: Vec3| (Vec3::new(q.x, 0.0, q.z).length() - 1.0).hypot(q.y) <= 0.3),
        ),
    ] {
        let g = geo(
            &format!(
                r#"{field}, "s": {{"type": "scatter_field", "inputs": ["f"], "params": {{"min": [-1.5, -1.5, -1.5], "max": [1.5, 1.5, 1.5], "count": 2000}}}}"#
            ),
            "s",
        );
        assert_eq!(g.num_points(), 2000);
        assert!(g.positions().iter().all(|q| inside(*q)));
    }
    // On the surface: points lie on the faces, N is the face normal.
    let s = geo(
        r#""b": {"type": "box", "params": {"size": [2, 2, 2]}}, "s": {"type": "scatter", "inputs": ["b"], "params": {"mode": "surface", "count": 300}}"#,
        "s",
    );
    for (q, n) in s.positions().iter().zip(attr3(&s, "N")) {
        assert!((q.abs().max_element() - 1.0).abs() < 1e-5);
        assert!(
            (q.dot(*n) - 1.0).abs() < 1e-4,
            "outward unit normal of the face the point is on"
        );
    }
}

#[test]
fn colonization_terminates_grows_by_frame_and_thickens_to_the_root() {
    let nodes = r#""ball": {"type": "frep_sphere", "params": {"radius": 1}},
        "attractors": {"type": "scatter_field", "inputs": ["ball"], "params": {"count": 3000, "seed": 4}},
        "birth": {"type": "curve_line", "params": {"start": [0, -1, 0], "end": [0, -0.95, 0], "points": 2}},
        "tree": {"type": "space_colonize", "inputs": ["attractors", "birth"], "params": {"influence": 0.3, "kill": 0.06, "step": 0.03,
            "iterations": {"keys": [{"frame": 1, "value": 1}, {"frame": 1001, "value": 1001, "interp": "linear"}]}}}"#;
    let full = cook_at(nodes, "tree", 1000.0).unwrap();
    let full = full.as_geometry().unwrap();
    let early = cook_at(nodes, "tree", 20.0).unwrap();
    let early = early.as_geometry().unwrap();
    let gen = |g: &geode_geo::Geometry| {
        g.attrib(AttribClass::Point, "generation")
            .unwrap()
            .as_i32()
            .unwrap()
            .to_vec()
    };
    assert!(gen(early).iter().all(|&k| k <= 20));
    // Growth is a prefix: the first steps are the same points.
    assert_eq!(&full.positions()[..early.num_points()], early.positions());
    assert!(full.num_points() > 3 * early.num_points());
    // Along each branch (root to tip) generation rises and radius falls.
    let r = full
        .attrib(AttribClass::Point, "pscale")
        .unwrap()
        .as_f32()
        .unwrap();
    let g = gen(full);
    for prim in 0..full.num_prims() {
        let pts = full.prim_points(prim);
        for w in pts.windows(2) {
            let (a, b) = (w[0] as usize, w[1] as usize);
            assert!(g[b] > g[a] && r[b] <= r[a] + 1e-6);
        }
    }
}

#[test]
fn density_sets_the_count_from_volume_or_area() {
    let count = |mode: &str, density: f64| {
        geo(&format!(r#""b": {{"type": "box", "params": {{"size": [2, 2, 2]}}}}, "s": {{"type": "scatter", "inputs": ["b"], "params": {{"mode": "{mode}", "density": {density}}}}}"#), "s").num_points()
    };
    assert_eq!(count("inside", 100.0), 800, "volume 8");
    assert_eq!(count("surface", 10.0), 240, "area 24");
    let n = geo(r#""f": {"type": "frep_sphere", "params": {"radius": 1}}, "s": {"type": "scatter_field", "inputs": ["f"], "params": {"min": [-1, -1, -1], "max": [1, 1, 1], "density": 1000}}"#, "s").num_points();
    let want = 4000.0 * std::f64::consts::PI / 3.0;
    assert!((n as f64 - want).abs() / want < 0.02, "{n} vs {want}");
}

/// A wrangle's `p@orient` is a plain vector4 column (no quaternion type):
/// copy_to_points still turns each copy by it, and an int `pscale` scales.
/// Copy k of source point s lands at P_k + R_z((k + 1) 90 deg) (2 s).
#[test]
fn copies_follow_an_orient_a_wrangle_wrote() {
    let nodes = r#"
        "source": {"type": "curve_line", "params": {"start": [1, 0, 0], "end": [1, 0, 2], "points": 2}},
        "line": {"type": "curve_line", "params": {"start": [0, 0, 0], "end": [0, 5, 0], "points": 2}},
        "aim": {"type": "wrangle", "inputs": ["line"], "params": {"snippet":
            "p@orient = quaternion(radians(90) * (@ptnum + 1), {0, 0, 1});\ni@pscale = 2;"}},
        "copy": {"type": "copy_to_points", "inputs": ["source", "aim"], "params": {"pack": false}}"#;
    let aim = geo(nodes, "aim");
    assert!(
        matches!(
            aim.attrib(AttribClass::Point, "orient").unwrap().data(),
            geode_geo::AttribData::Vec4(_)
        ),
        "the wrangle writes a vector4, the case this test is about"
    );
    let g = geo(nodes, "copy");
    let expected = [
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::new(0.0, 2.0, 4.0),
        Vec3::new(-2.0, 5.0, 0.0),
        Vec3::new(-2.0, 5.0, 4.0),
    ];
    assert_eq!(g.num_points(), 4);
    for (got, want) in g.positions().iter().zip(expected) {
        assert!((*got - want).length() < 1e-5, "{got} != {want}");
    }
    // The placing attributes are consumed, not carried onto the copies.
    assert!(g.attrib(AttribClass::Point, "orient").is_none());
    assert!(g.attrib(AttribClass::Point, "pscale").is_none());
}

/// An instance attribute whose type cannot mean what its name does is a
/// cook error naming the node, the attribute and the type it must have.
#[test]
fn a_string_orient_is_an_error_naming_node_attribute_and_type() {
    let nodes = |snippet: &str| {
        format!(
            r#""source": {{"type": "curve_line"}},
            "line": {{"type": "curve_line", "params": {{"points": 3}}}},
            "aim": {{"type": "wrangle", "inputs": ["line"], "params": {{"snippet": "{snippet}"}}}},
            "copy": {{"type": "copy_to_points", "inputs": ["source", "aim"]}}"#
        )
    };
    for (snippet, name, expected) in [
        ("s@orient = 'x';", "orient", "float4"),
        ("v@rot = {1, 0, 0};", "rot", "float4"),
        ("p@N = {0, 0, 0, 1};", "N", "float3"),
        ("v@pscale = {1, 1, 1};", "pscale", "a float or an int"),
    ] {
        let e = common::cook_errors(&nodes(snippet), "copy");
        assert_eq!(e[0].path, "/copy", "{snippet}");
        let text = e[0].to_string();
        assert!(
            text.contains(&format!("`{name}`")) && text.contains(expected),
            "{snippet}: {text}"
        );
    }
}

/// PolyPath through the engine: a Y of two-point segments (as a growth
/// wrangle writes them) becomes three polylines, one per branch, and a
/// ring of segments one closed polygon or, with close_loops off, an open
/// polyline back to its start.
#[test]
fn polypath_joins_segments_into_branches_and_loops() {
    let y = r#"
        "base": {"type": "curve_line", "params": {"start": [0, 0, 0], "end": [0, 1, 0], "points": 2}},
        "seg": {"type": "wrangle", "inputs": ["base"], "params": {"run_over": "detail", "snippet":
            "vector at[] = {{0,2,0}, {-1,3,0}, {-2,4,0}, {1,3,0}, {2,4,0}};\nforeach (vector p; at) addpoint(0, p);\nint s[] = {1,2, 2,3, 3,4, 2,5, 5,6};\nfor (int k = 0; k < len(s); k += 2) { int pr = addprim(0, \"polyline\"); addvertex(0, pr, s[k]); addvertex(0, pr, s[k + 1]); }"}},
        "paths": {"type": "polypath", "inputs": ["seg"]}"#;
    let g = geo(y, "paths");
    let prims: Vec<Vec<u32>> = (0..g.num_prims())
        .map(|p| g.prim_points(p).to_vec())
        .collect();
    assert_eq!(prims, vec![vec![0, 1, 2], vec![2, 3, 4], vec![2, 5, 6]]);
    let ring = |close: bool| {
        format!(
            r#""c": {{"type": "curve_circle", "params": {{"points": 6}}}},
            "cut": {{"type": "wrangle", "inputs": ["c"], "params": {{"run_over": "primitives", "snippet":
                "int n = len(primpoints(0, @primnum));\nfor (int k = 0; k < n; k++) {{ int pr = addprim(0, \"polyline\"); addvertex(0, pr, k); addvertex(0, pr, (k + 1) % n); }}\nremoveprim(0, @primnum, 0);"}}}},
            "paths": {{"type": "polypath", "inputs": ["cut"], "params": {{"close_loops": {close}}}}}"#
        )
    };
    let closed = geo(&ring(true), "paths");
    assert_eq!(closed.num_prims(), 1);
    assert_eq!(closed.prim_kind(0), geode_geo::PrimKind::Polygon);
    assert_eq!(closed.prim_points(0), [0, 1, 2, 3, 4, 5]);
    let open = geo(&ring(false), "paths");
    assert_eq!(open.prim_kind(0), geode_geo::PrimKind::Polyline);
    assert_eq!(open.prim_points(0), [0, 1, 2, 3, 4, 5, 0]);
    let bare = r#"
        "base": {"type": "curve_line"},
        "bare": {"type": "wrangle", "inputs": ["base"], "params": {"run_over": "detail", "snippet": "removeprim(0, 0, 0);"}},
        "paths": {"type": "polypath", "inputs": ["bare"]}"#;
    assert!(
        err(bare, "paths").contains("no curves"),
        "{}",
        err(bare, "paths")
    );
}
