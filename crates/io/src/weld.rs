//! Welding: one point per distinct position, for formats that store unshared corners (STL, glTF).

use geode_geo::glam::Vec3;
use rayon::prelude::*;

/// Unique positions numbered by first appearance, and the point of each
/// input position. Positions are equal when bit-identical (with -0 = 0).
/// Deterministic: a parallel sort, then a sequential numbering pass.
pub fn weld_positions(corners: &[Vec3]) -> (Vec<Vec3>, Vec<u32>) {
    let key = |p: &Vec3| {
        let b = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
        (b(p.x), b(p.y), b(p.z))
    };
    let mut order: Vec<u32> = (0..corners.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| (key(&corners[i as usize]), i));
    // Each run of equal keys becomes one point, represented by its first corner.
    let mut first_of_corner = vec![0u32; corners.len()];
    let mut run_start = 0;
    for k in 0..order.len() {
        if k == 0 || key(&corners[order[k] as usize]) != key(&corners[order[k - 1] as usize]) {
            run_start = order[k];
        }
        first_of_corner[order[k] as usize] = run_start;
    }
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
