//! Triangulation: convex polygons by fans, concave ones by ear clipping.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::normals::polygon_normal;
use crate::geometry::{Geometry, PrimKind};
use crate::group::Group;

fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}

/// Triangles of one polygon as corner indices `0..n` into `pts`, appended to
/// `out`. Convex polygons get a fan; others are ear clipped in the plane of
/// their Newell normal.
pub fn triangulate_polygon(p: &[Vec3], pts: &[u32], out: &mut Vec<[u32; 3]>) {
    let n = pts.len();
    if n < 3 {
        return;
    }
    if n == 3 {
        out.push([0, 1, 2]);
        return;
    }
    let normal = polygon_normal(p, pts);
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let q: Vec<Vec2> = pts
        .iter()
        .map(|&i| {
            let x = p[i as usize];
            Vec2::new(x.dot(u), x.dot(v))
        })
        .collect();
    let convex = (0..n).all(|i| {
        let a = q[(i + n - 1) % n];
        let b = q[i];
        let c = q[(i + 1) % n];
        cross2(b - a, c - b) >= 0.0
    });
    if convex || normal == Vec3::ZERO {
        for k in 1..n as u32 - 1 {
            out.push([0, k, k + 1]);
        }
        return;
    }
    ear_clip(&q, out);
}

fn ear_clip(q: &[Vec2], out: &mut Vec<[u32; 3]>) {
    let mut idx: Vec<u32> = (0..q.len() as u32).collect();
    let inside = |p: Vec2, a: Vec2, b: Vec2, c: Vec2| {
        cross2(b - a, p - a) >= 0.0 && cross2(c - b, p - b) >= 0.0 && cross2(a - c, p - c) >= 0.0
    };
    let mut guard = 0;
    let mut i = 0;
    while idx.len() > 3 {
        let m = idx.len();
        let (ia, ib, ic) = (idx[(i + m - 1) % m], idx[i % m], idx[(i + 1) % m]);
        let (a, b, c) = (q[ia as usize], q[ib as usize], q[ic as usize]);
        let is_convex = cross2(b - a, c - b) > 0.0;
        let is_ear = is_convex
            && idx.iter().all(|&j| {
                j == ia
                    || j == ib
                    || j == ic
                    || q[j as usize] == a
                    || q[j as usize] == b
                    || q[j as usize] == c
                    || !inside(q[j as usize], a, b, c)
            });
        // After a full pass without an ear the polygon is degenerate
        // (self-intersecting or collinear): clip anyway so we terminate.
        if is_ear || guard > m {
            out.push([ia, ib, ic]);
            idx.remove(i % m);
            guard = 0;
            i %= idx.len();
        } else {
            i = (i + 1) % m;
            guard += 1;
        }
    }
    out.push([idx[0], idx[1], idx[2]]);
}

/// Splits polygons of more than three vertices (all, or those in `group`) into
/// triangles that reuse the polygon's vertices, so vertex, primitive and point
/// attributes and groups carry over. Other primitives are kept as they are.
pub fn triangulate(g: &Geometry, group: Option<&Group>) -> Geometry {
    triangulate_with(g, group, &|| false).expect("never cancelled")
}

/// [`triangulate`], polling `cancel` per chunk of primitives and between
/// columns: `None` when cancelled.
pub fn triangulate_with(
    g: &Geometry,
    group: Option<&Group>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Geometry> {
    const CHUNK: usize = 1 << 14;
    let p = g.positions();
    let nprims = g.num_prims();
    // Each chunk yields its vertex list and, per new primitive, (source
    // primitive, vertex count).
    type Piece = (Vec<u32>, Vec<(u32, u32)>);
    let pieces: Option<Vec<Piece>> = (0..nprims.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            if cancel() {
                return None;
            }
            let mut verts = Vec::new();
            let mut prims = Vec::new();
            let mut tris = Vec::new();
            for prim in c * CHUNK..((c + 1) * CHUNK).min(nprims) {
                let r = g.prim_vertex_range(prim);
                let selected = group.is_none_or(|grp| grp.contains(prim));
                if g.prim_kind(prim) == PrimKind::Polygon && r.len() > 3 && selected {
                    tris.clear();
                    triangulate_polygon(p, g.prim_points(prim), &mut tris);
                    for t in &tris {
                        verts.extend(t.iter().map(|&k| r.start as u32 + k));
                        prims.push((prim as u32, 3));
                    }
                } else {
                    verts.extend(r.clone().map(|v| v as u32));
                    prims.push((prim as u32, r.len() as u32));
                }
            }
            Some((verts, prims))
        })
        .collect();
    let pieces = pieces?;
    let vertex_src: Vec<u32> = pieces.iter().flat_map(|(v, _)| v.iter().copied()).collect();
    let prim_src: Vec<u32> = pieces
        .iter()
        .flat_map(|(_, p)| p.iter().map(|x| x.0))
        .collect();
    let mut out = g.clone();
    let mut acc = 0u32;
    out.prim_offsets = std::iter::once(0)
        .chain(pieces.iter().flat_map(|(_, p)| p.iter()).map(|&(_, n)| {
            acc += n;
            acc
        }))
        .collect();
    out.vertex_point = vertex_src
        .iter()
        .map(|&v| g.vertex_point[v as usize])
        .collect();
    if cancel() {
        return None;
    }
    out.vertices = g.vertices.gather(&vertex_src);
    if cancel() {
        return None;
    }
    out.prims = g.prims.gather(&prim_src);
    out.prim_kinds = prim_src.iter().map(|&s| g.prim_kinds[s as usize]).collect();
    for grp in out.prim_groups.values_mut() {
        *grp = grp.gather(&prim_src);
    }
    out.invalidate_topology();
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::{signed_volume, surface_area};
    use crate::primitives::{cube, tube};

    fn area2(p: &[Vec3], pts: &[u32], tris: &[[u32; 3]]) -> f32 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| p[pts[k as usize] as usize]);
                (b - a).cross(c - a).length() * 0.5
            })
            .sum()
    }

    #[test]
    fn concave_polygon_by_ear_clipping() {
        // An L shape of area 3 (concave at one corner).
        let p = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let pts: Vec<u32> = (0..6).collect();
        let mut tris = Vec::new();
        triangulate_polygon(&p, &pts, &mut tris);
        assert_eq!(tris.len(), 4);
        assert!((area2(&p, &pts, &tris) - 3.0).abs() < 1e-6);
        // Every triangle keeps the polygon's orientation.
        for t in &tris {
            let [a, b, c] = t.map(|k| p[k as usize]);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }

    #[test]
    fn star_polygon_area_is_kept() {
        let n = 10;
        let p: Vec<Vec3> = (0..n)
            .map(|i| {
                let a = std::f32::consts::TAU * i as f32 / n as f32;
                let r = if i % 2 == 0 { 2.0 } else { 0.7 };
                Vec3::new(r * a.cos(), 0.0, -r * a.sin())
            })
            .collect();
        let pts: Vec<u32> = (0..n as u32).collect();
        let mut tris = Vec::new();
        triangulate_polygon(&p, &pts, &mut tris);
        assert_eq!(tris.len(), n - 2);
        let expect = 0.5 * n as f32 * 2.0 * 0.7 * (std::f32::consts::TAU / n as f32).sin();
        assert!((area2(&p, &pts, &tris) - expect).abs() < 1e-4);
    }

    #[test]
    fn mesh_triangulation_keeps_shape_and_attributes() {
        let g = tube(1.0, 2.0, 16, 3, true);
        let t = triangulate(&g, None);
        assert!(t.prim_offsets().windows(2).all(|w| w[1] - w[0] == 3));
        assert!((signed_volume(&t) - signed_volume(&g)).abs() < 1e-5);
        assert!((surface_area(&t) - surface_area(&g)).abs() < 1e-4);
        assert!(t.topology().manifold_report(&t).is_closed_manifold());
        let c = cube(1.0);
        let only = triangulate(&c, Some(&Group::from_members(6, [0])));
        assert_eq!(only.num_prims(), 7);
    }
}
