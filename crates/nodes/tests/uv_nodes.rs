//! The UV nodes through the engine: a tube cut along a seam flattens
//! without angle distortion into one island inside the unit square; box and
//! cylindrical projections land where their definitions say.

mod common;

use common::{err, geo};
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{AttribClass, AttribData, Geometry};

fn uv(g: &Geometry) -> Vec<Vec3> {
    match g.attrib(AttribClass::Vertex, "uv").map(|a| a.data()) {
        Some(AttribData::Vec3(v)) => v.clone(),
        other => panic!("no vertex uv: {other:?}"),
    }
}

/// The largest difference between a corner's angle in 3D and in uv.
fn angle_distortion(g: &Geometry) -> f32 {
    let uv = uv(g);
    let p = g.positions();
    let mut worst = 0.0f32;
    for prim in 0..g.num_prims() {
        let r = g.prim_vertex_range(prim);
        let n = r.len();
        for k in 0..n {
            let (a, b, c) = (
                r.start + (k + n - 1) % n,
                r.start + k,
                r.start + (k + 1) % n,
            );
            let vp = g.vertex_points();
            let (pa, pb, pc) = (p[vp[a] as usize], p[vp[b] as usize], p[vp[c] as usize]);
            let three = (pa - pb).angle_between(pc - pb);
            let (ua, ub, uc) = (uv[a].truncate(), uv[b].truncate(), uv[c].truncate());
            let flat = (ua - ub).angle_to(uc - ub).abs();
            worst = worst.max((three - flat).abs());
        }
    }
    worst
}

const TUBE: &str = r#""t": {"type": "tube", "params": {"radius": 1, "height": 3, "rows": 12, "columns": 48, "caps": false}},
    "seam": {"type": "group_expression", "inputs": ["t"], "params": {"group": "seam", "class": "point", "expression": "x > 0.999 && abs(z) < 0.001"}},
    "f": {"type": "uv_flatten", "inputs": ["seam"], "params": {"seams": "seam"}}"#;

#[test]
fn a_tube_cut_along_a_seam_flattens_without_distortion() {
    let g = geo(TUBE, "f");
    let d = angle_distortion(&g);
    assert!(d < 1e-3, "angle distortion {d}");
    let islands = g
        .attrib(AttribClass::Primitive, "island")
        .unwrap()
        .as_i32()
        .unwrap();
    assert!(islands.iter().all(|&i| i == 0), "one island");
    assert!(uv(&g)
        .iter()
        .all(|u| u.x >= 0.0 && u.x <= 1.0 && u.y >= 0.0 && u.y <= 1.0));
    // Without the seam the tube cannot open: it is cut at its rims only.
    let closed = geo(&TUBE.replace(r#""seams": "seam""#, r#""seams": """#), "f");
    assert!(angle_distortion(&closed) > 0.01);
    // Explicit edges name the same seam.
    let e = err(
        &TUBE.replace(r#""seams": "seam""#, r#""seams": "p0-99999""#),
        "f",
    );
    assert!(e.contains("seams") && e.contains("no point 99999"), "{e}");
}

#[test]
fn projections_follow_their_definitions() {
    let g = geo(
        r#""b": {"type": "box", "params": {"size": [2, 2, 2]}},
           "p": {"type": "uv_project", "inputs": ["b"], "params": {"type": "box"}}"#,
        "p",
    );
    // Each face covers the unit square exactly (the frame fitted to the box).
    let uv = uv(&g);
    for prim in 0..g.num_prims() {
        let r = g.prim_vertex_range(prim);
        let (lo, hi) = r
            .clone()
            .fold((Vec2::splat(9.0), Vec2::splat(-9.0)), |(lo, hi), v| {
                (lo.min(uv[v].truncate()), hi.max(uv[v].truncate()))
            });
        assert!(
            lo.abs_diff_eq(Vec2::ZERO, 1e-5) && hi.abs_diff_eq(Vec2::ONE, 1e-5),
            "face {prim}: {lo} {hi}"
        );
    }
    // Planar along Y of a grid: u follows x, v follows -z, offset and scaled.
    let g = geo(
        r#""g": {"type": "grid", "params": {"size": [4, 2], "rows": 2, "columns": 4}},
           "p": {"type": "uv_project", "inputs": ["g"], "params": {"uv_scale": [2, 1], "uv_offset": [1, 0]}}"#,
        "p",
    );
    let uv = self::uv(&g);
    for (v, &pt) in g.vertex_points().iter().enumerate() {
        let q = g.positions()[pt as usize];
        let want = Vec2::new((q.x / 4.0 + 0.5) * 2.0 + 1.0, -q.z / 2.0 + 0.5);
        assert!(
            uv[v].truncate().abs_diff_eq(want, 1e-5),
            "vertex {v}: {} against {want}",
            uv[v]
        );
    }
}

/// Per polygon: uv area over 3D area (shoelace in uv, Newell in 3D).
fn area_spread(g: &Geometry) -> f32 {
    let uv = uv(g);
    let p = g.positions();
    let vp = g.vertex_points();
    let ratios: Vec<f32> = (0..g.num_prims())
        .map(|prim| {
            let r = g.prim_vertex_range(prim);
            let (mut flat, mut solid) = (0.0f32, Vec3::ZERO);
            for k in r.clone() {
                let next = if k + 1 == r.end { r.start } else { k + 1 };
                flat += uv[k].truncate().perp_dot(uv[next].truncate());
                solid += p[vp[k] as usize].cross(p[vp[next] as usize]);
            }
            0.5 * flat / (0.5 * solid.length())
        })
        .collect();
    assert!(ratios.iter().all(|&r| r > 0.0), "a polygon flipped");
    let (lo, hi) = ratios
        .iter()
        .fold((f32::MAX, 0.0f32), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    hi / lo
}

/// A torus cut along a meridian and its outer ring is one strip: the
/// default spectral method lays it out as an even band (the continuous
/// rectangle's density spread is ((R + r) / (R - r))^2 = 2.8); two pins
/// let it curl, its density varying thousands of times.
#[test]
fn a_cut_torus_stays_an_even_band_by_default() {
    let nodes = |method: &str| {
        format!(
            r#""t": {{"type": "torus", "params": {{"rows": 16, "columns": 48}}}},
            "seam": {{"type": "group_expression", "inputs": ["t"], "params": {{"group": "seam", "class": "point",
                "expression": "(abs(z) < 0.001 && x > 0) || (abs(y) < 0.001 && x * x + z * z > 1.1)"}}}},
            "f": {{"type": "uv_flatten", "inputs": ["seam"], "params": {{"seams": "seam"{method}}}}}"#
        )
    };
    let spectral = area_spread(&geo(&nodes(""), "f"));
    assert!(spectral < 7.0, "spectral spread {spectral}");
    let pinned = geo(&nodes(r#", "method": "two_pins""#), "f");
    let uv = uv(&pinned);
    assert!(uv
        .iter()
        .all(|u| u.x >= 0.0 && u.y >= 0.0 && u.x <= 1.0 && u.y <= 1.0));
    assert!(
        area_spread(&pinned) > 100.0 * spectral,
        "two pins did not curl: the test no longer shows the difference"
    );
}
