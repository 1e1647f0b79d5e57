//! Welding: one point per distinct position, for formats that store unshared corners (STL, glTF).

use geode_geo::glam::Vec3;
use rayon::prelude::*;

/// Unique positions numbered by first appearance, and the point of each
/// input position. Positions are equal when bit-identical (with -0 = 0).
/// Deterministic: a parallel sort, then a sequential numbering pass.
pub fn weld_positions(corners: &[Vec3]) -> (Vec<Vec3>, Vec<u32>) {
    let bits = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
    // Keys laid out beside their indices so the sort compares in place.
    let mut keyed: Vec<([u32; 3], u32)> = corners
        .par_iter()
        .enumerate()
        .map(|(i, p)| ([bits(p.x), bits(p.y), bits(p.z)], i as u32))
        .collect();
    keyed.par_sort_unstable();
    // Each run of equal keys becomes one point, represented by its first
    // (lowest-index) corner, which sorts first within the run.
    let mut first_of_corner = vec![0u32; corners.len()];
    let mut run_start = 0;
    for k in 0..keyed.len() {
        if k == 0 || keyed[k].0 != keyed[k - 1].0 {
            run_start = keyed[k].1;
        }
        first_of_corner[keyed[k].1 as usize] = run_start;
    }
    drop(keyed);
    let mut point_of_first = vec![u32::MAX; corners.len()];
    let mut positions = Vec::new();
    let mut map = Vec::with_capacity(corners.len());
    for &first in &first_of_corner {
        let f = first as usize;
        if point_of_first[f] == u32::MAX {
            point_of_first[f] = positions.len() as u32;
            positions.push(corners[f]);
        }
        map.push(point_of_first[f]);
    }
    (positions, map)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_appearance_order() {
        let (p, m) = weld_positions(&[
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::new(-0.0, 1.0, 0.0),
            Vec3::Z,
        ]);
        assert_eq!(p, vec![Vec3::X, Vec3::Y, Vec3::Z]);
        assert_eq!(m, vec![0, 1, 0, 1, 2]);
    }
}
