//! Polygon, point and vertex normals (angle-weighted; vertex normals split at a cusp angle).

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::{Geometry, PrimKind};

/// Newell's normal of a polygon (unit length, zero when degenerate); robust
/// for non-planar and concave polygons.
pub fn polygon_normal(p: &[Vec3], pts: &[u32]) -> Vec3 {
    let mut n = Vec3::ZERO;
    let c = pts.len();
    for i in 0..c {
        let a = p[pts[i] as usize];
        let b = p[pts[(i + 1) % c] as usize];
        n += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n.normalize_or_zero()
}

/// One normal per primitive (zero for polylines and packed primitives).
pub fn prim_normals(g: &Geometry) -> Vec<Vec3> {
    let p = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .map(|prim| match g.prim_kind(prim) {
            PrimKind::Polygon => polygon_normal(p, g.prim_points(prim)),
            _ => Vec3::ZERO,
        })
        .collect()
}

/// The interior angle of every polygon corner (zero on other primitives).
fn corner_angles(g: &Geometry) -> Vec<f32> {
    let p = g.positions();
    let vp = g.vertex_points();
    let mut angles = vec![0.0f32; g.num_vertices()];
    let offsets = g.prim_offsets();
    // Split the vertex array at primitive boundaries so chunks are independent.
    let chunk_prims = 1 << 14;
    let mut rest: &mut [f32] = &mut angles;
    let mut jobs = Vec::new();
    let mut start_prim = 0;
    while start_prim < g.num_prims() {
        let end_prim = (start_prim + chunk_prims).min(g.num_prims());
        let len = (offsets[end_prim] - offsets[start_prim]) as usize;
        let (head, tail) = rest.split_at_mut(len);
        jobs.push((start_prim, end_prim, head));
        rest = tail;
        start_prim = end_prim;
    }
    jobs.into_par_iter().for_each(|(s, e, out)| {
        let base = offsets[s] as usize;
        for prim in s..e {
            if g.prim_kind(prim) != PrimKind::Polygon {
                continue;
            }
            let r = g.prim_vertex_range(prim);
            let n = r.len();
            for k in 0..n {
                let v = r.start + k;
                let here = p[vp[v] as usize];
                let prev = p[vp[r.start + (k + n - 1) % n] as usize] - here;
                let next = p[vp[r.start + (k + 1) % n] as usize] - here;
                out[v - base] = prev.cross(next).length().atan2(prev.dot(next));
            }
        }
    });
    angles
}

/// Vertex index ranges per point (counting sort; vertices in increasing order).
fn point_vertices(g: &Geometry) -> (Vec<u32>, Vec<u32>) {
    let np = g.num_points();
    let mut offsets = vec![0u32; np + 1];
    for &p in g.vertex_points() {
        offsets[p as usize + 1] += 1;
    }
    for i in 0..np {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut items = vec![0u32; g.num_vertices()];
    for (v, &p) in g.vertex_points().iter().enumerate() {
        items[fill[p as usize] as usize] = v as u32;
        fill[p as usize] += 1;
    }
    (offsets, items)
}

fn prim_of_vertex(g: &Geometry) -> Vec<u32> {
    let mut out = vec![0u32; g.num_vertices()];
    for prim in 0..g.num_prims() {
        for v in g.prim_vertex_range(prim) {
            out[v] = prim as u32;
        }
    }
    out
}

/// Angle-weighted point normals (Thürmer and Wüthrich): each polygon adds its
/// normal weighted by its corner angle at the point.
pub fn point_normals(g: &Geometry) -> Vec<Vec3> {
    let face_n = prim_normals(g);
    let angles = corner_angles(g);
    let (offsets, items) = point_vertices(g);
    let vprim = prim_of_vertex(g);
    (0..g.num_points())
        .into_par_iter()
        .map(|p| {
            let mut n = Vec3::ZERO;
            for &v in &items[offsets[p] as usize..offsets[p + 1] as usize] {
                n += face_n[vprim[v as usize] as usize] * angles[v as usize];
            }
            n.normalize_or_zero()
        })
        .collect()
}

/// Angle-weighted vertex normals that only average polygons whose normals are
/// within `cusp_degrees` of the vertex's own polygon, so hard edges stay hard.
pub fn vertex_normals(g: &Geometry, cusp_degrees: f32) -> Vec<Vec3> {
    let face_n = prim_normals(g);
    let angles = corner_angles(g);
    let (offsets, items) = point_vertices(g);
    let vprim = prim_of_vertex(g);
    let cos_cusp = cusp_degrees.to_radians().cos();
    let vp = g.vertex_points();
    (0..g.num_vertices())
        .into_par_iter()
        .map(|v| {
            let own = face_n[vprim[v] as usize];
            let p = vp[v] as usize;
            let mut n = Vec3::ZERO;
            for &w in &items[offsets[p] as usize..offsets[p + 1] as usize] {
                let other = face_n[vprim[w as usize] as usize];
                if w as usize == v || own.dot(other) >= cos_cusp {
                    n += other * angles[w as usize];
                }
            }
            let n = n.normalize_or_zero();
            if n == Vec3::ZERO {
                own
            } else {
                n
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::{cube, uv_sphere};

    #[test]
    fn cube_point_normals_are_diagonals_and_vertex_normals_split() {
        let g = cube(2.0);
        for (p, n) in g.positions().iter().zip(point_normals(&g)) {
            assert!((n - p.normalize()).length() < 1e-6, "{n} vs {p}");
        }
        let vn = vertex_normals(&g, 60.0);
        let fn_ = prim_normals(&g);
        for (prim, face_normal) in fn_.iter().enumerate() {
            for v in g.prim_vertex_range(prim) {
                assert!((vn[v] - *face_normal).length() < 1e-6);
            }
        }
        // Above 90 degrees the cube's corners are smooth again.
        let smooth = vertex_normals(&g, 91.0);
        let v0 = g.vertex_points()[0] as usize;
        assert!((smooth[0] - g.positions()[v0].normalize()).length() < 1e-6);
    }

    #[test]
    fn sphere_normals_are_radial() {
        let g = uv_sphere(3.0, 48, 24);
        for (p, n) in g.positions().iter().zip(point_normals(&g)) {
            assert!(n.angle_between(*p) < 0.01);
        }
    }
}
