//! Mesh simplification by vertex clustering (Rossignac & Borrel 1993):
//! points snap to the cells of a grid over the bounds, each occupied cell
//! becomes one point at the mean of its points, and triangles whose corners
//! fall in fewer than three cells vanish, as do repeats. Linear time, no
//! topology needed, and the shape holds to a cell's size: what a viewport
//! needs to draw a mesh too large for it. The grid is sized so that the
//! result has at most the asked number of triangles (a closed surface has
//! about two triangles per point, which gives the first guess).

use std::collections::HashMap;

use glam::Vec3;

use crate::{AttribClass, AttribData, Geometry, PrimKind};

use super::bounds::Aabb;

/// Fan triangles (point indices) of every polygon, as the viewport draws them.
fn fan_triangles(g: &Geometry) -> Vec<[u32; 3]> {
    let vp = g.vertex_points();
    let offsets = g.prim_offsets();
    let mut tris = Vec::new();
    for (prim, kind) in g.prim_kinds().iter().enumerate() {
        if *kind != PrimKind::Polygon {
            continue;
        }
        let (a, b) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        for k in a + 1..b.saturating_sub(1) {
            tris.push([vp[a], vp[k], vp[k + 1]]);
        }
    }
    tris
}

/// The number of fan triangles of `g`'s polygons, without building them.
pub fn fan_triangle_count(g: &Geometry) -> usize {
    let offsets = g.prim_offsets();
    g.prim_kinds()
        .iter()
        .enumerate()
        .filter(|(_, k)| **k == PrimKind::Polygon)
        .map(|(p, _)| ((offsets[p + 1] - offsets[p]) as usize).saturating_sub(2))
        .sum()
}

/// A grid over a box: `cells` along its longest side, cubic cells.
struct Grid {
    min: Vec3,
    inv_cell: f32,
    dims: [u64; 3],
}

impl Grid {
    fn new(b: &Aabb, cells: u64) -> Grid {
        let size = b.size();
        let longest = size.max_element().max(f32::MIN_POSITIVE);
        let inv_cell = cells as f32 / longest;
        let dim = |s: f32| ((s * inv_cell).floor() as u64 + 1).max(1);
        Grid {
            min: b.min,
            inv_cell,
            dims: [dim(size.x), dim(size.y), dim(size.z)],
        }
    }

    fn key(&self, p: Vec3) -> u64 {
        let c = ((p - self.min) * self.inv_cell).floor();
        let at = |v: f32, d: u64| (v.max(0.0) as u64).min(d - 1);
        let (x, y, z) = (
            at(c.x, self.dims[0]),
            at(c.y, self.dims[1]),
            at(c.z, self.dims[2]),
        );
        x + self.dims[0] * (y + self.dims[1] * z)
    }
}

/// Each used point's cluster, clusters numbered in order of first use.
fn clusters(g: &Geometry, used: &[bool], grid: &Grid) -> (Vec<u32>, usize) {
    let mut index: HashMap<u64, u32> = HashMap::new();
    let mut of_point = vec![u32::MAX; g.num_points()];
    for (i, p) in g.positions().iter().enumerate() {
        if used[i] {
            let next = index.len() as u32;
            of_point[i] = *index.entry(grid.key(*p)).or_insert(next);
        }
    }
    (of_point, index.len())
}

/// Triangles over clusters: degenerate ones dropped, each kept once (its
/// corners rotated to start at the smallest, so orientation is kept).
fn clustered_triangles(tris: &[[u32; 3]], of_point: &[u32]) -> Vec<[u32; 3]> {
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::new();
    for t in tris {
        let c = t.map(|p| of_point[p as usize]);
        if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
            continue;
        }
        let first = (0..3).min_by_key(|&k| c[k]).unwrap_or(0);
        let r = [c[first], c[(first + 1) % 3], c[(first + 2) % 3]];
        if seen.insert(r) {
            out.push(r);
        }
    }
    out
}

/// Mean of a point vec3 attribute per cluster (`N` renormalised).
fn cluster_means(values: &[Vec3], of_point: &[u32], n: usize, unit: bool) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; n];
    let mut count = vec![0u32; n];
    for (v, &c) in values.iter().zip(of_point) {
        if c != u32::MAX {
            sum[c as usize] += *v;
            count[c as usize] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &k)| {
            let m = *s / k.max(1) as f32;
            if unit {
                m.normalize_or_zero()
            } else {
                m
            }
        })
        .collect()
}

/// `g`'s polygons as a triangle mesh of at most `max_triangles` triangles
/// (vertex clustering on the coarsest grid needed), with the point `Cd`
/// and `N`, where present, averaged per cluster. Other primitives and
/// attributes are left out.
pub fn cluster_triangles(g: &Geometry, max_triangles: usize) -> Geometry {
    let tris = fan_triangles(g);
    let mut used = vec![false; g.num_points()];
    for t in &tris {
        for &p in t {
            used[p as usize] = true;
        }
    }
    let mut bounds = Aabb::empty();
    for (p, u) in g.positions().iter().zip(&used) {
        if *u {
            bounds.include(*p);
        }
    }
    if tris.len() <= max_triangles || bounds.is_empty() {
        return clustered_geometry(g, &tris, &identity(g, &used), g.num_points());
    }
    // About two triangles per occupied cell on a surface: aim there, then
    // shrink the grid until the result fits.
    let mut cells = ((max_triangles as f64 / 2.0).sqrt() as u64).max(2);
    loop {
        let grid = Grid::new(&bounds, cells);
        let (of_point, n) = clusters(g, &used, &grid);
        let out = clustered_triangles(&tris, &of_point);
        if out.len() <= max_triangles || cells <= 2 {
            return clustered_geometry(g, &out, &of_point, n);
        }
        let shrink = (max_triangles as f64 / out.len() as f64).sqrt() * 0.97;
        cells = ((cells as f64 * shrink) as u64).clamp(2, cells - 1);
    }
}

/// Each used point its own cluster (nothing to reduce).
fn identity(g: &Geometry, used: &[bool]) -> Vec<u32> {
    (0..g.num_points() as u32)
        .map(|i| if used[i as usize] { i } else { u32::MAX })
        .collect()
}

fn clustered_geometry(g: &Geometry, tris: &[[u32; 3]], of_point: &[u32], n: usize) -> Geometry {
    let positions = cluster_means(g.positions(), of_point, n, false);
    let mut out = Geometry::from_triangles(positions, tris)
        .expect("cluster indices are in range by construction");
    for (name, unit) in [("Cd", false), ("N", true)] {
        let Some(a) = g.attrib(AttribClass::Point, name) else {
            continue;
        };
        let AttribData::Vec3(values) = a.data() else {
            continue;
        };
        let means = cluster_means(values, of_point, n, unit);
        // Lengths match by construction: one value per cluster point.
        let _ = out.set_attrib(
            AttribClass::Point,
            name,
            a.with_data(AttribData::Vec3(means)),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere of `rows` x `columns` quads.
    fn sphere(rows: u32, columns: u32) -> Geometry {
        let mut pts = Vec::new();
        for r in 0..=rows {
            let theta = std::f32::consts::PI * r as f32 / rows as f32;
            for c in 0..columns {
                let phi = std::f32::consts::TAU * c as f32 / columns as f32;
                pts.push(Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ));
            }
        }
        let mut idx = Vec::new();
        let mut counts = Vec::new();
        for r in 0..rows {
            for c in 0..columns {
                let at = |r: u32, c: u32| r * columns + c % columns;
                idx.extend_from_slice(&[at(r, c), at(r + 1, c), at(r + 1, c + 1), at(r, c + 1)]);
                counts.push(4);
            }
        }
        Geometry::from_polygons(pts, idx, &counts).unwrap()
    }

    #[test]
    fn a_large_sphere_reduces_under_the_budget_and_keeps_its_shape() {
        let g = sphere(400, 800);
        assert_eq!(fan_triangle_count(&g), 640_000);
        let r = cluster_triangles(&g, 20_000);
        let n = fan_triangle_count(&r);
        assert!((8_000..=20_000).contains(&n), "{n} triangles");
        // Every clustered point lies near the unit sphere (within a cell).
        let cell = 2.0 / (10_000f32).sqrt();
        for p in r.positions() {
            assert!((p.length() - 1.0).abs() < cell, "{p}");
        }
        // The bounds survive to a cell.
        let b = crate::ops::bounds(&r).unwrap();
        assert!((b.max.y - 1.0).abs() < cell && (b.min.y + 1.0).abs() < cell);
    }

    #[test]
    fn within_the_budget_nothing_changes_and_the_result_is_deterministic() {
        let g = sphere(10, 20);
        let r = cluster_triangles(&g, 1_000_000);
        assert_eq!(fan_triangle_count(&r), fan_triangle_count(&g));
        let a = cluster_triangles(&sphere(200, 300), 5_000);
        let b = cluster_triangles(&sphere(200, 300), 5_000);
        assert_eq!(a.positions(), b.positions());
        assert_eq!(a.vertex_points(), b.vertex_points());
    }
}
