//! Measures of elements and surfaces (Houdini's Measure): area, perimeter
//! and enclosed volume per primitive (summed per piece or in total by the
//! caller), and the discrete mean and Gaussian curvature at each point by
//! Meyer, Desbrun, Schröder and Barr's operators ("Discrete
//! Differential-Geometry Operators for Triangulated 2-Manifolds", 2003):
//! the cotangent Laplacian of position over the mixed Voronoi area for the
//! mean curvature (its sign from the area-weighted normal: positive where
//! the surface bends away from its normal, 1/r on a sphere), the angle
//! defect over the same area for the Gaussian curvature.

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{Geometry, PrimKind};
use rayon::prelude::*;

use crate::error::unless_cancelled;
use crate::relation::polygon_area;
use crate::AttribError;

/// Each primitive's area (polygons; zero for the rest).
pub fn prim_areas(g: &Geometry) -> Vec<f32> {
    let p = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .map(|i| match g.prim_kind(i) {
            PrimKind::Polygon => polygon_area(p, g.prim_points(i)),
            _ => 0.0,
        })
        .collect()
}

/// Each primitive's perimeter: a polygon's closed loop, a polyline's length.
pub fn prim_perimeters(g: &Geometry) -> Vec<f32> {
    let p = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .map(|i| {
            let pts = g.prim_points(i);
            let closed = g.prim_kind(i) == PrimKind::Polygon;
            let open: f32 = pts
                .windows(2)
                .map(|w| p[w[0] as usize].distance(p[w[1] as usize]))
                .sum();
            match (closed, pts.first(), pts.last()) {
                (true, Some(&a), Some(&b)) if pts.len() > 2 => {
                    open + p[a as usize].distance(p[b as usize])
                }
                _ => open,
            }
        })
        .collect()
}

/// Each polygon's share of the volume its closed surface encloses: the
/// signed volume of the cone from the origin over it (fan triangles), so
/// the shares of a closed, outward-facing piece sum to its volume.
pub fn prim_volumes(g: &Geometry) -> Vec<f64> {
    let p = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .map(|i| {
            if g.prim_kind(i) != PrimKind::Polygon {
                return 0.0;
            }
            let pts = g.prim_points(i);
            let a = p[pts[0] as usize].as_dvec3();
            (1..pts.len().saturating_sub(1))
                .map(|k| {
                    let (b, c) = (
                        p[pts[k] as usize].as_dvec3(),
                        p[pts[k + 1] as usize].as_dvec3(),
                    );
                    a.dot(b.cross(c)) / 6.0
                })
                .sum()
        })
        .collect()
}

/// Per-piece sums of per-primitive values, written back on every primitive
/// of the piece.
pub fn per_piece(values: &[f64], piece_of_prim: &[u32]) -> Vec<f64> {
    let pieces = piece_of_prim
        .iter()
        .map(|&k| k as usize + 1)
        .max()
        .unwrap_or(0);
    let mut sums = vec![0.0f64; pieces];
    for (v, &k) in values.iter().zip(piece_of_prim) {
        sums[k as usize] += v;
    }
    piece_of_prim.iter().map(|&k| sums[k as usize]).collect()
}

/// Mean and Gaussian curvature at every point of the polygons (points on
/// no polygon get zero).
pub struct Curvature {
    pub mean: Vec<f32>,
    pub gaussian: Vec<f32>,
}

/// Points per cancellation poll.
const CHUNK: usize = 1 << 14;

/// The curvatures of `g`'s surface: each triangle's share at its corners
/// in parallel, then each point's sums over its corners (a point's
/// corners found by a counting sort), in parallel chunks, cancellable
/// between chunks.
pub fn curvature(
    g: &Geometry,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Curvature, AttribError> {
    let p = g.positions();
    let n = g.num_points();
    let tris = triangles(g, cancel)?;
    let parts: Vec<[Corner; 3]> = in_chunks(&tris, cancel, |t| corner_parts(p, t))?;
    let corners = corners_of_points(n, &tris, cancel)?;
    let points: Vec<u32> = (0..n as u32).collect();
    let values = in_chunks(&points, cancel, |&i| {
        let mine = &corners.entries
            [corners.offsets[i as usize] as usize..corners.offsets[i as usize + 1] as usize];
        point_curvature(&tris, &parts, mine)
    })?;
    Ok(Curvature {
        mean: values.iter().map(|v| v.0).collect(),
        gaussian: values.iter().map(|v| v.1).collect(),
    })
}

/// A triangle's share at a corner: mixed area, angle, cotangent Laplacian
/// part, area-weighted normal.
type Corner = (f64, f64, DVec3, DVec3);

/// `f` over `items` in parallel chunks, in order, polling `cancel` per chunk.
fn in_chunks<T: Sync, R: Send>(
    items: &[T],
    cancel: &(dyn Fn() -> bool + Sync),
    f: impl Fn(&T) -> R + Sync,
) -> Result<Vec<R>, AttribError> {
    let chunks: Vec<Result<Vec<R>, AttribError>> = items
        .par_chunks(CHUNK)
        .map(|c| {
            unless_cancelled(cancel)?;
            Ok(c.iter().map(&f).collect())
        })
        .collect();
    let mut out = Vec::with_capacity(items.len());
    for c in chunks {
        out.extend(c?);
    }
    Ok(out)
}

/// Each point's corners, as `triangle * 3 + corner`, in triangle order.
fn corners_of_points(
    n: usize,
    tris: &[[u32; 3]],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<crate::relation::Rows, AttribError> {
    let mut offsets = vec![0u32; n + 1];
    for (k, t) in tris.iter().enumerate() {
        if k % (CHUNK * 16) == 0 {
            unless_cancelled(cancel)?;
        }
        for &c in t {
            offsets[c as usize + 1] += 1;
        }
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut entries = vec![0u32; offsets[n] as usize];
    for (k, t) in tris.iter().enumerate() {
        if k % (CHUNK * 16) == 0 {
            unless_cancelled(cancel)?;
        }
        for (j, &c) in t.iter().enumerate() {
            entries[fill[c as usize] as usize] = (k * 3 + j) as u32;
            fill[c as usize] += 1;
        }
    }
    Ok(crate::relation::Rows { offsets, entries })
}

/// One point's (mean, Gaussian) curvature from its corners. A point is on
/// the boundary when a neighbour across its triangles is met once, not
/// twice (its fan does not close): its angle defect is then from π.
fn point_curvature(tris: &[[u32; 3]], parts: &[[Corner; 3]], corners: &[u32]) -> (f32, f32) {
    let (mut area, mut angle, mut lap, mut normal) = (0.0f64, 0.0f64, DVec3::ZERO, DVec3::ZERO);
    let mut around: Vec<u32> = Vec::with_capacity(corners.len() * 2);
    for &c in corners {
        let (t, j) = (c as usize / 3, c as usize % 3);
        let (a, th, l, nn) = parts[t][j];
        area += a;
        angle += th;
        lap += l;
        normal += nn;
        around.push(tris[t][(j + 1) % 3]);
        around.push(tris[t][(j + 2) % 3]);
    }
    if area <= 0.0 {
        return (0.0, 0.0);
    }
    around.sort_unstable();
    let boundary = around.chunk_by(|a, b| a == b).any(|run| run.len() != 2);
    // Δx = -2 H n: the Laplacian points against the normal where the
    // surface is convex.
    let delta = lap / (2.0 * area);
    let h = -0.5 * delta.dot(normal.normalize_or_zero());
    let full = if boundary {
        std::f64::consts::PI
    } else {
        std::f64::consts::TAU
    };
    let k = (full - angle) / area;
    (h as f32, k as f32)
}

/// The polygons' triangles, polygons in parallel chunks (cancellable).
fn triangles(
    g: &Geometry,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<[u32; 3]>, AttribError> {
    let p = g.positions();
    let prims: Vec<usize> = (0..g.num_prims()).collect();
    let chunks: Vec<Result<Vec<[u32; 3]>, AttribError>> = prims
        .par_chunks(CHUNK)
        .map(|chunk| {
            unless_cancelled(cancel)?;
            let (mut out, mut local) = (Vec::new(), Vec::new());
            for &prim in chunk {
                if g.prim_kind(prim) != PrimKind::Polygon {
                    continue;
                }
                let pts = g.prim_points(prim);
                local.clear();
                geode_geo::ops::triangulate_polygon(p, pts, &mut local);
                out.extend(local.iter().map(|t| t.map(|k| pts[k as usize])));
            }
            Ok(out)
        })
        .collect();
    let mut out = Vec::new();
    for c in chunks {
        out.extend(c?);
    }
    Ok(out)
}

/// One triangle's share at each corner: its mixed Voronoi area, its angle,
/// its part of the cotangent Laplacian of position, and its area-weighted
/// normal.
fn corner_parts(p: &[Vec3], t: &[u32; 3]) -> [Corner; 3] {
    let x = t.map(|k| p[k as usize].as_dvec3());
    let cross = (x[1] - x[0]).cross(x[2] - x[0]);
    let area = 0.5 * cross.length();
    let mut out = [(0.0, 0.0, DVec3::ZERO, DVec3::ZERO); 3];
    if area <= 1e-300 {
        return out;
    }
    let angle_at = |k: usize| {
        let (a, b) = (x[(k + 1) % 3] - x[k], x[(k + 2) % 3] - x[k]);
        a.angle_between(b)
    };
    let angles = [angle_at(0), angle_at(1), angle_at(2)];
    let cot = |k: usize| 1.0 / angles[k].tan();
    let obtuse = angles.iter().position(|&a| a > std::f64::consts::FRAC_PI_2);
    for k in 0..3 {
        let (j, l) = ((k + 1) % 3, (k + 2) % 3);
        // Edge k-j is opposite corner l; edge k-l opposite corner j.
        let lap = cot(l) * (x[j] - x[k]) + cot(j) * (x[l] - x[k]);
        let mixed = match obtuse {
            None => {
                (cot(l) * x[k].distance_squared(x[j]) + cot(j) * x[k].distance_squared(x[l])) / 8.0
            }
            Some(o) if o == k => area / 2.0,
            Some(_) => area / 4.0,
        };
        out[k] = (mixed, angles[k], lap, cross * 0.5);
    }
    out
}
