//! The three examples cook to what they show: colour carried from
//! a scan onto its remeshed copy, shattered pieces moved by their volumes,
//! a torus unwrapped into one island of the unit square.

use std::sync::Arc;

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Geometry};
use geode_graph::{load_str, Cache, CookOptions, Engine};

fn cook(example: &str, node: &str) -> Arc<Geometry> {
    let path = format!("{}/../../examples/{example}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let net = load_str(&text, &geode_nodes::registry()).unwrap_or_else(|e| panic!("{e:?}"));
    let cache = Cache::new(1 << 30);
    let r = Engine::new(net, &cache)
        .cook(node, &CookOptions::at_frame(1.0))
        .unwrap_or_else(|e| panic!("{e:?}"));
    Arc::clone(r.value.as_geometry().unwrap())
}

fn colours(g: &Geometry) -> Vec<Vec3> {
    match g.attrib(AttribClass::Point, "Cd").map(|a| a.data()) {
        Some(AttribData::Vec3(v)) => v.clone(),
        other => panic!("no point Cd: {other:?}"),
    }
}

/// How far each point's colour is from the scan's nearest point's: mean
/// and worst (largest channel difference).
fn distance_to_scan(scan: &Geometry, out: &Geometry) -> (f32, f32) {
    let (sc, oc) = (colours(scan), colours(out));
    let (mut worst, mut total) = (0.0f32, 0.0f32);
    for (q, c) in out.positions().iter().zip(&oc) {
        let nearest = scan
            .positions()
            .iter()
            .enumerate()
            .min_by(|a, b| {
                a.1.distance_squared(*q)
                    .total_cmp(&b.1.distance_squared(*q))
            })
            .map(|(i, _)| i)
            .unwrap();
        let d = (*c - sc[nearest]).abs().max_element();
        worst = worst.max(d);
        total += d;
    }
    (total / oc.len() as f32, worst)
}

/// The mean difference of colour across the edges of the mesh.
fn roughness(g: &Geometry) -> f32 {
    let c = colours(g);
    let topo = g.topology();
    let edges = topo.edges();
    edges
        .iter()
        .map(|[a, b]| (c[*a as usize] - c[*b as usize]).length())
        .sum::<f32>()
        / edges.len() as f32
}

#[test]
fn the_scan_s_colour_reaches_the_remeshed_copy() {
    let scan = cook("attribute_transfer.json", "/scan_colour");
    let moved = cook("attribute_transfer.json", "/transferred");
    let out = cook("attribute_transfer.json", "/blurred");
    assert!(out.num_points() < scan.num_points() / 2, "a coarser copy");
    // Every point took the colour of the scan around it.
    let (mean, worst) = distance_to_scan(&scan, &moved);
    assert!(mean < 0.05, "mean difference {mean}");
    assert!(worst < 0.5, "worst difference {worst}");
    let oc = colours(&out);
    let spread = oc.iter().map(|c| c.x).fold(0.0f32, f32::max)
        - oc.iter().map(|c| c.x).fold(1.0f32, f32::min);
    assert!(spread > 0.3, "the colour varies over the surface: {spread}");
    // The blur smooths it: neighbours differ less.
    assert!(
        roughness(&out) < 0.8 * roughness(&moved),
        "{} against {}",
        roughness(&out),
        roughness(&moved)
    );
}

#[test]
fn shattered_pieces_move_by_their_volume() {
    let out = cook("shatter_for_each.json", "/moved");
    let vols: Vec<f32> = match out
        .attrib(AttribClass::Point, "piece_volume")
        .map(|a| a.data())
    {
        Some(AttribData::Float(v)) => v.clone(),
        other => panic!("{other:?}"),
    };
    let pieces: Vec<i32> = out
        .attrib(AttribClass::Point, "piece")
        .unwrap()
        .as_i32()
        .unwrap()
        .to_vec();
    let count = *pieces.iter().max().unwrap() + 1;
    assert_eq!(count, 7, "three slabs cut the ball into seven pieces");
    let mut per_piece = vec![0.0f32; count as usize];
    for (k, v) in pieces.iter().zip(&vols) {
        per_piece[*k as usize] = *v;
    }
    let total: f32 = per_piece.iter().sum();
    let ball = 4.0 / 3.0 * std::f32::consts::PI;
    assert!(
        (total / ball - 1.0).abs() < 0.01,
        "the pieces' volumes add up to the ball's: {total}"
    );
    // Pieces moved apart: the result is wider than the ball along x.
    let xs = out.positions().iter().map(|p| p.x);
    let width = xs.clone().fold(f32::MIN, f32::max) - xs.fold(f32::MAX, f32::min);
    assert!(width > 2.2, "{width}");
}

#[test]
fn the_can_unwraps_into_three_undistorted_islands() {
    let out = cook("uv_flatten.json", "/checker");
    let uv = match out.attrib(AttribClass::Vertex, "uv").map(|a| a.data()) {
        Some(AttribData::Vec3(v)) => v.clone(),
        other => panic!("{other:?}"),
    };
    assert!(uv
        .iter()
        .all(|u| (0.0..=1.0).contains(&u.x) && (0.0..=1.0).contains(&u.y)));
    let islands = out
        .attrib(AttribClass::Primitive, "island")
        .unwrap()
        .as_i32()
        .unwrap();
    let mut distinct: Vec<i32> = islands.to_vec();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct, [0, 1, 2], "the side and the two caps");
    // The side is developable and the caps flat: every corner keeps its
    // angle, and no face is flipped.
    let p = out.positions();
    let vp = out.vertex_points();
    let mut worst = 0.0f32;
    for prim in 0..out.num_prims() {
        let r = out.prim_vertex_range(prim);
        let n = r.len();
        let mut area = 0.0f32;
        for k in 0..n {
            let (a, b, c) = (
                r.start + (k + n - 1) % n,
                r.start + k,
                r.start + (k + 1) % n,
            );
            let three = (p[vp[a] as usize] - p[vp[b] as usize])
                .angle_between(p[vp[c] as usize] - p[vp[b] as usize]);
            let (ua, ub, uc) = (uv[a].truncate(), uv[b].truncate(), uv[c].truncate());
            worst = worst.max((three - (ua - ub).angle_to(uc - ub).abs()).abs());
            area += uv[b].x * uv[c].y - uv[c].x * uv[b].y;
        }
        assert!(area.abs() > 0.0, "face {prim} collapsed");
    }
    assert!(worst < 1e-3, "angle distortion {worst}");
    assert!(
        out.attrib(AttribClass::Vertex, "Cd").is_some(),
        "checker colours"
    );
}
