//! Adaptive target lengths: at each original vertex, the length whose
//! chord strays `tolerance` from a circle of the surface's largest normal
//! curvature there (`L = sqrt(6 e / k - 3 e^2)`, as the PMP library
//! takes it), clamped to `[min, max]`, then limited so it grows by at most
//! `gradation` per unit of distance from any neighbour (a smooth grading
//! instead of a jump from fine to coarse).
//!
//! A vertex's curvature is the largest over its edges of `2 |n . e| / |e|^2`
//! (the circle through both ends tangent to the vertex normal). Across a
//! feature edge the surface is not smooth, so feature vertices take the
//! largest curvature of their non-feature neighbours instead.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use super::mesh::{Mesh, Topo};

/// Jacobi passes of the grading at most.
const GRADE_PASSES: usize = 200;

pub(super) fn adaptive_sizes(
    m: &Mesh,
    topo: &Topo,
    min: f32,
    max: f32,
    tolerance: f32,
    gradation: f32,
) -> Vec<f32> {
    let n = m.pos.len();
    let normals: Vec<Vec3> = (0..n as u32)
        .into_par_iter()
        .map(|v| {
            topo.faces_of(v)
                .iter()
                .map(|&f| {
                    let q = m.faces[f as usize].map(|x| m.pos[x as usize]);
                    (q[1] - q[0]).cross(q[2] - q[0])
                })
                .sum::<Vec3>()
                .normalize_or_zero()
        })
        .collect();
    let smooth: Vec<f32> = (0..n as u32)
        .into_par_iter()
        .map(|v| {
            if topo.feature[v as usize] > 0 {
                return 0.0;
            }
            let mut scratch = Vec::new();
            topo.neighbours(m, v, &mut scratch);
            let p = m.pos[v as usize];
            scratch
                .iter()
                .map(|&x| {
                    let e = m.pos[x as usize] - p;
                    let l2 = e.length_squared();
                    if l2 > 0.0 {
                        2.0 * normals[v as usize].dot(e).abs() / l2
                    } else {
                        0.0
                    }
                })
                .fold(0.0, f32::max)
        })
        .collect();
    let curvature: Vec<f32> = (0..n as u32)
        .into_par_iter()
        .map(|v| {
            if topo.feature[v as usize] == 0 {
                return smooth[v as usize];
            }
            let mut scratch = Vec::new();
            topo.neighbours(m, v, &mut scratch);
            scratch
                .iter()
                .filter(|&&x| topo.feature[x as usize] == 0)
                .map(|&x| smooth[x as usize])
                .fold(0.0, f32::max)
        })
        .collect();
    let e = tolerance;
    let mut sizes: Vec<f32> = curvature
        .iter()
        .map(|&k| {
            let l2 = if k > 0.0 {
                6.0 * e / k - 3.0 * e * e
            } else {
                f32::INFINITY
            };
            if l2 > 0.0 { l2.sqrt() } else { min }.clamp(min, max)
        })
        .collect();
    grade(m, topo, gradation, &mut sizes);
    sizes
}

/// Limits each size to its neighbours' plus `gradation` times their
/// distance, until nothing changes.
fn grade(m: &Mesh, topo: &Topo, gradation: f32, sizes: &mut Vec<f32>) {
    for _ in 0..GRADE_PASSES {
        let old = &*sizes;
        let next: Vec<f32> = (0..m.pos.len() as u32)
            .into_par_iter()
            .map(|v| {
                let p = m.pos[v as usize];
                let mut s = old[v as usize];
                for &f in topo.faces_of(v) {
                    for &x in &m.faces[f as usize] {
                        let d = (m.pos[x as usize] - p).length();
                        s = s.min(old[x as usize] + gradation * d);
                    }
                }
                s
            })
            .collect();
        let changed = next.iter().zip(old.iter()).any(|(a, b)| a != b);
        *sizes = next;
        if !changed {
            break;
        }
    }
}
