//! Which of polyfill's loops share a plane and may nest: a cut through a
//! torus leaves an outer and an inner circle in one plane, and their fill
//! is one ring-shaped face, not two discs over each other.
//!
//! A loop may nest when it is planar (every point within a hundred-
//! thousandth of its size of its best-fit plane) and no face along it lies
//! in that plane: the hole in a flat sheet shares its plane with the
//! sheet's outer border, but the sheet already covers the ring between
//! them, and each is filled on its own. Loops are taken largest first; a
//! loop leads a group and takes every other loop in its plane (normals
//! parallel either way, points within the leader's tolerance), found in a
//! window of loops sorted by their planes' offsets.

use geode_geo::glam::DVec3;
use geode_geo::Geometry;

use super::newell_normal;

/// Relative distance from a plane that still counts as in it.
const PLANAR: f64 = 1e-5;
/// |cos| between a face's and a loop's normals above which the face lies
/// in the loop's plane.
const IN_PLANE: f64 = 0.99;

/// A loop's plane: unit normal (as the loop winds), centroid, size.
struct Plane {
    normal: DVec3,
    centre: DVec3,
    area: f64,
    tolerance: f64,
    /// The offset along the normal turned to a fixed side, for sorting.
    offset: f64,
}

/// Groups of loops (indices into `loops`, ascending) lying in one plane,
/// of two loops or more; `loops[k]` are the loop's points and the faces
/// along it.
pub(crate) fn coplanar_groups(g: &Geometry, loops: &[(Vec<u32>, Vec<u32>)]) -> Vec<Vec<usize>> {
    let positions = g.positions();
    let points: Vec<Vec<DVec3>> = loops
        .iter()
        .map(|(l, _)| {
            l.iter()
                .map(|&p| positions[p as usize].as_dvec3())
                .collect()
        })
        .collect();
    let planes: Vec<Option<Plane>> = (0..loops.len())
        .map(|k| plane_of(g, &points[k], &loops[k].1))
        .collect();
    let mut by_offset: Vec<usize> = (0..loops.len()).filter(|&k| planes[k].is_some()).collect();
    let plane = |k: usize| planes[k].as_ref().expect("filtered");
    by_offset.sort_by(|&a, &b| plane(a).offset.total_cmp(&plane(b).offset).then(a.cmp(&b)));
    let mut by_area = by_offset.clone();
    by_area.sort_by(|&a, &b| plane(b).area.total_cmp(&plane(a).area).then(a.cmp(&b)));
    let mut taken = vec![false; loops.len()];
    let mut groups = Vec::new();
    for &lead in &by_area {
        if taken[lead] {
            continue;
        }
        taken[lead] = true;
        let l = plane(lead);
        let lo = by_offset.partition_point(|&k| plane(k).offset < l.offset - l.tolerance);
        let hi = by_offset.partition_point(|&k| plane(k).offset <= l.offset + l.tolerance);
        let mut group = vec![lead];
        for &k in &by_offset[lo..hi] {
            let parallel = plane(k).normal.dot(l.normal).abs() > 1.0 - 1e-6;
            if taken[k] || !parallel {
                continue;
            }
            let in_plane = points[k]
                .iter()
                .all(|&p| (p - l.centre).dot(l.normal).abs() <= l.tolerance);
            if in_plane {
                taken[k] = true;
                group.push(k);
            }
        }
        if group.len() > 1 {
            group.sort_unstable();
            groups.push(group);
        }
    }
    groups.sort_unstable();
    groups
}

/// The plane of a loop that may nest (see the module doc), or `None`.
fn plane_of(g: &Geometry, p: &[DVec3], faces: &[u32]) -> Option<Plane> {
    let centre = p.iter().sum::<DVec3>() / p.len() as f64;
    let area_vector = newell_normal(&p.iter().map(|&x| x - centre).collect::<Vec<_>>());
    let normal = area_vector.try_normalize()?;
    let (lo, hi) = p
        .iter()
        .fold((p[0], p[0]), |(lo, hi), &x| (lo.min(x), hi.max(x)));
    let tolerance = PLANAR * (hi - lo).length();
    if p.iter()
        .any(|&x| (x - centre).dot(normal).abs() > tolerance)
    {
        return None;
    }
    let positions = g.positions();
    let lies_in_plane = faces.iter().any(|&f| {
        let corners: Vec<DVec3> = g
            .prim_points(f as usize)
            .iter()
            .map(|&q| positions[q as usize].as_dvec3())
            .collect();
        newell_normal(&corners)
            .try_normalize()
            .is_some_and(|n| n.dot(normal).abs() > IN_PLANE)
    });
    if lies_in_plane {
        return None;
    }
    let axis = (0..3)
        .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
        .expect("three axes");
    let side = normal[axis].signum();
    Some(Plane {
        normal,
        centre,
        area: area_vector.length() / 2.0,
        tolerance,
        offset: side * normal.dot(centre),
    })
}
