//! Wall thickness of a closed mesh at each point: the distance to the
//! opposite wall along the inverted point normal (the ray test of 3D-print
//! checkers such as Blender's 3D-Print toolbox), through a triangle BVH;
//! the wall is the first triangle the ray leaves the solid through.

use glam::Vec3;
use rayon::prelude::*;

use super::normals::point_normals;
use super::raycast::TriangleBvh;
use super::triangulate::triangulate_polygon;
use crate::geometry::{Geometry, PrimKind};

/// The value of a point whose inward ray leaves the mesh (an open surface).
pub const NO_OPPOSITE_WALL: f32 = -1.0;

/// Points measured between cancellation checks.
const CHUNK: usize = 4096;

/// The cast was cancelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cancelled;

/// Every polygon's triangles as point triples, and the triangles each point touches.
fn triangles_with_incidence(g: &Geometry) -> (Vec<[u32; 3]>, Vec<u32>, Vec<u32>) {
    let mut tris = Vec::new();
    let mut local = Vec::new();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != PrimKind::Polygon {
            continue;
        }
        let pts = g.prim_points(prim);
        local.clear();
        triangulate_polygon(g.positions(), pts, &mut local);
        tris.extend(local.iter().map(|t| t.map(|c| pts[c as usize])));
    }
    // Compressed incidence lists, point -> triangles, in triangle order.
    let mut offsets = vec![0u32; g.num_points() + 1];
    for t in &tris {
        for &p in t {
            offsets[p as usize + 1] += 1;
        }
    }
    for i in 0..g.num_points() {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut items = vec![0u32; offsets[g.num_points()] as usize];
    for (i, t) in tris.iter().enumerate() {
        for &p in t {
            items[fill[p as usize] as usize] = i as u32;
            fill[p as usize] += 1;
        }
    }
    (tris, offsets, items)
}

/// Each point's wall thickness (see the module doc), or
/// [`NO_OPPOSITE_WALL`]; polygons only (other primitives are not walls).
pub fn wall_thickness(
    g: &Geometry,
    cancelled: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<f32>, Cancelled> {
    let (tris, offsets, items) = triangles_with_incidence(g);
    let bvh = TriangleBvh::new(g.positions(), &tris);
    let normals = point_normals(g);
    let extent = super::bounds(g).map_or(1.0, |b| (b.max - b.min).length().max(f32::MIN_POSITIVE));
    // Past rounding at the origin, well below any wall a printer resolves.
    let t_min = extent * 1e-6;
    let positions = g.positions();
    let mut out = vec![NO_OPPOSITE_WALL; g.num_points()];
    for (chunk_index, chunk) in out.chunks_mut(CHUNK).enumerate() {
        if cancelled() {
            return Err(Cancelled);
        }
        chunk.par_iter_mut().enumerate().for_each(|(i, slot)| {
            let p = chunk_index * CHUNK + i;
            let n = normals[p];
            if n == Vec3::ZERO {
                return;
            }
            let own = &items[offsets[p] as usize..offsets[p + 1] as usize];
            // The opposite wall is where the ray leaves the solid: a
            // triangle facing along it. One facing against it is met
            // entering, which from a point on the surface means a
            // neighbour at a sharp edge (the point's normal averages
            // faces meeting at an angle), not a wall.
            let entering = |t: u32| {
                let [a, b, c] = tris[t as usize].map(|i| positions[i as usize]);
                (b - a).cross(c - a).dot(-n) <= 0.0
            };
            let hit = bvh.first_hit(positions[p], -n, t_min, f32::INFINITY, |t| {
                own.contains(&t) || entering(t)
            });
            if let Some(hit) = hit {
                *slot = hit.t;
            }
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::box_mesh;

    /// A slab 0.2 thick: points inside its faces read 0.2 (top and bottom)
    /// or its width (sides); corners, whose normals are diagonal, more.
    #[test]
    fn a_slab_reads_its_thickness() {
        let size = Vec3::new(2.0, 1.6, 0.2);
        let g = box_mesh(size, [10, 8, 1]);
        let t = wall_thickness(&g, &|| false).unwrap();
        let mut interior = 0;
        for (p, v) in g.positions().iter().zip(&t) {
            let on_top_or_bottom = p.x.abs() < 0.99 && p.y.abs() < 0.79;
            if on_top_or_bottom {
                assert!((v - 0.2).abs() < 1e-5, "{p}: {v}");
                interior += 1;
            } else {
                assert!(*v >= 0.2 - 1e-5, "{p}: {v}");
            }
        }
        assert_eq!(interior, 2 * 9 * 7);
    }

    /// A point on a sharp edge, its normal halfway between the faces, with
    /// a sliver of the neighbouring face just ahead of its ray (as a dual
    /// contouring mesh has at sharp edges): the sliver is entered, not
    /// left, so the wall is the slab's far side.
    #[test]
    fn faces_met_entering_are_not_walls() {
        let size = Vec3::new(2.0, 2.0, 0.2);
        let mut g = box_mesh(size, [1, 1, 1]);
        // A tiny triangle facing outward (+z) just below the top face near
        // the edge x = 1, where the corner (1, 1, 0.1) casts inward along
        // -(1, 1, 1)/sqrt(3).
        let at = Vec3::new(0.999, 0.999, 0.099);
        let base = g.num_points() as u32;
        g.add_points(&[
            at - Vec3::X * 0.01,
            at + Vec3::new(0.005, -0.01, 0.0),
            at + Vec3::Y * 0.01,
        ]);
        g.add_polygon(&[base, base + 1, base + 2]).unwrap();
        let t = wall_thickness(&g, &|| false).unwrap();
        let corner = g
            .positions()
            .iter()
            .position(|p| (*p - Vec3::new(1.0, 1.0, 0.1)).length() < 1e-6)
            .unwrap();
        assert!(t[corner] > 0.1, "{}", t[corner]);
    }

    #[test]
    fn an_open_surface_has_no_opposite_wall() {
        let mut g = Geometry::new();
        g.add_points(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
        g.add_polygon(&[0, 1, 2]).unwrap();
        assert_eq!(
            wall_thickness(&g, &|| false).unwrap(),
            vec![NO_OPPOSITE_WALL; 3]
        );
        assert_eq!(wall_thickness(&g, &|| true), Err(Cancelled));
    }
}
