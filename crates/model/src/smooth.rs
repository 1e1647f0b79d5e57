//! Smoothing of polygon meshes and polylines over their edge connectivity:
//! Laplacian and Taubin's λ|μ, with pinned points and optional volume
//! keeping.
//!
//! Each point's neighbours are the points it shares an edge with (polygon
//! edges and polyline segments alike, `graph.rs`), weighted uniformly. One Laplacian step moves every free point
//! a fraction `f` of the way to its neighbours' mean: `p += f (mean - p)`.
//! Repeated, it shrinks a closed surface toward its centroid (a sphere's
//! radius drops every step). Taubin's filter (Taubin 1995, "A signal
//! processing approach to fair surface design") alternates a step of
//! `λ > 0` with one of `μ < -λ`; the pair passes low frequencies of the
//! surface (its shape) and damps high ones (noise), so the surface keeps
//! its size. `μ` follows from `λ` and the pass-band frequency
//! `k_pb = 1/λ + 1/μ` (Taubin's 0.01 to 0.1).
//!
//! Every step reads the previous positions and writes new ones (Jacobi
//! order), so points are independent and run in parallel, each summing its
//! neighbours in their stored order: the result is the same bytes on any
//! number of threads.
//!
//! Pinned points never move: border points (ends of boundary edges, which
//! one polygon uses, and the ends of open polylines) when asked, and any
//! point set the caller gives. Volume keeping, for closed meshes, rescales
//! the free points about the points' centroid after every iteration so the
//! enclosed volume is the input's again (one scaling is exact when nothing
//! is pinned; with pins the scaling is repeated, at most four times, until
//! the volume is within 1e-7 of the input's). Volumes and centroids are
//! summed in f64 over fixed blocks, combined in block order.

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{Geometry, Group, PrimKind};
use rayon::prelude::*;

use crate::ModelError;

mod graph;

use graph::EdgeGraph;

/// Which filter a step applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SmoothMethod {
    /// One step of the strength per iteration (shrinks closed surfaces).
    Laplacian,
    /// A step of the strength `λ`, then one of `μ = 1 / (pass_band - 1/λ)`.
    Taubin { pass_band: f32 },
}

impl SmoothMethod {
    pub const NAMES: &'static [&'static str] = &["laplacian", "taubin"];
}

/// What `smooth` does.
#[derive(Clone, Copy, Debug)]
pub struct SmoothOptions<'a> {
    pub method: SmoothMethod,
    /// The fraction of the way to the neighbours' mean a point moves in a
    /// step (Taubin's λ), in [0, 1] (0: no change).
    pub strength: f32,
    pub iterations: u32,
    /// Boundary points and open polyline ends stay where they are.
    pub pin_border: bool,
    /// Further points that stay where they are.
    pub pinned: Option<&'a Group>,
    /// Restore the enclosed volume after every iteration (closed meshes).
    pub keep_volume: bool,
}

/// Points per block of the parallel sums (fixed, so sums do not depend on
/// the thread count).
const BLOCK: usize = 1 << 14;

/// Smooths `g`'s point positions in place; every attribute but `P` is left
/// as it was. `cancel` is polled every step.
pub fn smooth(
    g: &mut Geometry,
    opts: &SmoothOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    let steps = step_factors(opts)?;
    if opts.iterations == 0 || g.num_points() == 0 {
        return Ok(());
    }
    let graph = EdgeGraph::build(g);
    if opts.keep_volume {
        check_closed(g, &graph)?;
    }
    let free = free_points(g, &graph, opts)?;
    let target_volume = if opts.keep_volume {
        Some(enclosed_volume(g, g.positions()))
    } else {
        None
    };
    let mut current = g.positions().to_vec();
    let mut next = current.clone();
    for _ in 0..opts.iterations {
        for &factor in &steps {
            if cancel() {
                return Err(ModelError::Cancelled);
            }
            laplacian_step(&graph, &free, factor, &current, &mut next);
            std::mem::swap(&mut current, &mut next);
        }
        if let Some(volume) = target_volume {
            restore_volume(g, &free, volume, &mut current);
        }
    }
    g.positions_mut().copy_from_slice(&current);
    Ok(())
}

/// The factor of each step of one iteration, the options checked.
fn step_factors(opts: &SmoothOptions) -> Result<Vec<f32>, ModelError> {
    let lambda = opts.strength;
    if !(0.0..=1.0).contains(&lambda) {
        return Err(ModelError::Invalid(format!(
            "strength must be in [0, 1], not {lambda}"
        )));
    }
    if lambda == 0.0 {
        return Ok(Vec::new());
    }
    Ok(match opts.method {
        SmoothMethod::Laplacian => vec![lambda],
        SmoothMethod::Taubin { pass_band } => {
            if !(pass_band > 0.0 && pass_band < 1.0) {
                return Err(ModelError::Invalid(format!(
                    "pass band must be in (0, 1), not {pass_band}"
                )));
            }
            vec![lambda, 1.0 / (pass_band - 1.0 / lambda)]
        }
    })
}

/// Whether each point may move: not pinned by the border or the group.
fn free_points(
    g: &Geometry,
    graph: &EdgeGraph,
    opts: &SmoothOptions,
) -> Result<Vec<bool>, ModelError> {
    let mut free = vec![true; g.num_points()];
    if let Some(group) = opts.pinned {
        if group.len() != g.num_points() {
            return Err(ModelError::Invalid(format!(
                "the pinned group has {} entries for {} points",
                group.len(),
                g.num_points()
            )));
        }
        for p in group.members() {
            free[p] = false;
        }
    }
    if opts.pin_border {
        for p in border_points(g, graph) {
            free[p as usize] = false;
        }
    }
    Ok(free)
}

/// Ends of edges one polygon uses, and ends of open polylines (a polyline
/// whose last point is its first is a loop, with no ends).
fn border_points(g: &Geometry, graph: &EdgeGraph) -> Vec<u32> {
    let mut border = graph.boundary_points.clone();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != PrimKind::Polyline {
            continue;
        }
        if let (Some(&first), Some(&last)) =
            (g.prim_points(prim).first(), g.prim_points(prim).last())
        {
            if first != last {
                border.extend([first, last]);
            }
        }
    }
    border.sort_unstable();
    border.dedup();
    border
}

/// One Jacobi step: every free point moves `factor` of the way from
/// `current` to its neighbours' mean, written to `next`.
fn laplacian_step(
    graph: &EdgeGraph,
    free: &[bool],
    factor: f32,
    current: &[Vec3],
    next: &mut [Vec3],
) {
    next.par_iter_mut().enumerate().for_each(|(p, out)| {
        let here = current[p];
        let neighbours = graph.neighbours(p);
        if !free[p] || neighbours.is_empty() {
            *out = here;
            return;
        }
        let mut sum = DVec3::ZERO;
        for &q in neighbours {
            sum += current[q as usize].as_dvec3();
        }
        let mean = sum / neighbours.len() as f64;
        let moved = here.as_dvec3() + f64::from(factor) * (mean - here.as_dvec3());
        *out = moved.as_vec3();
    });
}

/// Refuses a mesh that is not closed: only polygons, every edge used by
/// exactly two of them.
fn check_closed(g: &Geometry, graph: &EdgeGraph) -> Result<(), ModelError> {
    let not_closed = |why: String| ModelError::NotClosed {
        input: "geometry",
        why,
    };
    if let Some(prim) = (0..g.num_prims()).find(|&k| g.prim_kind(k) != PrimKind::Polygon) {
        return Err(not_closed(format!(
            "keeping the volume needs polygons only; primitive {prim} is a {}",
            g.prim_kind(prim).name()
        )));
    }
    let open = graph.open_edges;
    if open > 0 || g.num_prims() == 0 {
        return Err(not_closed(format!(
            "{open} edges are not shared by exactly two polygons"
        )));
    }
    Ok(())
}

/// The volume `g`'s polygons enclose with the points at `positions`
/// (divergence theorem over each polygon's fan), in f64.
pub fn enclosed_volume(g: &Geometry, positions: &[Vec3]) -> f64 {
    let blocks: Vec<f64> = (0..g.num_prims().div_ceil(BLOCK))
        .into_par_iter()
        .map(|b| {
            let mut v = 0.0;
            for prim in b * BLOCK..((b + 1) * BLOCK).min(g.num_prims()) {
                let q = g.prim_points(prim);
                let a = positions[q[0] as usize].as_dvec3();
                for j in 1..q.len().saturating_sub(1) {
                    let b = positions[q[j] as usize].as_dvec3();
                    let c = positions[q[j + 1] as usize].as_dvec3();
                    v += a.dot(b.cross(c));
                }
            }
            v
        })
        .collect();
    blocks.iter().sum::<f64>() / 6.0
}

/// The mean of the points, in f64.
fn centroid(positions: &[Vec3]) -> DVec3 {
    let blocks: Vec<DVec3> = positions
        .par_chunks(BLOCK)
        .map(|c| c.iter().map(|p| p.as_dvec3()).sum::<DVec3>())
        .collect();
    blocks.iter().sum::<DVec3>() / positions.len().max(1) as f64
}

/// Scales the free points about the centroid until the enclosed volume is
/// `target` again (once when nothing is pinned).
fn restore_volume(g: &Geometry, free: &[bool], target: f64, positions: &mut [Vec3]) {
    let center = centroid(positions);
    for _ in 0..4 {
        let volume = enclosed_volume(g, positions);
        if volume.abs() < f64::MIN_POSITIVE || (volume / target - 1.0).abs() < 1e-7 {
            return;
        }
        let ratio = target / volume;
        if ratio <= 0.0 {
            return;
        }
        let scale = ratio.cbrt();
        positions
            .par_iter_mut()
            .zip(free.par_iter())
            .for_each(|(p, &free)| {
                if free {
                    *p = (center + (p.as_dvec3() - center) * scale).as_vec3();
                }
            });
    }
}
