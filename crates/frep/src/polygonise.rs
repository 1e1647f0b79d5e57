//! The polygoniser: an octree over bricks of 8^3 cells pruned by interval
//! arithmetic (each level evaluates a tape simplified for its region), then
//! dual contouring in the surviving bricks: one vertex per connected surface
//! component of a cell (faces paired by the asymptotic decider, so the mesh is
//! closed; vertices shared by two sheets are split afterwards, see `pinch`),
//! placed by a QEF
//! over the crossings' tangent planes so sharp edges and corners survive,
//! with analytic normals from the gradient.

use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use rayon::prelude::*;

use crate::eval::{BatchEval, BatchGradEval, Grad, IntervalEval, PointEval};
use crate::field::Field;
use crate::interval::Interval;
use crate::pinch;
use crate::qef::Qef;
use crate::shapes;
use crate::tape::Tape;

/// Cells per brick edge.
const B: usize = 8;

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
}

impl MeshOptions {
    pub fn new(min: [f64; 3], max: [f64; 3], depth: u32) -> MeshOptions {
        MeshOptions {
            min,
            max,
            depth,
            sharpness: 0.05,
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

/// Counters of a meshing run (for tests and benchmarks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshStats {
    pub bricks_total: usize,
    pub bricks_meshed: usize,
    pub cells_with_surface: usize,
    /// Vertices added where one vertex was shared by two sheets.
    pub vertices_split: usize,
}

struct Grid {
    origin: [f64; 3],
    h: f64,
    /// Corner count per axis (cells + 1).
    corners: [usize; 3],
    bricks: [usize; 3],
}

impl Grid {
    fn point(&self, c: [usize; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.origin[k] + c[k] as f64 * self.h)
    }
}

struct BrickOut {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// (edge key, slot around the edge, local vertex, outward is +axis).
    refs: Vec<(u64, u8, u32, bool)>,
    /// Local vertices whose component holds both crossings of an ambiguous
    /// face: the only ones that can be pinched (see `pinch`).
    pinched: Vec<u32>,
    cells: usize,
}

fn edge_key(axis: usize, c: [usize; 3]) -> u64 {
    (axis as u64) << 60 | (c[0] as u64) << 40 | (c[1] as u64) << 20 | c[2] as u64
}

/// Local edge id (0..12) of the cube edge along `axis` whose lower corner
/// has offsets `p` (0 or 1 on the other axes).
fn local_edge(axis: usize, p: [usize; 3]) -> usize {
    axis * 4 + p[(axis + 1) % 3] + 2 * p[(axis + 2) % 3]
}

fn corner_index(p: [usize; 3]) -> usize {
    p[0] + 2 * p[1] + 4 * p[2]
}

/// Pairs of local edges joined across each face, from the asymptotic
/// decider; for each ambiguous face, one edge of each of its two segments.
fn face_pairs(v: &[f32; 8], pairs: &mut Vec<(usize, usize)>, ambiguous: &mut Vec<(usize, usize)>) {
    for axis in 0..3 {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2 {
            // Corners in cyclic order (0,0), (1,0), (1,1), (0,1) over (u, w).
            let cyc = [(0, 0), (1, 0), (1, 1), (0, 1)];
            let mut pos = [[0usize; 3]; 4];
            for (i, (a, b)) in cyc.iter().enumerate() {
                pos[i][axis] = side;
                pos[i][u] = *a;
                pos[i][w] = *b;
            }
            let f: [f32; 4] = pos.map(|p| v[corner_index(p)]);
            let inside = f.map(|x| x >= 0.0);
            // Edge i joins cyclic corners i and i+1.
            let edge = |i: usize| {
                let (p, q) = (pos[i], pos[(i + 1) % 4]);
                let ax = (0..3).find(|&k| p[k] != q[k]).expect("adjacent corners");
                let lo = if p[ax] < q[ax] { p } else { q };
                local_edge(ax, lo)
            };
            let crossed: Vec<usize> = (0..4)
                .filter(|&i| inside[i] != inside[(i + 1) % 4])
                .collect();
            match crossed.len() {
                2 => pairs.push((edge(crossed[0]), edge(crossed[1]))),
                4 => {
                    ambiguous.push((edge(0), edge(2)));
                    let denom = f[0] + f[2] - f[1] - f[3];
                    let saddle = if denom != 0.0 {
                        (f[0] * f[2] - f[1] * f[3]) / denom
                    } else {
                        (f[0] + f[1] + f[2] + f[3]) * 0.25
                    };
                    if (saddle >= 0.0) == inside[0] {
                        // Corners 0 and 2 connect through the face: 1 and 3 are cut off.
                        pairs.push((edge(0), edge(1)));
                        pairs.push((edge(2), edge(3)));
                    } else {
                        pairs.push((edge(3), edge(0)));
                        pairs.push((edge(1), edge(2)));
                    }
                }
                _ => {}
            }
        }
    }
}

fn find(parent: &mut [usize; 12], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// A crossed grid edge being bracketed: the surface lies between `t0` and
/// `t1` (parameters along a-b), where the field has values `f0` and `f1`.
struct Root {
    key: u64,
    a: [f64; 3],
    b: [f64; 3],
    t0: f64,
    f0: f64,
    t1: f64,
    f1: f64,
    /// Which end moved last (-1 low, 1 high): Illinois halves the other.
    side: i8,
}

impl Root {
    fn guess(&self) -> f64 {
        let t = self.t0 + (self.t1 - self.t0) * (self.f0 / (self.f0 - self.f1));
        if t.is_finite() && t > self.t0 && t < self.t1 {
            t
        } else {
            0.5 * (self.t0 + self.t1)
        }
    }

    /// Narrows the bracket with the value `ft` at `t`; true once converged.
    fn update(&mut self, t: f64, ft: f64) -> bool {
        if ft == 0.0 {
            (self.t0, self.t1) = (t, t);
            return true;
        }
        if (ft >= 0.0) == (self.f0 >= 0.0) {
            (self.t0, self.f0) = (t, ft);
            if self.side == -1 {
                self.f1 *= 0.5;
            }
            self.side = -1;
        } else {
            (self.t1, self.f1) = (t, ft);
            if self.side == 1 {
                self.f0 *= 0.5;
            }
            self.side = 1;
        }
        self.t1 - self.t0 < 1e-6
    }

    fn point(&self) -> [f64; 3] {
        let t = if self.t1 - self.t0 < 1e-6 {
            0.5 * (self.t0 + self.t1)
        } else {
            self.guess()
        };
        std::array::from_fn(|k| self.a[k] + (self.b[k] - self.a[k]) * t)
    }
}

/// Where the surface crosses each edge: Illinois false position (fast on
/// smooth fields, and it cannot stall on the flat stretches of distance
/// fields) run on all edges of a brick at once, one batch per step, on the
/// same f32 evaluator that classified the corners (so brackets agree).
fn solve_roots(batch: &mut BatchEval, roots: &mut [Root]) {
    let mut active: Vec<usize> = (0..roots.len()).collect();
    let (mut xs, mut ys, mut zs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut ts, mut values) = (Vec::new(), Vec::new());
    for _ in 0..24 {
        if active.is_empty() {
            break;
        }
        xs.clear();
        ys.clear();
        zs.clear();
        ts.clear();
        for &i in &active {
            let r = &roots[i];
            let t = r.guess();
            ts.push(t);
            xs.push((r.a[0] + (r.b[0] - r.a[0]) * t) as f32);
            ys.push((r.a[1] + (r.b[1] - r.a[1]) * t) as f32);
            zs.push((r.a[2] + (r.b[2] - r.a[2]) * t) as f32);
        }
        values.resize(xs.len(), 0.0);
        batch.eval(&xs, &ys, &zs, &mut values);
        let mut k = 0;
        active.retain(|&i| {
            let done = roots[i].update(ts[k], values[k] as f64);
            k += 1;
            !done
        });
    }
}

/// `-grad f / |grad f|`; central differences where the gradient is
/// singular (a kink exactly at the point), the segment direction never.
fn outward_normal(point: &mut PointEval, gradient: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let unit = |g: [f64; 3]| {
        let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        (len > 0.0 && len.is_finite()).then(|| g.map(|x| -x / len))
    };
    if let Some(n) = unit(gradient) {
        return n;
    }
    let h = 1e-7 * (1.0 + p.iter().fold(0.0f64, |m, x| m.max(x.abs())));
    let g: [f64; 3] = std::array::from_fn(|k| {
        let (mut a, mut b) = (p, p);
        a[k] -= h;
        b[k] += h;
        (point.eval(b) - point.eval(a)) / (2.0 * h)
    });
    unit(g).unwrap_or([0.0, 1.0, 0.0])
}

/// Outward unit normals at many points: exact gradients in one batch, the
/// scalar fallback only where a gradient vanishes.
fn outward_normals(
    point: &mut PointEval,
    grads: &mut BatchGradEval,
    points: &[[f64; 3]],
) -> Vec<[f64; 3]> {
    let mut g = vec![Grad::default(); points.len()];
    grads.eval(points, &mut g);
    points
        .iter()
        .zip(&g)
        .map(|(p, g)| outward_normal(point, g.d, *p))
        .collect()
}

fn mesh_brick(tape: &Tape, grid: &Grid, brick: [usize; 3], sharpness: f64) -> BrickOut {
    let base = brick.map(|b| b * B);
    let m = B + 1;
    // Corner values of the brick, in one batch.
    let mut xs = Vec::with_capacity(m * m * m);
    let mut ys = Vec::with_capacity(m * m * m);
    let mut zs = Vec::with_capacity(m * m * m);
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                let p = grid.point([base[0] + i, base[1] + j, base[2] + k]);
                xs.push(p[0] as f32);
                ys.push(p[1] as f32);
                zs.push(p[2] as f32);
            }
        }
    }
    let mut values = vec![0.0f32; xs.len()];
    let mut batch = BatchEval::new(tape);
    batch.eval(&xs, &ys, &zs, &mut values);
    let at = |c: [usize; 3]| values[c[0] + m * (c[1] + m * c[2])];
    let mut point = PointEval::new(tape);
    let mut grads = BatchGradEval::new(tape);
    let mut vertex_points: Vec<[f64; 3]> = Vec::new();
    // Every crossed edge of the brick, solved together.
    let mut roots = Vec::new();
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                let c = [i, j, k];
                let v0 = at(c);
                for axis in 0..3 {
                    if c[axis] + 1 >= m {
                        continue;
                    }
                    let mut d = c;
                    d[axis] += 1;
                    let v1 = at(d);
                    if (v0 >= 0.0) != (v1 >= 0.0) {
                        let lo = std::array::from_fn(|q| base[q] + c[q]);
                        let hi = std::array::from_fn(|q| base[q] + d[q]);
                        roots.push(Root {
                            key: edge_key(axis, lo),
                            a: grid.point(lo),
                            b: grid.point(hi),
                            t0: 0.0,
                            f0: v0 as f64,
                            t1: 1.0,
                            f1: v1 as f64,
                            side: 0,
                        });
                    }
                }
            }
        }
    }
    solve_roots(&mut batch, &mut roots);
    let root_points: Vec<[f64; 3]> = roots.iter().map(Root::point).collect();
    let root_normals = outward_normals(&mut point, &mut grads, &root_points);
    let crossings: HashMap<u64, ([f64; 3], [f64; 3])> = roots
        .iter()
        .zip(root_points.into_iter().zip(root_normals))
        .map(|(r, pn)| (r.key, pn))
        .collect();
    let mut out = BrickOut {
        positions: Vec::new(),
        normals: Vec::new(),
        refs: Vec::new(),
        pinched: Vec::new(),
        cells: 0,
    };
    let mut pairs = Vec::with_capacity(12);
    let mut ambiguous = Vec::with_capacity(6);
    for k in 0..B {
        for j in 0..B {
            for i in 0..B {
                let cell = [base[0] + i, base[1] + j, base[2] + k];
                if (0..3).any(|a| cell[a] + 1 >= grid.corners[a]) {
                    continue;
                }
                let v: [f32; 8] =
                    std::array::from_fn(|c| at([i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)]));
                let inside = v.map(|x| x >= 0.0);
                if inside.iter().all(|&s| s) || inside.iter().all(|&s| !s) {
                    continue;
                }
                out.cells += 1;
                // Crossed edges and their connected components.
                let mut crossed = [false; 12];
                for axis in 0..3 {
                    for c in 0..8 {
                        let p = [c & 1, c >> 1 & 1, c >> 2 & 1];
                        if p[axis] == 0 {
                            let mut q = p;
                            q[axis] = 1;
                            crossed[local_edge(axis, p)] =
                                inside[corner_index(p)] != inside[corner_index(q)];
                        }
                    }
                }
                pairs.clear();
                ambiguous.clear();
                face_pairs(&v, &mut pairs, &mut ambiguous);
                let mut parent: [usize; 12] = std::array::from_fn(|e| e);
                for &(a, b) in &pairs {
                    let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                    parent[ra] = rb;
                }
                let mut component_vertex: [u32; 12] = [u32::MAX; 12];
                let mut qefs: Vec<(usize, Qef)> = Vec::new();
                let mut edge_info: Vec<(usize, u64, u8, bool)> = Vec::new();
                for axis in 0..3 {
                    for c in 0..8 {
                        let p = [c & 1, c >> 1 & 1, c >> 2 & 1];
                        if p[axis] != 0 || !crossed[local_edge(axis, p)] {
                            continue;
                        }
                        let e = local_edge(axis, p);
                        let lo = [cell[0] + p[0], cell[1] + p[1], cell[2] + p[2]];
                        let key = edge_key(axis, lo);
                        // Every crossed edge of the brick was solved above.
                        let Some(&(cp, cn)) = crossings.get(&key) else {
                            continue;
                        };
                        let root = find(&mut parent, e);
                        match qefs.iter_mut().find(|(r, _)| *r == root) {
                            Some((_, q)) => q.add(cp, cn),
                            None => {
                                let mut q = Qef::default();
                                q.add(cp, cn);
                                qefs.push((root, q));
                            }
                        }
                        // Slot of this cell around the edge, counter-clockwise about +axis.
                        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                        let slot = match (p[u] == 0, p[w] == 0) {
                            (false, false) => 0,
                            (true, false) => 1,
                            (true, true) => 2,
                            (false, true) => 3,
                        };
                        let outward_plus = inside[corner_index(p)];
                        edge_info.push((e, key, slot, outward_plus));
                    }
                }
                let cmin = grid.point(cell);
                let cmax = grid.point([cell[0] + 1, cell[1] + 1, cell[2] + 1]);
                for (root, q) in &qefs {
                    let mut x = q.solve(sharpness);
                    if !x.iter().all(|c| c.is_finite()) {
                        x = q.mass_point();
                    }
                    // Strictly inside the cell: a feature on a cell boundary (a
                    // cone's apex on a grid line) must not put the vertices of
                    // neighbouring cells at one point, or the mesh pinches there.
                    let margin = 1e-4 * grid.h;
                    let outside =
                        (0..3).any(|a| x[a] < cmin[a] + margin || x[a] > cmax[a] - margin);
                    if outside && qefs.len() > 1 {
                        // Clamped, two components could meet at one corner of
                        // the cell; their mass points are distinct and inside.
                        x = q.mass_point();
                    }
                    for a in 0..3 {
                        x[a] = x[a].clamp(cmin[a] + margin, cmax[a] - margin);
                    }
                    component_vertex[*root] = out.positions.len() as u32;
                    out.positions
                        .push(Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32));
                    vertex_points.push(x);
                }
                for &(a, b) in &ambiguous {
                    let root = find(&mut parent, a);
                    if root == find(&mut parent, b)
                        && !out.pinched.contains(&component_vertex[root])
                    {
                        out.pinched.push(component_vertex[root]);
                    }
                }
                for (e, key, slot, plus) in edge_info {
                    let root = find(&mut parent, e);
                    out.refs.push((key, slot, component_vertex[root], plus));
                }
            }
        }
    }
    out.normals = outward_normals(&mut point, &mut grads, &vertex_points)
        .into_iter()
        .map(|n| Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32))
        .collect();
    out
}

/// Octree nodes of `stop` levels above the bricks (0: bricks) that may hold
/// surface, each with the tape simplified for it.
fn surviving_bricks(
    tape: Arc<Tape>,
    grid: &Grid,
    (level, stop): (u32, u32),
    b: [usize; 3],
    out: &mut Vec<([usize; 3], Arc<Tape>)>,
    cancel: &(dyn Fn() -> bool + Sync),
) {
    if cancel() || (0..3).any(|a| b[a] >= grid.bricks[a]) {
        return;
    }
    let span = (1usize << level) * B;
    let lo = grid.point([b[0] * B, b[1] * B, b[2] * B]);
    let hi = grid.point([b[0] * B + span, b[1] * B + span, b[2] * B + span]);
    let mut iv = IntervalEval::new(&tape);
    let r = iv.eval(
        Interval::new(lo[0], hi[0]),
        Interval::new(lo[1], hi[1]),
        Interval::new(lo[2], hi[2]),
    );
    if !r.has_nan() && (r.lo > 0.0 || r.hi < 0.0) {
        return;
    }
    let simplified = Arc::new(tape.simplify(iv.choices()));
    if level <= stop {
        out.push((b, simplified));
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
    if level >= 3 {
        let parts: Vec<Vec<([usize; 3], Arc<Tape>)>> = children
            .par_iter()
            .map(|c| {
                let mut v = Vec::new();
                let levels = (level - 1, stop);
                surviving_bricks(Arc::clone(&simplified), grid, levels, *c, &mut v, cancel);
                v
            })
            .collect();
        out.extend(parts.into_iter().flatten());
    } else {
        for c in children {
            surviving_bricks(
                Arc::clone(&simplified),
                grid,
                (level - 1, stop),
                c,
                out,
                cancel,
            );
        }
    }
}

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
    };
    let center: [f64; 3] = std::array::from_fn(|k| 0.5 * (opts.min[k] + opts.max[k]));
    let half: [f64; 3] = std::array::from_fn(|k| 0.5 * size[k]);
    let clipped = field.min(shapes::block(center, half));
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
    surviving_bricks(tape, &grid, (top, stop), [0, 0, 0], &mut nodes, cancel);
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
    surviving_bricks(tape, &grid, (top, 0), [0, 0, 0], &mut bricks, cancel);
    stop()?;
    bricks.sort_by_key(|(b, _)| (b[2], b[1], b[0]));
    let done = AtomicUsize::new(0);
    let total = bricks.len().max(1);
    let outs: Vec<Option<BrickOut>> = bricks
        .par_iter()
        .map(|(b, t)| {
            if cancel() {
                return None;
            }
            let o = mesh_brick(t, &grid, *b, opts.sharpness);
            progress(done.fetch_add(1, Ordering::Relaxed) as f32 / total as f32);
            Some(o)
        })
        .collect();
    if cancel() || outs.iter().any(|o| o.is_none()) {
        return Err(MeshError::Cancelled);
    }
    let outs: Vec<BrickOut> = outs.into_iter().flatten().collect();
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut refs: Vec<(u64, u8, u32, bool)> = Vec::new();
    // Pinch candidates with the brick whose (simplified) tape is valid there.
    let mut pinched: Vec<(u32, u32)> = Vec::new();
    let mut stats = MeshStats {
        bricks_total: grid.bricks.iter().product(),
        bricks_meshed: outs.len(),
        cells_with_surface: 0,
        vertices_split: 0,
    };
    for (brick, o) in outs.into_iter().enumerate() {
        let offset = positions.len() as u32;
        positions.extend(o.positions);
        normals.extend(o.normals);
        refs.extend(o.refs.into_iter().map(|(k, s, v, p)| (k, s, v + offset, p)));
        pinched.extend(o.pinched.into_iter().map(|v| (v + offset, brick as u32)));
        stats.cells_with_surface += o.cells;
    }
    stop()?;
    refs.par_sort_unstable_by_key(|r| (r.0, r.1));
    stop()?;
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(refs.len() / 2);
    for group in refs.chunk_by(|a, b| a.0 == b.0) {
        if group.len() != 4 || group.iter().enumerate().any(|(i, r)| r.1 as usize != i) {
            // Cannot happen when every cell around a crossed edge survived
            // pruning (intervals are conservative); skip rather than panic.
            continue;
        }
        let mut q = [group[0].2, group[1].2, group[2].2, group[3].2];
        if !group[0].3 {
            q.reverse();
        }
        // Split along the shorter diagonal.
        let d02 = (positions[q[0] as usize] - positions[q[2] as usize]).length_squared();
        let d13 = (positions[q[1] as usize] - positions[q[3] as usize]).length_squared();
        if d02 <= d13 {
            triangles.push([q[0], q[1], q[2]]);
            triangles.push([q[0], q[2], q[3]]);
        } else {
            triangles.push([q[0], q[1], q[3]]);
            triangles.push([q[1], q[2], q[3]]);
        }
    }
    stop()?;
    pinched.sort_unstable();
    pinched.dedup_by_key(|c| c.0);
    let tapes: Vec<&Tape> = bricks.iter().map(|(_, t)| t.as_ref()).collect();
    stats.vertices_split = pinch::split_pinched_vertices(
        &mut positions,
        &mut normals,
        &mut triangles,
        &pinched,
        &tapes,
        &pinch::Cells {
            origin: grid.origin,
            h: grid.h,
        },
    );
    stop()?;
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
