//! The convex hull as the oriented box needs it: the exact hull's
//! triangles (`crate::hull`, quickhull with exact orientation tests) with
//! their unit normals, areas, vertices and edges.

use std::collections::BTreeMap;

use geode_geo::glam::{DVec3, Vec3};

use crate::hull::{span, Span};
use crate::ModelError;

/// A closed triangle hull: outward faces over the input's point indices.
pub struct Hull {
    /// The triangles (the oriented box reads their normals and areas; the
    /// tests check the hull through them).
    #[cfg_attr(not(test), allow(dead_code))]
    pub faces: Vec<[u32; 3]>,
    /// Unit outward normals.
    pub normals: Vec<DVec3>,
    /// Twice each face's area.
    pub double_areas: Vec<f64>,
    /// The hull's vertices (input point indices), ascending.
    pub vertices: Vec<u32>,
    /// Each undirected edge once: its two points and the faces beside it.
    pub edges: Vec<([u32; 2], [u32; 2])>,
}

/// Why there is no solid hull.
pub enum NoHull {
    /// All points on one line or at one point.
    Line,
    /// All points on one plane (its unit normal).
    Flat(DVec3),
    Cancelled,
}

/// The convex hull of `points`.
pub fn convex_hull(points: &[Vec3], cancel: &(dyn Fn() -> bool + Sync)) -> Result<Hull, NoHull> {
    let faces = match span(points, cancel) {
        Ok(Span::Solid(faces)) => faces,
        Ok(Span::Flat(n)) => return Err(NoHull::Flat(n.as_dvec3())),
        Ok(Span::Lower) => return Err(NoHull::Line),
        Err(ModelError::Cancelled) => return Err(NoHull::Cancelled),
        // The exact hull fails only on non-finite input, which has no box.
        Err(_) => return Err(NoHull::Line),
    };
    let at = |i: u32| points[i as usize].as_dvec3();
    let (mut normals, mut double_areas) = (
        Vec::with_capacity(faces.len()),
        Vec::with_capacity(faces.len()),
    );
    for f in &faces {
        let n = (at(f[1]) - at(f[0])).cross(at(f[2]) - at(f[0]));
        double_areas.push(n.length());
        normals.push(n.normalize_or_zero());
    }
    let mut vertices: Vec<u32> = faces.iter().flatten().copied().collect();
    vertices.sort_unstable();
    vertices.dedup();
    let mut beside: BTreeMap<[u32; 2], Vec<u32>> = BTreeMap::new();
    for (k, f) in faces.iter().enumerate() {
        for j in 0..3 {
            let (a, b) = (f[j], f[(j + 1) % 3]);
            beside
                .entry([a.min(b), a.max(b)])
                .or_default()
                .push(k as u32);
        }
    }
    let edges = beside
        .into_iter()
        .filter(|(_, fs)| fs.len() == 2)
        .map(|(e, fs)| (e, [fs[0], fs[1]]))
        .collect();
    Ok(Hull {
        faces,
        normals,
        double_areas,
        vertices,
        edges,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::random;

    fn never() -> bool {
        false
    }

    /// The points as the hull reads them (f32); the checks below use the
    /// same rounded points.
    fn f32s(p: &[DVec3]) -> Vec<Vec3> {
        p.iter().map(|q| q.as_vec3()).collect()
    }

    fn rounded(p: Vec<DVec3>) -> Vec<DVec3> {
        p.into_iter().map(|q| q.as_vec3().as_dvec3()).collect()
    }

    /// A convex hull: closed (V - E + F = 2 with every edge in two faces),
    /// every input point on or below every face plane, every vertex an
    /// input point that lies on its faces.
    fn check_hull(points: &[DVec3], h: &Hull) {
        let (v, e, f) = (h.vertices.len(), h.edges.len(), h.faces.len());
        assert_eq!(2 * e, 3 * f, "every edge in two faces");
        assert_eq!(v as i64 - e as i64 + f as i64, 2, "Euler characteristic");
        let extent = points
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        for (face, n) in h.faces.iter().zip(&h.normals) {
            let offset = n.dot(points[face[0] as usize]);
            for p in points {
                assert!(
                    n.dot(*p) - offset <= 1e-9 * extent,
                    "a point outside a face"
                );
            }
        }
    }

    #[test]
    fn a_cloud_points_on_a_sphere_and_a_divided_box() {
        let cloud: Vec<DVec3> = (0..3000u64)
            .map(|i| {
                DVec3::new(
                    random::unit_f64(1, i, 0),
                    random::unit_f64(1, i, 1),
                    random::unit_f64(1, i, 2),
                )
            })
            .collect();
        let cloud = rounded(cloud);
        let h = convex_hull(&f32s(&cloud), &never).ok().unwrap();
        check_hull(&cloud, &h);

        // Every point of a sphere is a vertex of its hull.
        let sphere: Vec<DVec3> = (0..2000u64)
            .map(|i| {
                let z = 2.0 * random::unit_f64(2, i, 0) - 1.0;
                let phi = std::f64::consts::TAU * random::unit_f64(2, i, 1);
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        let sphere = rounded(sphere);
        let h = convex_hull(&f32s(&sphere), &never).ok().unwrap();
        check_hull(&sphere, &h);
        assert_eq!(h.vertices.len(), sphere.len());

        // A box's grid of points: only the eight corners are vertices.
        let mut grid = Vec::new();
        for x in 0..5 {
            for y in 0..4 {
                for z in 0..3 {
                    grid.push(DVec3::new(
                        f64::from(x),
                        f64::from(y) * 0.5,
                        f64::from(z) * 0.25,
                    ));
                }
            }
        }
        let h = convex_hull(&f32s(&grid), &never).ok().unwrap();
        check_hull(&grid, &h);
        assert_eq!(h.vertices.len(), 8);
    }

    #[test]
    fn flat_and_straight_sets_have_no_solid_hull() {
        let flat: Vec<DVec3> = (0..50)
            .map(|i| DVec3::new(f64::from(i % 7), f64::from(i / 7), 2.0))
            .collect();
        assert!(
            matches!(convex_hull(&f32s(&flat), &never), Err(NoHull::Flat(n)) if n.z.abs() > 0.999)
        );
        let line: Vec<DVec3> = (0..10).map(|i| DVec3::splat(f64::from(i))).collect();
        assert!(matches!(
            convex_hull(&f32s(&line), &never),
            Err(NoHull::Line)
        ));
    }
}
