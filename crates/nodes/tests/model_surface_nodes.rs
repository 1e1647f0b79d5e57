//! The surface modelling nodes through the engine: smooth, peak, mountain,
//! bound and match_size cook from networks, keep the input's attributes and
//! groups, give analytic answers on spheres and boxes, are the same bytes
//! on one and two threads, and name the parameter a bad value is in.

mod common;

use common::{cook_errors, geo};
use geode_geo::glam::{Mat3, Vec3};
use geode_geo::{ops, AttribClass, AttribData, Geometry};

fn vec3s(g: &Geometry, class: AttribClass, name: &str) -> Vec<Vec3> {
    match g.attrib(class, name).map(|a| a.data()) {
        Some(AttribData::Vec3(v)) => v.clone(),
        other => panic!("no vector {name}: {other:?}"),
    }
}

fn float(g: &Geometry, name: &str) -> f32 {
    match g.attrib(AttribClass::Detail, name).map(|a| a.data()) {
        Some(AttribData::Float(v)) => v[0],
        other => panic!("no float {name}: {other:?}"),
    }
}

fn bits(g: &Geometry) -> Vec<[u32; 3]> {
    g.positions()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

/// The parameter the only error of cooking `output` blames.
fn blamed(nodes: &str, output: &str) -> (Option<String>, String) {
    let errors = cook_errors(nodes, output);
    assert_eq!(errors.len(), 1, "{errors:?}");
    (errors[0].param.clone(), errors[0].to_string())
}

/// A sphere with a random point colour and a point group `top` (y > 0.5).
const DECORATED_SPHERE: &str = r#"
    "s": {"type": "sphere", "params": {"rows": 24, "columns": 48}},
    "c": {"type": "attribute_randomize", "inputs": ["s"]},
    "top": {"type": "group_bbox", "inputs": ["c"], "params": {"group": "top", "min": [-2, 0.5, -2], "max": [2, 2, 2]}}"#;

#[test]
fn smooth_keeps_attributes_groups_and_pinned_points() {
    let input = geo(DECORATED_SPHERE, "top");
    let g = geo(
        &format!(
            r#"{DECORATED_SPHERE}, "sm": {{"type": "smooth", "inputs": ["top"], "params": {{"method": "laplacian", "iterations": 5, "pin_group": "top"}}}}"#
        ),
        "sm",
    );
    assert_eq!(
        vec3s(&input, AttribClass::Point, "Cd"),
        vec3s(&g, AttribClass::Point, "Cd")
    );
    let top = &g.point_groups()["top"];
    assert_eq!(top, &input.point_groups()["top"]);
    let (a, b) = (bits(&input), bits(&g));
    for i in 0..g.num_points() {
        if top.contains(i) {
            assert_eq!(a[i], b[i], "pinned point {i} moved");
        }
    }
    // The free part shrank (Laplacian), the pinned part did not.
    let lowest = g.positions().iter().map(|p| p.y).fold(f32::MAX, f32::min);
    assert!(lowest > -0.99, "{lowest}");
}

#[test]
fn smooth_names_the_parameter_at_fault() {
    let (param, text) = blamed(
        r#""g": {"type": "grid"}, "sm": {"type": "smooth", "inputs": ["g"], "params": {"keep_volume": true}}"#,
        "sm",
    );
    assert_eq!(param.as_deref(), Some("keep_volume"), "{text}");
    assert!(
        text.contains("not shared by exactly two polygons"),
        "{text}"
    );
    let (param, text) = blamed(
        &format!(
            r#"{DECORATED_SPHERE}, "sm": {{"type": "smooth", "inputs": ["top"], "params": {{"pin_group": "bottom"}}}}"#
        ),
        "sm",
    );
    assert_eq!(param.as_deref(), Some("pin_group"), "{text}");
    assert!(text.contains("`bottom`") && text.contains("top"), "{text}");
    let e = common::err(
        r#""g": {"type": "grid"}, "sm": {"type": "smooth", "inputs": ["g"], "params": {"strength": 1.5}}"#,
        "sm",
    );
    assert!(e.contains("strength") && e.contains("maximum"), "{e}");
}

#[test]
fn taubin_smoothing_with_volume_keeping_holds_a_spheres_volume() {
    let input = geo(
        r#""s": {"type": "sphere", "params": {"rows": 24, "columns": 48}}"#,
        "s",
    );
    let g = geo(
        r#""s": {"type": "sphere", "params": {"rows": 24, "columns": 48}},
           "sm": {"type": "smooth", "inputs": ["s"], "params": {"iterations": 20, "keep_volume": true}}"#,
        "sm",
    );
    let (v0, v1) = (ops::signed_volume(&input), ops::signed_volume(&g));
    assert!((v1 / v0 - 1.0).abs() < 1e-4, "{v0} -> {v1}");
}

#[test]
fn peak_moves_a_sphere_to_radius_one_plus_distance() {
    let g = geo(
        r#""s": {"type": "sphere", "params": {"rows": 48, "columns": 96}},
           "n": {"type": "normals", "inputs": ["s"], "params": {"class": "point"}},
           "p": {"type": "peak", "inputs": ["n"], "params": {"distance": 0.5}}"#,
        "p",
    );
    for p in g.positions() {
        assert!((p.length() - 1.5).abs() < 1e-3, "radius {}", p.length());
    }
    // N was recomputed: still the unit outward normal of the bigger sphere.
    for (p, n) in g.positions().iter().zip(vec3s(&g, AttribClass::Point, "N")) {
        assert!(n.dot(p.normalize()) > 0.999);
    }
    // Without N, area-weighted normals; a group moves alone.
    let g = geo(
        &format!(
            r#"{DECORATED_SPHERE}, "p": {{"type": "peak", "inputs": ["top"], "params": {{"distance": -0.25, "group": "top"}}}}"#
        ),
        "p",
    );
    let top = &g.point_groups()["top"];
    for (i, p) in g.positions().iter().enumerate() {
        let expected = if top.contains(i) { 0.75 } else { 1.0 };
        assert!(
            (p.length() - expected).abs() < 1e-3,
            "point {i}: {}",
            p.length()
        );
    }
}

fn mountain(noise: &str, seed: i64) -> String {
    format!(
        r#""s": {{"type": "sphere", "params": {{"rows": 64, "columns": 128}}}},
           "m": {{"type": "mountain", "inputs": ["s"], "params": {{"noise": "{noise}", "height": 0.2, "element_size": 0.4, "seed": {seed}, "offset": [0.3, 0, 0]}}}}"#
    )
}

#[test]
fn mountain_is_deterministic_bounded_and_along_the_normals() {
    let sphere = geo(
        r#""s": {"type": "sphere", "params": {"rows": 64, "columns": 128}}"#,
        "s",
    );
    let normals = geode_model::deform::area_weighted_normals(&sphere);
    for noise in ["perlin", "simplex", "worley"] {
        let one = common::cook_on(1, &mountain(noise, 4), "m");
        let two = common::cook_on(2, &mountain(noise, 4), "m");
        assert_eq!(bits(&one), bits(&two), "{noise}: thread counts");
        assert_eq!(
            bits(&one),
            bits(&geo(&mountain(noise, 4), "m")),
            "{noise}: twice"
        );
        let mut largest = 0.0f32;
        for ((p, q), n) in sphere.positions().iter().zip(one.positions()).zip(&normals) {
            let d = *q - *p;
            assert!(d.length() <= 0.2 + 1e-6, "{noise}: moved {}", d.length());
            assert!(d.cross(*n).length() < 1e-5, "{noise}: tangential {d}");
            largest = largest.max(d.length());
        }
        assert!(largest > 0.02, "{noise}: largest move {largest}");
        let other = geo(&mountain(noise, 5), "m");
        let differ = one
            .positions()
            .iter()
            .zip(other.positions())
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differ > one.num_points() / 2,
            "{noise}: seeds differ at {differ}"
        );
    }
    let (param, text) = blamed(
        r#""s": {"type": "sphere"}, "m": {"type": "mountain", "inputs": ["s"], "params": {"element_size": 0}}"#,
        "m",
    );
    assert_eq!(param.as_deref(), Some("element_size"), "{text}");
    // A height past single precision names the height.
    let (param, text) = blamed(
        r#""s": {"type": "sphere"}, "m": {"type": "mountain", "inputs": ["s"], "params": {"height": 1e39}}"#,
        "m",
    );
    assert_eq!(param.as_deref(), Some("height"), "{text}");
    assert!(text.contains("height must be finite"), "{text}");
}

const TILTED_BOX: &str = r#"
    "b": {"type": "box", "params": {"size": [2, 1, 0.5], "divisions": [4, 2, 2]}},
    "t": {"type": "transform", "inputs": ["b"], "params": {"rotate": [30, 40, 50], "translate": [1, 2, 3]}},
    "tg": {"type": "group_bbox", "inputs": ["t"], "params": {"group": "all", "min": [-9, -9, -9], "max": [9, 9, 9]}}"#;

#[test]
fn bound_gives_the_box_the_oriented_box_and_the_sphere() {
    let input = geo(TILTED_BOX, "tg");
    let aabb = ops::bounds(&input).unwrap();
    let bound = |params: &str| {
        geo(
            &format!(
                r#"{TILTED_BOX}, "bd": {{"type": "bound", "inputs": ["tg"], "params": {params}}}"#
            ),
            "bd",
        )
    };
    let b = bound(r#"{"padding": 0.1}"#);
    assert_eq!((b.num_points(), b.num_prims()), (8, 6));
    let padded = ops::bounds(&b).unwrap();
    assert!((padded.min - (aabb.min - 0.1)).abs().max_element() < 1e-5);
    assert!((padded.max - (aabb.max + 0.1)).abs().max_element() < 1e-5);
    assert!(ops::signed_volume(&b) > 0.0, "outward quads");

    let o = bound(r#"{"type": "oriented"}"#);
    let v = ops::signed_volume(&o);
    assert!((v - 1.0).abs() < 0.01, "oriented volume {v}");
    let size = vec3s(&o, AttribClass::Detail, "size")[0];
    let mut sides = size.to_array();
    sides.sort_by(f32::total_cmp);
    assert!(
        (Vec3::from_array(sides) - Vec3::new(0.5, 1.0, 2.0))
            .abs()
            .max_element()
            < 1e-4
    );
    let centre = vec3s(&o, AttribClass::Detail, "center")[0];
    assert!((centre - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-5);
    match o.attrib(AttribClass::Detail, "axes").map(|a| a.data()) {
        Some(AttribData::Mat3(m)) => {
            let m: Mat3 = m[0];
            assert!((m * m.transpose() - Mat3::IDENTITY).abs_diff_eq(Mat3::ZERO, 1e-5));
        }
        other => panic!("axes: {other:?}"),
    }

    // The sphere around a box is the one through its corners.
    let s = bound(r#"{"type": "sphere", "output": "attributes"}"#);
    let half_diagonal = Vec3::new(1.0, 0.5, 0.25).length();
    assert!((float(&s, "radius") - half_diagonal).abs() < 1e-5);
    // The attributes output is the input with the detail attributes.
    assert_eq!(bits(&s), bits(&input));
    assert_eq!(s.point_groups()["all"], input.point_groups()["all"]);
    assert_eq!(vec3s(&s, AttribClass::Detail, "bbox_min")[0], aabb.min);
}

#[test]
fn bound_names_a_missing_group() {
    let (param, text) = blamed(
        &format!(
            r#"{TILTED_BOX}, "bd": {{"type": "bound", "inputs": ["tg"], "params": {{"group": "some"}}}}"#
        ),
        "bd",
    );
    assert_eq!(param.as_deref(), Some("group"), "{text}");
    assert!(text.contains("all"), "{text}");
}

#[test]
fn match_size_fits_the_reference_or_the_target() {
    // A 2 x 4 x 6 box onto a unit sphere's bounds, per axis: [-1, 1]³.
    let fitted = geo(
        r#""b": {"type": "box", "params": {"size": [2, 4, 6], "center": [5, 5, 5]}},
           "c": {"type": "attribute_randomize", "inputs": ["b"]},
           "s": {"type": "sphere"},
           "m": {"type": "match_size", "inputs": ["c", "s"], "params": {"scale": "per_axis"}}"#,
        "m",
    );
    let b = ops::bounds(&fitted).unwrap();
    assert!((b.min + Vec3::ONE).abs().max_element() < 1e-5, "{b:?}");
    assert!((b.max - Vec3::ONE).abs().max_element() < 1e-5, "{b:?}");
    assert!(fitted.attrib(AttribClass::Point, "Cd").is_some());
    // No reference: onto the target centre, the minimum y on its floor.
    let moved = geo(
        r#""b": {"type": "box", "params": {"size": [2, 4, 6], "center": [5, 5, 5]}},
           "m": {"type": "match_size", "inputs": ["b"], "params": {"target_center": [0, 0, 0], "target_size": [1, 1, 1], "justify_y": "min", "scale": "uniform"}}"#,
        "m",
    );
    let b = ops::bounds(&moved).unwrap();
    assert!(
        (b.size() - Vec3::new(2.0, 4.0, 6.0) / 6.0)
            .abs()
            .max_element()
            < 1e-5,
        "{b:?}"
    );
    assert!(
        (b.min.y + 0.5).abs() < 1e-6 && b.center().x.abs() < 1e-6,
        "{b:?}"
    );
}
