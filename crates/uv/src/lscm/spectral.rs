//! Spectral conformal maps (Mullen, Tong, Alliez, Desbrun 2008,
//! "Spectral Conformal Parameterization"): LSCM's energy without pins.
//!
//! Why: with two pins the free-boundary conformal energy is nearly flat
//! along every holomorphic map that keeps the pins (`z -> exp z` among
//! them), and on a long curved strip LSCM's discrete minimiser drifts
//! along one of them: the island curls (a torus cut open spirals, its
//! texel density varying thousands of times). SCP asks instead for the
//! map of least conformal energy among those whose boundary has unit
//! spread and no mean: the smallest non-trivial generalised eigenvector
//! of `H x = lambda B x`, `H` LSCM's Hermitian matrix over every vertex
//! and `B` the boundary's lumped edge lengths (the constants, the energy's
//! kernel, are projected out). Inverse iteration finds it with one
//! sparse Cholesky factorisation of `H` (shifted by 1e-10 of its mean
//! diagonal, so it is definite) and a solve per iteration.
//!
//! It needs a boundary (an island cut open by seams or with edges of its
//! own); deterministic like the rest (sequential factorisation, fixed
//! start vector).

use geode_geo::glam::Vec3;

use super::assemble::{assemble, triangle_terms, Role};
use super::pins::boundary_edges;
use super::{solution, vertex_roles, LscmSolution};
use crate::error::UvError;
use crate::solver::{cholesky_iterate, Complex, Csr, SolveReport};

/// Most inverse iterations (each one triangular solve pair).
const MAX_ITERATIONS: usize = 300;
/// Relative change of the Rayleigh quotient that counts as converged.
const EIGEN_TOLERANCE: f64 = 1e-10;

/// The spectral conformal map of `triangles` (indices into `positions`):
/// one uv per position, at an arbitrary scale and rotation (callers
/// rescale). An error when the mesh has no boundary or its energy cannot
/// be factored (parts joined only through zero-area triangles).
pub fn spectral(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<LscmSolution, UvError> {
    let terms = triangle_terms(positions, triangles);
    UvError::unless_cancelled(cancel)?;
    let (roles, free_vertices) = vertex_roles(positions.len(), &terms, &[]);
    let (mut matrix, _) = assemble(&terms, &roles, &free_vertices);
    let used: Vec<[u32; 3]> = terms.iter().map(|t| t.corners).collect();
    let mass = boundary_mass(positions, &used, &roles, free_vertices.len());
    let total: f64 = mass.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(UvError::Invalid(
            "a spectral map needs a boundary: the island is closed".into(),
        ));
    }
    shift_diagonal(&mut matrix);
    UvError::unless_cancelled(cancel)?;
    let mut start = start_vector(free_vertices.len());
    normalise(&mut start, &mass, total);
    let first: Vec<Complex> = start.iter().zip(&mass).map(|(x, m)| x.scale(*m)).collect();
    let mut iterations = 0;
    let mut previous = f64::INFINITY;
    let mut converged = false;
    let solved = cholesky_iterate(&matrix, &first, cancel, &mut |x| {
        iterations += 1;
        if !normalise(x, &mass, total) {
            return Ok(false);
        }
        let quotient = rayleigh(&matrix, x);
        converged = (quotient - previous).abs() <= EIGEN_TOLERANCE * quotient.abs().max(1e-300);
        if converged || iterations >= MAX_ITERATIONS {
            return Ok(false);
        }
        previous = quotient;
        for (x, m) in x.iter_mut().zip(&mass) {
            *x = x.scale(*m);
        }
        Ok(true)
    })?;
    let Some(x) = solved else {
        return Err(UvError::Invalid(
            "the island's conformal energy could not be factored (parts joined only through triangles without area?)".into(),
        ));
    };
    let report = SolveReport {
        iterations,
        relative_residual: 0.0,
        converged,
    };
    Ok(solution(&roles, &x, triangles, report))
}

/// Half of each boundary edge's length to each of its ends (unknown order).
fn boundary_mass(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    roles: &[Role],
    unknowns: usize,
) -> Vec<f64> {
    let mut mass = vec![0.0f64; unknowns];
    for [a, b] in boundary_edges(triangles) {
        let length = positions[a as usize]
            .as_dvec3()
            .distance(positions[b as usize].as_dvec3());
        for v in [a, b] {
            if let Role::Free(k) = roles[v as usize] {
                mass[k as usize] += 0.5 * length;
            }
        }
    }
    mass
}

/// Adds 1e-10 of the mean diagonal to the diagonal: the constants stop
/// being a kernel, nothing else moves measurably.
fn shift_diagonal(matrix: &mut Csr) {
    let diagonal = matrix.diagonal();
    let mean = diagonal.iter().sum::<f64>() / diagonal.len().max(1) as f64;
    let shift = 1e-10 * mean.max(f64::MIN_POSITIVE);
    for row in 0..matrix.rows() {
        for k in matrix.offsets[row]..matrix.offsets[row + 1] {
            if matrix.cols[k] as usize == row {
                matrix.values[k].re += shift;
            }
        }
    }
}

/// A fixed pseudo-random start (a smooth one could miss the eigenvector).
fn start_vector(n: usize) -> Vec<Complex> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    (0..n).map(|_| Complex::new(next(), next())).collect()
}

/// Removes the boundary-weighted mean and scales to unit boundary norm;
/// false when nothing is left.
fn normalise(x: &mut [Complex], mass: &[f64], total: f64) -> bool {
    let mut mean = Complex::ZERO;
    for (x, m) in x.iter().zip(mass) {
        mean += x.scale(*m);
    }
    let mean = mean.scale(1.0 / total);
    let mut norm = 0.0;
    for (x, m) in x.iter_mut().zip(mass) {
        *x -= mean;
        norm += m * x.norm_sqr();
    }
    let norm = norm.sqrt();
    if !(norm > 0.0 && norm.is_finite()) {
        return false;
    }
    for x in x.iter_mut() {
        *x = x.scale(1.0 / norm);
    }
    true
}

/// `x^H H x` (real for Hermitian `H`).
fn rayleigh(matrix: &Csr, x: &[Complex]) -> f64 {
    let mut hx = vec![Complex::ZERO; x.len()];
    matrix.multiply(x, &mut hx);
    x.iter().zip(&hx).map(|(a, b)| a.dot(*b)).sum()
}
