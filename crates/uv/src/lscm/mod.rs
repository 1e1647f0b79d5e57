//! Least-squares conformal maps (Lévy, Petitjean, Ray, Maillot 2002,
//! "Least Squares Conformal Maps for Automatic Texture Atlas
//! Generation") of one triangle mesh with pinned vertices.
//!
//! A map is conformal when it keeps angles: on each triangle the gradient
//! of v is the gradient of u turned a quarter turn. LSCM minimises the
//! squared failure of that, summed over the triangles with their areas
//! (`assemble.rs` has the formula). The energy is zero for a
//! similarity of the plane, so at least two vertices must be pinned; with
//! exactly two the minimiser is unique on a connected mesh (Lévy et al.
//! show it, and that the pins' values only move, turn and scale it).
//! The map keeps the triangles' orientation: counter-clockwise about
//! their normal in 3D is counter-clockwise in uv.
//!
//! The minimiser solves a sparse complex Hermitian positive definite
//! system (the normal equations of the least-squares problem, with the
//! pinned unknowns moved to the right-hand side) in double precision, by
//! sparse Cholesky factorisation or conjugate gradients ([`LinearSolver`];
//! the `solver` module has the measurements that chose the default),
//! deterministically.
//!
//! Triangles with no area (and slivers whose area is below 1e-10 of
//! their longest edge squared) carry no angle and are left out; a vertex
//! that is then in no triangle takes the mean uv of its neighbours in the
//! triangles given (or (0, 0) when it has none).

mod assemble;
mod pins;
mod spectral;

use geode_geo::glam::Vec3;

use crate::error::UvError;
use crate::solver::{solve_hermitian, CgSettings, Complex, SolveReport};
use assemble::{assemble, triangle_terms, Role};
pub use pins::choose_pins;
pub use spectral::spectral;

/// A vertex held at a given uv.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pin {
    pub vertex: u32,
    pub uv: [f64; 2],
}

/// Which linear solver LSCM uses (see the `solver` module for the
/// measurements behind the default).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum LinearSolver {
    /// Sparse Cholesky factorisation (faer), then conjugate gradients if
    /// the tolerance is not met (or the factorisation fails). Fast:
    /// 0.3 s for 200k triangles; memory grows a little faster than the
    /// mesh.
    #[default]
    Cholesky,
    /// Conjugate gradients with a multigrid preconditioner alone: little
    /// memory, but about ten times slower at 200k triangles and worse
    /// beyond; cancellable every few iterations.
    ConjugateGradient,
}

/// Which conformal map an island gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum ConformalMethod {
    /// LSCM with the two farthest-apart boundary vertices pinned (Lévy et
    /// al.; what libigl's `lscm` and Blender's Conformal unwrap do): exact
    /// for developable islands, but a long curved strip can curl.
    #[default]
    TwoPins,
    /// The spectral conformal map ([`spectral`]): no pins, so nothing to
    /// curl about; islands without a boundary fall back on two pins.
    Spectral,
}

/// How the linear system is solved, and how exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverOptions {
    pub method: LinearSolver,
    /// Relative residual `|b - A x| / |b|` to reach.
    pub tolerance: f64,
    /// The most conjugate gradient iterations per solve.
    pub max_iterations: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            method: LinearSolver::Cholesky,
            tolerance: 1e-9,
            max_iterations: 20_000,
        }
    }
}

/// The uv of every vertex and how the solve went.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LscmSolution {
    /// One uv per input position (pinned vertices at their pins).
    pub uv: Vec<[f64; 2]>,
    pub iterations: usize,
    pub relative_residual: f64,
    /// False when `max_iterations` ran out before `tolerance` was met.
    pub converged: bool,
}

/// The least-squares conformal map of `triangles` (indices into
/// `positions`) with `pins` held: one uv per position. Needs two pins or
/// more on distinct vertices (see [`choose_pins`]); every connected part
/// of the mesh needs two of its own, or it collapses. Polls `cancel`
/// between phases and every 16 conjugate gradient iterations.
pub fn lscm(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    pins: &[Pin],
    options: &SolverOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<LscmSolution, UvError> {
    validate(positions.len(), triangles, pins)?;
    let terms = triangle_terms(positions, triangles);
    UvError::unless_cancelled(cancel)?;
    let (roles, free_vertices) = vertex_roles(positions.len(), &terms, pins);
    let (matrix, rhs) = assemble(&terms, &roles, &free_vertices);
    UvError::unless_cancelled(cancel)?;
    let settings = CgSettings {
        tolerance: options.tolerance,
        max_iterations: options.max_iterations,
    };
    let direct = options.method == LinearSolver::Cholesky;
    let (x, report) = solve_hermitian(&matrix, &rhs, direct, &settings, cancel)?;
    Ok(solution(&roles, &x, triangles, report))
}

/// Each vertex's uv from the solved unknowns `x` (pins at their values,
/// vertices in no triangle filled from their neighbours), with how the
/// solve went.
fn solution(
    roles: &[Role],
    x: &[Complex],
    triangles: &[[u32; 3]],
    report: SolveReport,
) -> LscmSolution {
    let mut uv: Vec<Option<Complex>> = roles
        .iter()
        .map(|role| match *role {
            Role::Free(k) => Some(x[k as usize]),
            Role::Pinned(p) => Some(p),
            Role::Unused => None,
        })
        .collect();
    fill_unused(&mut uv, triangles);
    LscmSolution {
        uv: uv
            .into_iter()
            .map(|c| c.map_or([0.0, 0.0], |c| [c.re, c.im]))
            .collect(),
        iterations: report.iterations,
        relative_residual: report.relative_residual,
        converged: report.converged,
    }
}

/// Indices in range, two distinct pins or more with finite values.
fn validate(vertices: usize, triangles: &[[u32; 3]], pins: &[Pin]) -> Result<(), UvError> {
    if let Some(t) = triangles
        .iter()
        .find(|t| t.iter().any(|&v| v as usize >= vertices))
    {
        return Err(UvError::Invalid(format!(
            "triangle {t:?} refers past the {vertices} positions"
        )));
    }
    if pins.len() < 2 {
        return Err(UvError::Invalid(format!(
            "LSCM needs two pinned vertices or more, {} given",
            pins.len()
        )));
    }
    let mut pinned: Vec<u32> = pins.iter().map(|p| p.vertex).collect();
    pinned.sort_unstable();
    if pinned.windows(2).any(|w| w[0] == w[1]) {
        return Err(UvError::Invalid("a vertex is pinned twice".into()));
    }
    if let Some(p) = pins
        .iter()
        .find(|p| p.vertex as usize >= vertices || !p.uv.iter().all(|c| c.is_finite()))
    {
        return Err(UvError::Invalid(format!(
            "pin {p:?} is out of range or not finite"
        )));
    }
    Ok(())
}

/// Each vertex's role, and the free vertices in unknown order.
fn vertex_roles(
    vertices: usize,
    terms: &[assemble::TriangleTerm],
    pins: &[Pin],
) -> (Vec<Role>, Vec<u32>) {
    let mut used = vec![false; vertices];
    for term in terms {
        for &c in &term.corners {
            used[c as usize] = true;
        }
    }
    let mut roles: Vec<Role> = used
        .iter()
        .map(|&u| if u { Role::Free(0) } else { Role::Unused })
        .collect();
    for pin in pins {
        roles[pin.vertex as usize] = Role::Pinned(Complex::new(pin.uv[0], pin.uv[1]));
    }
    let mut free_vertices = Vec::new();
    for (v, role) in roles.iter_mut().enumerate() {
        if let Role::Free(k) = role {
            *k = free_vertices.len() as u32;
            free_vertices.push(v as u32);
        }
    }
    (roles, free_vertices)
}

/// Gives each vertex without a uv the mean uv of its triangle neighbours
/// that have one, sweeping until nothing changes (vertices cut off from
/// every solved one stay None).
fn fill_unused(uv: &mut [Option<Complex>], triangles: &[[u32; 3]]) {
    if uv.iter().all(Option::is_some) {
        return;
    }
    loop {
        let mut sums: Vec<(Complex, u32)> = vec![(Complex::ZERO, 0); uv.len()];
        for t in triangles {
            for (i, &v) in t.iter().enumerate() {
                if uv[v as usize].is_some() {
                    continue;
                }
                for &other in [t[(i + 1) % 3], t[(i + 2) % 3]].iter() {
                    if let Some(value) = uv[other as usize] {
                        let s = &mut sums[v as usize];
                        s.0 += value;
                        s.1 += 1;
                    }
                }
            }
        }
        let mut changed = false;
        for (value, (sum, count)) in uv.iter_mut().zip(sums) {
            if value.is_none() && count > 0 {
                *value = Some(sum.scale(1.0 / count as f64));
                changed = true;
            }
        }
        if !changed {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat mesh's LSCM is a similarity: with the pins at their own
    /// positions it is the identity.
    #[test]
    fn a_flat_grid_comes_back_as_it_was() {
        let n = 12;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
                positions.push(Vec3::new(x + 0.2 * y * y, y + 0.1 * x, 0.0));
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        // A degenerate triangle and an unused vertex change nothing.
        positions.push(Vec3::new(0.5, 0.5, 0.0));
        triangles.push([id(0, 0), id(1, 0), id(1, 0)]);
        let pin = |v: u32| Pin {
            vertex: v,
            uv: [
                positions[v as usize].x as f64,
                positions[v as usize].y as f64,
            ],
        };
        let pins = [pin(id(0, 0)), pin(id(n, n))];
        let out = lscm(
            &positions,
            &triangles,
            &pins,
            &SolverOptions::default(),
            &|| false,
        )
        .unwrap();
        assert!(out.converged);
        for (p, uv) in positions.iter().zip(&out.uv).take(positions.len() - 1) {
            assert!((p.x as f64 - uv[0]).abs() < 1e-5 && (p.y as f64 - uv[1]).abs() < 1e-5);
        }
        assert_eq!(out.uv[positions.len() - 1], [0.0, 0.0]);
        let err = lscm(
            &positions,
            &triangles,
            &pins[..1],
            &SolverOptions::default(),
            &|| false,
        );
        assert!(matches!(err, Err(UvError::Invalid(_))));
    }
}
