//! The polygoniser: an octree over bricks of 8^3 cells pruned by interval
//! arithmetic (each level evaluates a tape simplified for its region), then
//! dual contouring in the surviving bricks: one vertex per connected surface
//! component of a cell (faces paired by the field at their centre where the
//! corners alternate, and by the surface's direction where an edge is
//! crossed twice, so the mesh is closed; vertices shared by two sheets are
//! split afterwards, see `pinch`), placed by a QEF over the crossings'
//! tangent planes so sharp edges and corners survive, with analytic normals
//! from the gradient. Each brick makes the dual quads of the crossed edges
//! all four of whose cells it holds; the cells' references to edges on
//! brick faces meet in one sort afterwards.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use rayon::prelude::*;

use crate::adaptive;
use crate::brick::{join_bricks, mesh_brick, take_quads, BrickOut, Joined};
use crate::cell::{Grid, B};
use crate::coarse;
use crate::lattice::SNAP;
use crate::pinch;
use geode_frep::eval::{BatchEval, IntervalEval};
use geode_frep::field::{Binary, Field, Node};
use geode_frep::interval::Interval;
use geode_frep::shapes;
use geode_frep::tape::Tape;

/// What to mesh and how finely.
#[derive(Clone, Debug)]
pub struct MeshOptions {
    pub min: [f64; 3],
    pub max: [f64; 3],
    /// The longest side of the box is cut into `2^depth` cells.
    pub depth: u32,
    /// QEF truncation: singular values below this fraction of the largest
    /// are ignored (larger keeps fewer sharp features, smaller risks spikes).
    pub sharpness: f64,
    /// Adaptive output: triangles merge while the field finds the merged
    /// surface within this distance (model units) of the exact one; 0 keeps
    /// the uniform mesh.
    pub tolerance: f64,
}

impl MeshOptions {
    pub fn new(min: [f64; 3], max: [f64; 3], depth: u32) -> MeshOptions {
        MeshOptions {
            min,
            max,
            depth,
            sharpness: 0.05,
            tolerance: 0.0,
        }
    }
}

/// Why meshing stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("cancelled")]
    Cancelled,
    #[error("the bounding box is empty or not finite")]
    BadBounds,
    #[error("depth {0} is out of range (1 to 16)")]
    BadDepth(u32),
}

/// Counters of a meshing run (for tests, benchmarks and warnings).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshStats {
    pub bricks_total: usize,
    pub bricks_meshed: usize,
    pub cells_with_surface: usize,
    /// Adaptive output: octree nodes of 2 cells or more meshed as one vertex
    /// each (see `coarse`), whose cells `cells_with_surface` leaves out.
    pub leaves: usize,
    /// Vertices added where one vertex was shared by two sheets.
    pub vertices_split: usize,
    /// Cells proven to hold surface that none of their corners shows: a
    /// feature thinner than a cell, missing from the mesh there.
    pub thin_cells: usize,
    /// The box of those cells (model units), when there are any.
    pub thin_region: Option<([f64; 3], [f64; 3])>,
    /// Edges flipped to follow a crease (see `crease.rs`).
    pub crease_flips: usize,
    /// Adaptive output: edges split where the uniform mesh strayed beyond
    /// the tolerance, edges collapsed where the surface allowed, and the
    /// largest deviation measured after splitting (model units).
    pub splits: usize,
    pub collapses: usize,
    pub deviation: f64,
}

impl MeshStats {
    fn add_missed(&mut self, grid: &Grid, cells: &[[usize; 3]]) {
        for c in cells {
            let (lo, hi) = (grid.point(*c), grid.point(c.map(|x| x + 1)));
            let (mut rlo, mut rhi) = self.thin_region.unwrap_or((lo, hi));
            for a in 0..3 {
                rlo[a] = rlo[a].min(lo[a]);
                rhi[a] = rhi[a].max(hi[a]);
            }
            self.thin_region = Some((rlo, rhi));
        }
        self.thin_cells += cells.len();
    }
}

/// An octree node that may hold surface, with the tape simplified for its
/// box and the coarser tape of its parent, which stays valid one cell
/// beyond the node on every side (feature recovery reads that ring).
struct Surviving {
    node: [usize; 3],
    tape: Arc<Tape>,
    ring_tape: Arc<Tape>,
    /// A coarse leaf (adaptive output, see `coarse`): its level above the
    /// bricks and its vertex, taken when the bricks are meshed.
    leaf: Option<(u32, BrickOut)>,
}

/// How the octree descends: the level where it stops (0: bricks) and the
/// adaptive tolerance coarse leaves must meet (0: none).
#[derive(Clone, Copy)]
struct Descent {
    stop: u32,
    tolerance: f64,
    sharpness: f64,
}

/// Octree nodes of `stop` levels above the bricks (0: bricks) that may hold
/// surface. Nodes above the bricks are simplified over their box grown by
/// one cell, so each parent's tape serves its children's rings; bricks over
/// their exact box (the tape most of the meshing work runs).
fn surviving_bricks(
    tape: Arc<Tape>,
    grid: &Grid,
    (level, descent): (u32, Descent),
    b: [usize; 3],
    out: &mut Vec<Surviving>,
    cancel: &(dyn Fn() -> bool + Sync),
) {
    if cancel() || (0..3).any(|a| b[a] >= grid.bricks[a]) {
        return;
    }
    let span = (1usize << level) * B;
    let grow = if level == 0 { 0.0 } else { grid.h };
    let lo = grid.point([b[0] * B, b[1] * B, b[2] * B]).map(|x| x - grow);
    let hi = grid
        .point([b[0] * B + span, b[1] * B + span, b[2] * B + span])
        .map(|x| x + grow);
    let mut iv = IntervalEval::new(&tape);
    let r = iv.eval(
        Interval::new(lo[0], hi[0]),
        Interval::new(lo[1], hi[1]),
        Interval::new(lo[2], hi[2]),
    );
    // Outside by less than the snap (see `lattice::SNAP`) may still mesh:
    // a corner there reads as on the surface, and the node beside it must
    // mesh its edges too.
    let snapped = SNAP * grid.h;
    if !r.has_nan() && (r.lo > 0.0 || r.hi < -snapped) {
        return;
    }
    let simplified = Arc::new(tape.simplify(iv.choices()));
    let side = B << level;
    if descent.tolerance > 0.0 && side <= coarse::LARGEST {
        let node = (b.map(|x| x * B), side);
        if let Some(leaf) = coarse::coarse_leaf(
            &simplified,
            grid,
            node,
            (descent.sharpness, descent.tolerance),
        ) {
            out.push(Surviving {
                node: b,
                tape: simplified,
                ring_tape: tape,
                leaf: Some((level, leaf)),
            });
            return;
        }
    }
    if level <= descent.stop {
        out.push(Surviving {
            node: b,
            tape: simplified,
            ring_tape: tape,
            leaf: None,
        });
        return;
    }
    let half = 1usize << (level - 1);
    let children: Vec<[usize; 3]> = (0..8)
        .map(|c| {
            [
                b[0] + (c & 1) * half,
                b[1] + (c >> 1 & 1) * half,
                b[2] + (c >> 2 & 1) * half,
            ]
        })
        .collect();
    // Every level's children in parallel: subtrees are uneven (a column's
    // bricks beside empty air), and a task of 64 bricks on one thread left
    // the other idle (colonnade at depth 6: 0.6 ms of 27.7 saved).
    let parts: Vec<Vec<Surviving>> = children
        .par_iter()
        .map(|c| {
            let mut v = Vec::new();
            let levels = (level - 1, descent);
            surviving_bricks(Arc::clone(&simplified), grid, levels, *c, &mut v, cancel);
            v
        })
        .collect();
    out.extend(parts.into_iter().flatten());
}

/// How far from the surface, in cells, the mesher reads the field's value
/// (beyond it only the sign): corners next to a crossing lie within one
/// cell of it on a distance field, thin-feature probes within two.
const FLOOR_CELLS: f64 = 3.0;

/// The field with the datasets it reaches through `min` and `max` alone
/// floored at `floor` (< 0): `max(floor, f)` distributes over both, so the
/// result equals `f` wherever either is above the floor, and has its sign
/// everywhere; capsules that never rise above it drop out of every search.
fn floor_capsules(f: &Field, floor: f64) -> Field {
    let min_or_max = |g: &Field| matches!(g.node(), Node::Binary(Binary::Min | Binary::Max, _, _));
    f.fold(min_or_max, |g, get: &dyn Fn(&Field) -> Field| {
        match g.node() {
            Node::Binary(op @ (Binary::Min | Binary::Max), a, b) => get(a).binary(*op, get(b)),
            Node::Dataset(set, args) => match set.with_floor(floor) {
                Some(floored) => Field::dataset_at(&Arc::new(floored), args.clone()),
                None => g.clone(),
            },
            _ => g.clone(),
        }
    })
}

/// Meshes begun, numbering each (see `Grid::mesh`).
static MESHES: AtomicU64 = AtomicU64::new(0);

/// The cell grid, the tape of the field clipped to the box, and the octree's
/// top level (bricks per side as a power of two).
fn setup(field: &Field, opts: &MeshOptions) -> Result<(Grid, Arc<Tape>, u32), MeshError> {
    if !(1..=16).contains(&opts.depth) {
        return Err(MeshError::BadDepth(opts.depth));
    }
    let size: [f64; 3] = std::array::from_fn(|k| opts.max[k] - opts.min[k]);
    if size.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
        return Err(MeshError::BadBounds);
    }
    let longest = size.iter().fold(0.0f64, |a, b| a.max(*b));
    let h = longest / (1u64 << opts.depth) as f64;
    // One cell of margin on every side: the clipped solid never touches the grid's edge.
    let cells: [usize; 3] = std::array::from_fn(|k| (size[k] / h).ceil() as usize + 2);
    let grid = Grid {
        origin: std::array::from_fn(|k| opts.min[k] - h),
        h,
        corners: cells.map(|c| c + 1),
        bricks: cells.map(|c| c.div_ceil(B)),
        mesh: MESHES.fetch_add(1, Ordering::Relaxed),
    };
    let center: [f64; 3] = std::array::from_fn(|k| 0.5 * (opts.min[k] + opts.max[k]));
    let half: [f64; 3] = std::array::from_fn(|k| 0.5 * size[k]);
    let clipped = floor_capsules(&field.min(shapes::block(center, half)), -FLOOR_CELLS * h);
    let tape = Arc::new(Tape::compile(&clipped));
    let top = grid
        .bricks
        .iter()
        .copied()
        .max()
        .unwrap_or(1)
        .next_power_of_two()
        .trailing_zeros();
    Ok((grid, tape, top))
}

/// Peak bytes per cell with surface while meshing (positions, normals, QEF
/// points, dual-edge references, triangles and the geometry built from
/// them), measured on spheres at depths 8-10.
const BYTES_PER_SURFACE_CELL: f64 = 480.0;

/// Cells with surface per unit of a surviving octree node's cross-section:
/// measured on a sphere, a torus and a gyroid (meshed over estimated cells
/// 0.63-0.68 at brick level; coarser nodes over-count, which errs safe).
const CROSSING_FACTOR: f64 = 1.0;

/// What meshing would cost, estimated before anything large is allocated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshEstimate {
    pub surface_cells: f64,
    pub bytes: f64,
}

/// Estimates the cells with surface (and the bytes meshing takes) from the
/// octree pruned only down to nodes of about 64^3 over the box, so it takes
/// milliseconds at any depth: a surface crossing a node of side n cells
/// crosses about n^2 of its cells. `cancel` is polled per octree node.
pub fn estimate(
    field: &Field,
    opts: &MeshOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<MeshEstimate, MeshError> {
    let (grid, tape, top) = setup(field, opts)?;
    let stop = top.saturating_sub(6);
    let mut nodes = Vec::new();
    let descent = Descent {
        stop,
        tolerance: 0.0,
        sharpness: opts.sharpness,
    };
    surviving_bricks(tape, &grid, (top, descent), [0, 0, 0], &mut nodes, cancel);
    if cancel() {
        return Err(MeshError::Cancelled);
    }
    let side = (B << stop) as f64;
    let surface_cells = nodes.len() as f64 * CROSSING_FACTOR * side * side;
    Ok(MeshEstimate {
        surface_cells,
        bytes: surface_cells * BYTES_PER_SURFACE_CELL,
    })
}

/// Meshes the solid `field >= 0` inside the box into closed, consistently
/// oriented triangles with point normals `N` from the gradient. The box
/// closes the surface where the solid reaches it. Deterministic for any
/// thread count; `cancel` is polled per brick and between phases,
/// `progress` gets 0..1.
pub fn polygonise(
    field: &Field,
    opts: &MeshOptions,
    cancel: &(dyn Fn() -> bool + Sync),
    progress: &(dyn Fn(f32) + Sync),
) -> Result<(Geometry, MeshStats), MeshError> {
    // On a pool thread from the start: a parallel loop begun outside the
    // pool hands its job over and waits on a latch, and reduction's fifty
    // passes begin a hundred and fifty of them (colonnade at depth 6: 24.5
    // against 24.0 ms). Already on a pool thread, the scope runs in place.
    rayon::scope(|_| polygonise_on_pool(field, opts, cancel, progress))
}

/// [`polygonise`], run on a thread of the current pool.
fn polygonise_on_pool(
    field: &Field,
    opts: &MeshOptions,
    cancel: &(dyn Fn() -> bool + Sync),
    progress: &(dyn Fn(f32) + Sync),
) -> Result<(Geometry, MeshStats), MeshError> {
    let (grid, tape, top) = setup(field, opts)?;
    // Polled between phases; bricks poll `cancel` themselves.
    let stop = || {
        if cancel() {
            Err(MeshError::Cancelled)
        } else {
            Ok(())
        }
    };
    let mut bricks = Vec::new();
    let descent = Descent {
        stop: 0,
        tolerance: opts.tolerance,
        sharpness: opts.sharpness,
    };
    surviving_bricks(
        Arc::clone(&tape),
        &grid,
        (top, descent),
        [0, 0, 0],
        &mut bricks,
        cancel,
    );
    let root = tape;
    stop()?;
    bricks.sort_by_key(|s| (s.node[2], s.node[1], s.node[0]));
    let done = AtomicUsize::new(0);
    let total = bricks.len().max(1);
    let outs: Vec<Option<BrickOut>> = bricks
        .par_iter_mut()
        .map(|s| {
            if cancel() {
                return None;
            }
            if let Some((_, leaf)) = s.leaf.as_mut() {
                return Some(std::mem::take(leaf));
            }
            let tapes = (s.tape.as_ref(), s.ring_tape.as_ref());
            let o = mesh_brick(tapes, &grid, s.node, (opts.sharpness, opts.tolerance));
            progress(done.fetch_add(1, Ordering::Relaxed) as f32 / total as f32);
            Some(o)
        })
        .collect();
    if cancel() || outs.iter().any(|o| o.is_none()) {
        return Err(MeshError::Cancelled);
    }
    let outs: Vec<BrickOut> = outs.into_iter().flatten().collect();
    let Joined {
        mut positions,
        mut normals,
        mut quads,
        mut refs,
        mut pinched,
        offsets,
    } = join_bricks(&outs);
    let mut stats = MeshStats {
        bricks_total: grid.bricks.iter().product(),
        bricks_meshed: outs.len(),
        cells_with_surface: 0,
        leaves: 0,
        vertices_split: 0,
        thin_cells: 0,
        thin_region: None,
        crease_flips: 0,
        splits: 0,
        collapses: 0,
        deviation: 0.0,
    };
    let doubled = outs.iter().any(|o| o.doubled);
    for o in &outs {
        stats.cells_with_surface += o.cells;
        stats.leaves += o.leaves;
        stats.add_missed(&grid, &o.missed);
    }
    // Freed before the adaptive passes, which allocate their own.
    drop(outs);
    stop()?;
    refs.par_sort_unstable_by_key(|r| (r.0, r.1));
    stop()?;
    // Edges on bricks' faces: any group left incomplete cannot happen when
    // every cell around a crossed edge survived pruning (intervals are
    // conservative), and is skipped rather than panicked on.
    let mut cancelled = Vec::new();
    quads.extend(take_quads(&mut refs, &mut cancelled));
    // Each cancelled corner with the brick it belongs to.
    let brick_of = |v: u32| (offsets.partition_point(|&first| first <= v) - 1) as u32;
    pinched.extend(cancelled.into_iter().map(|v| (v, brick_of(v))));
    let mut triangles: Vec<[u32; 3]> = quads
        .par_iter()
        .with_min_len(4096)
        .flat_map_iter(|&q| quad_triangles(&positions, &normals, q))
        .collect();
    stop()?;
    pinched.sort_unstable();
    pinched.dedup_by_key(|c| c.0);
    let tapes: Vec<&Tape> = bricks.iter().map(|s| s.tape.as_ref()).collect();
    stats.vertices_split = pinch::split_pinched_vertices(
        &mut positions,
        &mut normals,
        &mut triangles,
        (&pinched, &brick_of),
        &tapes,
        &pinch::Cells {
            origin: grid.origin,
            h: grid.h,
        },
    );
    stop()?;
    let tapes = adaptive::RegionTapes::new(
        &root,
        covered_bricks(&bricks, &grid),
        (grid.origin, grid.h * B as f64, grid.bricks),
    );
    if opts.tolerance > 0.0 {
        let mesh = (&mut positions, &mut normals, &mut triangles);
        let adapted = adaptive::adapt(&tapes, mesh, (opts.tolerance, grid.h), cancel)
            .ok_or(MeshError::Cancelled)?;
        stats.crease_flips = adapted.crease_flips;
        (stats.splits, stats.collapses, stats.deviation) =
            (adapted.splits, adapted.collapses, adapted.deviation);
    } else {
        stats.crease_flips =
            crate::crease::straighten_creases(&tapes, &positions, &mut triangles, grid.h, cancel);
        stop()?;
    }
    if doubled {
        // Vertices whose only quads cancelled (see `brick::take_quads`).
        adaptive::compact(&mut positions, &mut normals, &mut triangles);
    }
    let mut g =
        Geometry::from_triangles(positions, &triangles).map_err(|_| MeshError::BadBounds)?;
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(normals), TypeInfo::Normal),
    )
    .map_err(|_| MeshError::BadBounds)?;
    progress(1.0);
    Ok((g, stats))
}

/// Every brick the octree's leaves cover (a coarse leaf several) with its
/// leaf's tape, keyed (z, y, x) in ascending order.
fn covered_bricks<'a>(leaves: &'a [Surviving], grid: &Grid) -> Vec<([usize; 3], &'a Tape)> {
    let mut covered: Vec<([usize; 3], &Tape)> = Vec::with_capacity(leaves.len());
    for s in leaves {
        let span = s.leaf.as_ref().map_or(1, |(level, _)| 1usize << level);
        for d in 0..span * span * span {
            let b = [
                s.node[0] + d % span,
                s.node[1] + d / span % span,
                s.node[2] + d / (span * span),
            ];
            if (0..3).all(|a| b[a] < grid.bricks[a]) {
                covered.push(([b[2], b[1], b[0]], s.tape.as_ref()));
            }
        }
    }
    covered.sort_by_key(|c| c.0);
    covered
}

/// The triangles of a dual quad: two, split along the diagonal
/// `split_along_02` picks; where adaptive output merged cells, repeated
/// corners are neighbours around the edge and three distinct make one
/// triangle (fewer make none).
fn quad_triangles(
    positions: &[Vec3],
    normals: &[Vec3],
    q: [u32; 4],
) -> impl Iterator<Item = [u32; 3]> {
    let (pair, count) = if q[0] == q[1] || q[1] == q[2] || q[2] == q[3] || q[3] == q[0] {
        let mut distinct = [0; 4];
        let mut n = 0;
        for i in 0..4 {
            if q[i] != q[(i + 3) % 4] {
                distinct[n] = q[i];
                n += 1;
            }
        }
        let [a, b, c, _] = distinct;
        ([[a, b, c]; 2], usize::from(n == 3))
    } else if split_along_02(positions, normals, q) {
        ([[q[0], q[1], q[2]], [q[0], q[2], q[3]]], 2)
    } else {
        ([[q[0], q[1], q[3]], [q[1], q[2], q[3]]], 2)
    };
    pair.into_iter().take(count)
}

/// Whether a quad splits along its diagonal q0-q2 (else q1-q3): the split
/// whose triangles face most nearly the way their corners' normals do (so a
/// quad across a sharp crease splits along the crease, not across it),
/// the shorter diagonal when both agree as well.
fn split_along_02(positions: &[Vec3], normals: &[Vec3], q: [u32; 4]) -> bool {
    let p = |i: usize| positions[q[i] as usize];
    let n = |i: usize| normals[q[i] as usize];
    let disagreement = |tris: [[usize; 3]; 2]| -> f32 {
        tris.iter()
            .map(|t| {
                let face = (p(t[1]) - p(t[0]))
                    .cross(p(t[2]) - p(t[0]))
                    .normalize_or_zero();
                t.iter().map(|&i| 1.0 - face.dot(n(i))).sum::<f32>()
            })
            .sum()
    };
    let along_02 = disagreement([[0, 1, 2], [0, 2, 3]]);
    let along_13 = disagreement([[0, 1, 3], [1, 2, 3]]);
    // Agreeing to within this, the shorter diagonal (as on smooth surfaces).
    const ALIKE: f32 = 0.05;
    if (along_02 - along_13).abs() > ALIKE {
        return along_02 < along_13;
    }
    (p(0) - p(2)).length_squared() <= (p(1) - p(3)).length_squared()
}

/// Evaluates a field at points (the "sample" path: scatter inside, colouring).
pub fn sample(field: &Field, points: &[Vec3]) -> Vec<f32> {
    let tape = Tape::compile(field);
    let chunks: Vec<Vec<f32>> = points
        .par_chunks(1 << 14)
        .map(|c| {
            let xs: Vec<f32> = c.iter().map(|p| p.x).collect();
            let ys: Vec<f32> = c.iter().map(|p| p.y).collect();
            let zs: Vec<f32> = c.iter().map(|p| p.z).collect();
            let mut out = vec![0.0; c.len()];
            BatchEval::new(&tape).eval(&xs, &ys, &zs, &mut out);
            out
        })
        .collect();
    chunks.concat()
}
