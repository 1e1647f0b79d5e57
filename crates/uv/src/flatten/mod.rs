//! Flattening: a polygon mesh cut into islands along seams, each island
//! flattened by least-squares conformal maps, all packed into [0,1]^2.
//!
//! The phases, each its own function, with `cancel` polled between them
//! and inside the solves:
//!
//! 1. **charts** (`charts.rs`): islands are polygons joined through edges
//!    that are not cuts (seams, the mesh's boundary, non-manifold edges,
//!    edges between inconsistently oriented polygons); wedges are the uv
//!    vertices, one per point and side of a cut. Polylines, packed and
//!    patch primitives are no part of any island: their vertices get
//!    uv (0, 0) and island -1.
//! 2. **islands** (`island.rs`): each island becomes a triangle mesh over
//!    its wedges (polygons triangulated, concave ones by ear clipping;
//!    the output stays per original vertex), is solved by LSCM
//!    ([`crate::lscm`]) with its two farthest-apart boundary wedges pinned
//!    ([`crate::choose_pins`]) or by the spectral conformal map
//!    ([`crate::spectral`], [`FlattenOptions::method`]; an island without
//!    a boundary falls back on two pins), then rescaled so its uv area equals its 3D
//!    area (relative texel density kept). Islands are solved in parallel.
//!    An island without area (all its polygons degenerate) collapses to a
//!    point; a closed island (no boundary, no seam) is pinned at its two
//!    farthest wedges and flattens badly, as in every LSCM: give it seams.
//! 3. **packing** ([`crate::pack`]): islands turned to their minimal-area
//!    rectangles, shelf-packed at one common scale with the margin.
//! 4. **output**: each vertex's uv is its wedge's placed uv.
//!
//! Everything is deterministic: the same input gives bit-identical
//! output whatever the number of threads.

mod charts;
mod island;

use geode_geo::glam::Vec3;
use geode_geo::Geometry;
use rayon::prelude::*;

use crate::error::UvError;
use crate::lscm::{ConformalMethod, SolverOptions};
use crate::pack::{pack_islands, PackOptions, Packed, Placement};
use charts::{build_charts, Charts, NONE};
use island::{flatten_island, index_islands, island_mesh, FlatIsland, IslandIndex};

/// Everything [`flatten`] takes besides the mesh and its seams.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FlattenOptions {
    /// Margin and rotation of the packing.
    pub pack: PackOptions,
    /// When false the islands are not packed: each keeps its LSCM uv at
    /// its 3D scale (pinned wedge at the origin), so they overlap.
    pub skip_packing: bool,
    /// When the conjugate gradient solves stop.
    pub solver: SolverOptions,
    /// Two pins (LSCM) or spectral, per island.
    pub method: ConformalMethod,
}

/// What [`flatten`] returns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Flattened {
    /// One uv per vertex (z = 0), ready for the vertex attribute `uv`;
    /// (0, 0) for vertices of primitives that are not polygons.
    pub uv: Vec<Vec3>,
    /// The island of each primitive, numbered from 0 in the order of
    /// their first primitive; -1 for primitives that are not polygons.
    pub prim_island: Vec<i32>,
    pub island_count: usize,
    /// uv units per world unit of every island (1 when not packed).
    pub scale: f64,
    /// The margin used: less than asked when the islands were too many.
    pub margin: f64,
    /// Conjugate gradient iterations over all islands.
    pub iterations: usize,
    /// Islands whose solve hit `max_iterations` before its tolerance.
    pub unconverged_islands: usize,
}

/// Flattens the polygons of `g` cut along `seams` (undirected point pairs;
/// pairs that are no edge of `g` are ignored) into packed uv islands.
/// Fails on a margin outside [0, 0.5), and with `Cancelled` when `cancel`
/// says stop. Degenerate input (zero-area polygons, isolated points,
/// non-manifold edges, an empty mesh) is handled, never an error.
pub fn flatten(
    g: &Geometry,
    seams: &[[u32; 2]],
    options: &FlattenOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Flattened, UvError> {
    if !(0.0..0.5).contains(&options.pack.margin) {
        return Err(UvError::Invalid(format!(
            "the margin {} is not in [0, 0.5)",
            options.pack.margin
        )));
    }
    UvError::unless_cancelled(cancel)?;
    let charts = build_charts(g, seams);
    let index = index_islands(&charts);
    UvError::unless_cancelled(cancel)?;
    let islands = solve_islands(g, &charts, &index, options, cancel)?;
    UvError::unless_cancelled(cancel)?;
    let packed = place_islands(&islands, options)?;
    Ok(Flattened {
        uv: vertex_uv(&charts, &index, &islands, &packed.placements),
        prim_island: charts
            .prim_island
            .iter()
            .map(|&i| if i == NONE { -1 } else { i as i32 })
            .collect(),
        island_count: charts.islands,
        scale: packed.scale,
        margin: packed.margin,
        iterations: islands.iter().map(|i| i.iterations).sum(),
        unconverged_islands: islands.iter().filter(|i| !i.converged).count(),
    })
}

/// Every island flattened, in island order (in parallel).
fn solve_islands(
    g: &Geometry,
    charts: &Charts,
    index: &IslandIndex,
    options: &FlattenOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<FlatIsland>, UvError> {
    (0..charts.islands)
        .into_par_iter()
        .map(|island| {
            UvError::unless_cancelled(cancel)?;
            let mesh = island_mesh(g, charts, index, island);
            flatten_island(&mesh, &options.solver, options.method, cancel)
        })
        .collect()
}

/// The packing, or each island where LSCM left it when packing is off.
fn place_islands(islands: &[FlatIsland], options: &FlattenOptions) -> Result<Packed, UvError> {
    if options.skip_packing {
        let identity = Placement {
            rect: crate::pack::Oriented {
                direction: [1.0, 0.0],
                min: [0.0; 2],
                size: [0.0; 2],
            },
            corner: [0.0; 2],
            scale: 1.0,
        };
        return Ok(Packed {
            placements: vec![identity; islands.len()],
            scale: 1.0,
            margin: options.pack.margin,
        });
    }
    let points: Vec<&[[f64; 2]]> = islands.iter().map(|i| i.uv.as_slice()).collect();
    pack_islands(&points, &options.pack)
}

/// Each vertex's uv: its wedge's uv in its island, placed.
fn vertex_uv(
    charts: &Charts,
    index: &IslandIndex,
    islands: &[FlatIsland],
    placements: &[Placement],
) -> Vec<Vec3> {
    charts
        .vertex_wedge
        .par_iter()
        .with_min_len(4096)
        .map(|&wedge| {
            if wedge == NONE {
                return Vec3::ZERO;
            }
            let island = charts.wedge_island[wedge as usize] as usize;
            let local = index.wedge_local[wedge as usize] as usize;
            let [u, v] = placements[island].apply(islands[island].uv[local]);
            Vec3::new(u as f32, v as f32, 0.0)
        })
        .collect()
}
