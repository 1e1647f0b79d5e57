//! Dual contouring of one brick of 8^3 cells: corner samples, edge
//! crossings solved in batches (both crossings of edges crossed twice, see
//! `double`), one vertex per connected surface component of a cell placed
//! on its features (see `features`), and the dual-edge references from
//! which the mesher builds quads.

use geode_geo::glam::Vec3;
use geode_geo::ops::renumber_used;

use crate::cell::{find, Grid, B, CELL_EDGES, SECOND};
use crate::cluster::{merge_cells, Clustering, Node};
use crate::components::{CellAt, Components};
use crate::double;
use crate::features::{self, Plane, Proposal};
use crate::inner_leaves::InnerLeaves;
use crate::lattice::{outward_normals, Crossings, Lattice};
use crate::parts::par_fill;
use crate::qef::Qef;
use crate::recovery::{
    cell_box, cell_slot, recover_features, verify_features, Candidate, CellTable, Check,
};
use crate::thin;
use geode_frep::eval::{BatchEval, BatchGradEval, GradEval, PointEval};
use geode_frep::tape::Tape;

#[derive(Default)]
pub(crate) struct BrickOut {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// The dual quads of the edges all four of whose cells are in the
    /// brick, over local vertices, oriented outward.
    pub quads: Vec<[u32; 4]>,
    /// The cells' references to the other crossed edges (their quads are
    /// made once every brick is meshed).
    pub refs: Vec<EdgeRef>,
    /// Local vertices whose component holds both crossings of an ambiguous
    /// face: the only ones that can be pinched (see `pinch`).
    pub pinched: Vec<u32>,
    pub cells: usize,
    /// Coarse leaves (adaptive output: see `coarse` and `inner_leaves`),
    /// each one vertex for the cells it covers, which `cells` leaves out.
    pub leaves: usize,
    /// Whether some edge of the brick is crossed twice: its quads may have
    /// cancelled, leaving vertices no quad uses.
    pub doubled: bool,
    /// Cells holding surface that none of their corners shows (see `thin`).
    pub missed: Vec<[usize; 3]>,
}

/// A cell's reference to a crossed grid edge: (edge key, slot around the
/// edge, local vertex, outward is +axis).
pub(crate) type EdgeRef = (u64, u8, u32, bool);

/// The dual quads, oriented outward, of the edges all four of whose cells
/// `refs` (sorted by key and slot) holds; `refs` keeps the others. The two
/// quads of an edge crossed twice cancel where they join the same four
/// vertices (every cell around it holds both crossings in one component:
/// a ridge grazing the edge, finer than the grid can show, whose planes
/// still placed those vertices).
/// The corners of cancelled quads go to `cancelled`: a vertex that kept
/// quads besides them may hold two fans now, which `pinch` splits.
pub(crate) fn take_quads(refs: &mut Vec<EdgeRef>, cancelled: &mut Vec<u32>) -> Vec<[u32; 4]> {
    let mut quads: Vec<[u32; 4]> = Vec::with_capacity(refs.len() / 4);
    let mut rest = Vec::new();
    // The key and quad of the first crossing of the last edge crossed twice.
    let mut first: Option<(u64, [u32; 4])> = None;
    for group in refs.chunk_by(|a, b| a.0 == b.0) {
        if group.len() == 4 && group.iter().enumerate().all(|(i, r)| r.1 as usize == i) {
            let mut q = [group[0].2, group[1].2, group[2].2, group[3].2];
            if !group[0].3 {
                q.reverse();
            }
            let key = group[0].0;
            if key & 1 == 1 {
                if let Some((k, p)) = first {
                    let mut both = (p, q);
                    both.0.sort_unstable();
                    both.1.sort_unstable();
                    if k == key - 1 && both.0 == both.1 {
                        quads.pop();
                        cancelled.extend_from_slice(&both.0);
                        first = None;
                        continue;
                    }
                }
            }
            first = Some((key, q));
            quads.push(q);
        } else {
            rest.extend_from_slice(group);
        }
    }
    *refs = rest;
    quads
}

/// Every brick's output in one mesh (bricks in order).
pub(crate) struct Joined {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub quads: Vec<[u32; 4]>,
    pub refs: Vec<EdgeRef>,
    /// Pinch candidates with the brick whose (simplified) tape is valid there.
    pub pinched: Vec<(u32, u32)>,
    /// Each brick's first vertex.
    pub offsets: Vec<u32>,
}

/// Joins the bricks' outputs in their order, each brick's vertex indices
/// moved past the vertices of the bricks before it; bricks in parallel.
pub(crate) fn join_bricks(outs: &[BrickOut]) -> Joined {
    let lens = |part: fn(&BrickOut) -> usize| outs.iter().map(part).collect::<Vec<_>>();
    let offsets: Vec<u32> = outs
        .iter()
        .scan(0u32, |next, o| {
            let at = *next;
            *next += o.positions.len() as u32;
            Some(at)
        })
        .collect();
    let vertex_lens = lens(|o| o.positions.len());
    Joined {
        positions: par_fill(&vertex_lens, |b, s| s.copy_from_slice(&outs[b].positions)),
        normals: par_fill(&vertex_lens, |b, s| s.copy_from_slice(&outs[b].normals)),
        quads: par_fill(&lens(|o| o.quads.len()), |b, s| {
            for (to, q) in s.iter_mut().zip(&outs[b].quads) {
                *to = q.map(|v| v + offsets[b]);
            }
        }),
        refs: par_fill(&lens(|o| o.refs.len()), |b, s| {
            for (to, &(k, slot, v, outward)) in s.iter_mut().zip(&outs[b].refs) {
                *to = (k, slot, v + offsets[b], outward);
            }
        }),
        pinched: par_fill(&lens(|o| o.pinched.len()), |b, s| {
            for (to, &v) in s.iter_mut().zip(&outs[b].pinched) {
                *to = (v + offsets[b], b as u32);
            }
        }),
        offsets,
    }
}

/// Meshes one brick with `tape` (valid over the brick) and `ring_tape`
/// (valid one cell beyond it, for feature recovery).
pub(crate) fn mesh_brick(
    (tape, ring_tape): (&Tape, &Tape),
    grid: &Grid,
    brick: [usize; 3],
    (sharpness, tolerance): (f64, f64),
) -> BrickOut {
    let base = brick.map(|b| b * B);
    let mut batch = BatchEval::new(tape);
    let mut point = PointEval::new(tape);
    let mut grads = BatchGradEval::new(tape);
    let mut grad = GradEval::new(tape);
    let mut lattice = Lattice::sample(&mut batch, grid, base);
    let missed = thin::missed_cells((&mut batch, &mut grads), &lattice, grid, base);
    let mut crossings = Crossings::new();
    let doubles = double::doubly_crossed_edges(&mut batch, &lattice, grid);
    // Adaptive output: octants proved one sheet leave their inner edges unsolved.
    let mut leaves = if tolerance > 0.0 {
        InnerLeaves::candidates(grid, base, &lattice, &doubles)
    } else {
        InnerLeaves::none()
    };
    let range = (0, B as isize);
    let roots = lattice.crossed_edges_where(grid, range, |axis, c| !leaves.interior(axis, c));
    crossings.add(&mut batch, &mut point, &mut grads, roots);
    crossings.add_doubles(&mut batch, &mut point, &mut grads, doubles);
    let tolerances = (sharpness, tolerance);
    let mut any_failed = leaves.fit(tape, grid, base, &crossings, tolerances);
    while any_failed {
        // Candidates whose vertex did not fit try their octants; the edges
        // none of those holds are solved for them (or for the brick's cells).
        let nodes = leaves.split_failed(grid, base, &lattice);
        let exposed = |axis, c| leaves.exposed(&nodes, axis, c);
        let roots = lattice.crossed_edges_where(grid, range, exposed);
        crossings.add(&mut batch, &mut point, &mut grads, roots);
        any_failed = leaves.fit(tape, grid, base, &crossings, tolerances);
    }
    // Cells meshed through edges crossed twice (no longer missed).
    let mut doubled_cells: Vec<[usize; 3]> = Vec::new();
    // Sized from the crossed edges: each is referenced by the (up to) four
    // cells around it, and a brick has about as many vertices as edges.
    let edges = crossings.planes.len();
    let mut out = BrickOut {
        positions: Vec::with_capacity(edges),
        normals: Vec::new(),
        quads: Vec::new(),
        refs: Vec::with_capacity(4 * edges),
        pinched: Vec::new(),
        cells: 0,
        leaves: 0,
        doubled: crossings.has_doubles(),
        missed,
    };
    let mut vertex_points: Vec<[f64; 3]> = Vec::with_capacity(edges);
    let mut cells = CellTable::new();
    let mut parts = Components::new();
    let mut scratch: Vec<Plane> = Vec::with_capacity(12);
    // Edge and corner points still to check against the field, all at once:
    // (vertex, its planes in `unverified_planes`, cell, candidate index).
    let mut unverified: Vec<Check> = Vec::new();
    let mut unverified_planes: Vec<Plane> = Vec::new();
    let mut candidates: Vec<Candidate> = Vec::new();
    // What each cell holds, for merging cells (adaptive output).
    let mut nodes = vec![Node::Empty; B * B * B];
    for k in 0..B {
        for j in 0..B {
            for i in 0..B {
                let cell = [base[0] + i, base[1] + j, base[2] + k];
                let node = i + B * (j + B * k);
                if (0..3).any(|a| cell[a] + 1 >= grid.corners[a]) || leaves.covers([i, j, k]) {
                    nodes[node] = Node::Blocked;
                    continue;
                }
                let local = [i as isize, j as isize, k as isize];
                let v: [f32; 8] = std::array::from_fn(|c| {
                    lattice.at([
                        local[0] + (c & 1) as isize,
                        local[1] + (c >> 1 & 1) as isize,
                        local[2] + (c >> 2 & 1) as isize,
                    ])
                });
                let signs = v
                    .iter()
                    .enumerate()
                    .fold(0u8, |m, (c, x)| m | ((*x >= 0.0) as u8) << c);
                let corner_of = |p: [usize; 3]| [i + p[0], j + p[1], k + p[2]].map(|x| x as isize);
                // Edges crossed twice show surface the corners do not.
                let doubled = crossings.has_doubles()
                    && CELL_EDGES
                        .iter()
                        .any(|e| crossings.get_double(e.axis, corner_of(e.offset)).is_some());
                if (signs == 0 || signs == u8::MAX) && !doubled {
                    continue;
                }
                out.cells += 1;
                if doubled {
                    doubled_cells.push(cell);
                }
                // The field at a face's centre settles an ambiguous face.
                let mut centre = |face: usize| {
                    let mut at = [i, j, k].map(|x| x as f64 + 0.5);
                    at[face / 2] += if face.is_multiple_of(2) { -0.5 } else { 0.5 };
                    let x =
                        std::array::from_fn(|a| grid.origin[a] + (base[a] as f64 + at[a]) * grid.h);
                    Some(point.eval(x) >= 0.0)
                };
                let at = CellAt {
                    values: v,
                    signs,
                    cell,
                    local,
                    doubled,
                };
                parts.build(&at, &crossings, &mut centre);
                let mut component_vertex = [u32::MAX; 2 * SECOND];
                let bounds = cell_box(grid, cell, 0);
                let slot = cell_slot(local);
                for root in &parts.roots {
                    let mut proposal = propose_from(
                        &parts.planes,
                        *root,
                        |_| true,
                        &mut scratch,
                        (sharpness, &bounds, grid.h),
                    );
                    let own = parts.planes.iter().filter(|p| p.0 == *root);
                    let kinds = own.fold([false; 2], |k, p| [k[0] | !p.2, k[1] | p.2]);
                    if matches!(proposal, Proposal::Unfit { .. }) && kinds == [true; 2] {
                        // The edges crossed twice show a feature beyond the
                        // cell (a solid's corner poking in); the cell's own
                        // sign changes place its vertex on what it holds.
                        proposal = propose_from(
                            &parts.planes,
                            *root,
                            |double| !double,
                            &mut scratch,
                            (sharpness, &bounds, grid.h),
                        );
                    }
                    let vertex = out.positions.len();
                    let placed = match proposal {
                        Proposal::Fits(placed) => placed,
                        Proposal::Verify(placed) => {
                            let planes = unverified_planes.len()..;
                            unverified_planes.extend_from_slice(&scratch);
                            let planes = planes.start..unverified_planes.len();
                            let candidate = (parts.roots.len() == 1).then_some(candidates.len());
                            unverified.push((vertex, planes, bounds, candidate));
                            placed
                        }
                        Proposal::Unfit {
                            rank,
                            achieved,
                            qef,
                            reduced,
                        } => {
                            // A crease or corner a hair beside the cell (past
                            // a grid edge, between two diagonal cells that
                            // share no dual edge) takes the vertex there.
                            let near = bounds.grown(BESIDE * grid.h);
                            let beside = (rank >= 2)
                                .then(|| beside_feature(&qef, rank, &near, grid, cell))
                                .flatten()
                                .filter(|x| features::verified(&grad.eval(*x), grid.h));
                            let point = if rank <= 1 {
                                // No feature: the surface curves within the cell.
                                features::smooth_on_surface(
                                    &qef, reduced, &bounds, &mut grad, grid.h,
                                )
                            } else if let Some(x) = beside {
                                x
                            } else {
                                features::best_on_surface(
                                    &scratch, &qef, reduced, sharpness, &bounds, &mut grad, grid.h,
                                )
                            };
                            features::Placed {
                                point,
                                rank,
                                achieved,
                                qef,
                            }
                        }
                    };
                    let x = placed.point;
                    let rank = if parts.roots.len() == 1 {
                        candidates.push(Candidate {
                            vertex: out.positions.len() as u32,
                            cell: [i as u8, j as u8, k as u8],
                            rank: placed.achieved as u8,
                        });
                        placed.rank as u8
                    } else {
                        0
                    };
                    cells.merge(slot, &placed.qef, rank);
                    nodes[node] =
                        if parts.roots.len() == 1 && parts.ambiguous.is_empty() && !doubled {
                            let vertex = out.positions.len() as u32;
                            Node::Surface {
                                vertex,
                                qef: placed.qef,
                                feature: None,
                            }
                        } else {
                            Node::Blocked
                        };
                    component_vertex[*root] = out.positions.len() as u32;
                    out.positions
                        .push(Vec3::new(x[0] as f32, x[1] as f32, x[2] as f32));
                    vertex_points.push(x);
                }
                let mut parent = parts.parent;
                for &(a, b) in &parts.ambiguous {
                    let root = find(&mut parent, a);
                    if root == find(&mut parent, b)
                        && !out.pinched.contains(&component_vertex[root])
                    {
                        out.pinched.push(component_vertex[root]);
                    }
                }
                for &(e, key, slot, plus) in &parts.refs {
                    let root = find(&mut parent, e);
                    out.refs.push((key, slot, component_vertex[root], plus));
                }
            }
        }
    }
    // Cells whose surface edges crossed twice show are no longer missed.
    // Both lists are in cell order (z, then y, then x).
    let order = |c: &[usize; 3]| (c[2], c[1], c[0]);
    out.missed.retain(|c| {
        doubled_cells
            .binary_search_by_key(&order(c), order)
            .is_err()
    });
    let checks = (unverified.as_slice(), unverified_planes.as_slice());
    let vertices = (out.positions.as_mut_slice(), vertex_points.as_mut_slice());
    verify_features(tape, grid, sharpness, checks, &mut candidates, vertices);
    // Vertices recovery moves stand on a feature their cell's own planes do
    // not hold (a corner seen through neighbours), which a merged cell must keep.
    let mut recovered = Vec::new();
    if cells.ranks.iter().any(|&r| r >= 2) {
        let vertices = (out.positions.as_mut_slice(), vertex_points.as_mut_slice());
        let state = (&mut lattice, &mut crossings, &mut cells);
        recovered = recover_features(ring_tape, grid, sharpness, state, &candidates, vertices);
    }
    if tolerance > 0.0 {
        leaves.emit(base, &mut out, &mut vertex_points);
        recovered.sort_unstable();
        for node in &mut nodes {
            if let Node::Surface {
                vertex, feature, ..
            } = node
            {
                if recovered.binary_search(vertex).is_ok() {
                    *feature = Some(vertex_points[*vertex as usize]);
                }
            }
        }
        let clustering = Clustering {
            lattice: &lattice,
            grid,
            base,
            tolerance,
            sharpness,
        };
        let remap = merge_cells(&clustering, nodes, &mut grad, &mut vertex_points);
        let added = out.positions.len()..vertex_points.len();
        out.positions.extend(
            vertex_points[added]
                .iter()
                .map(|x| Vec3::from_array(x.map(|c| c as f32))),
        );
        for r in &mut out.refs {
            r.2 = remap[r.2 as usize];
        }
        drop_unused_vertices(&mut out, &mut vertex_points);
    }
    out.normals = normals_of_used(&mut point, &mut grads, &vertex_points, &out.refs);
    // Most edges lie inside the brick: their quads are made here, in
    // parallel, and only edges on the brick's faces meet in the global sort.
    out.refs.sort_unstable_by_key(|r| (r.0, r.1));
    let mut cancelled = Vec::new();
    out.quads = take_quads(&mut out.refs, &mut cancelled);
    for v in cancelled {
        if !out.pinched.contains(&v) {
            out.pinched.push(v);
        }
    }
    out
}

/// How far beyond its cell (in cells) a vertex may stand on the crease or
/// corner its planes meet at, where none of the cell's own points is on it.
const BESIDE: f64 = 0.1;

/// The point of a crease or corner (the solution of `qef` at `rank`; on a
/// crease's line, its point in `near` nearest the line's point nearest the
/// planes' mass point) a thousandth of a cell towards the centre of `cell`:
/// a neighbour whose planes are the same keeps the feature's point itself,
/// or moves towards its own centre, so no two cells put a vertex at one
/// point. `None` where the feature misses `near`.
fn beside_feature(
    qef: &Qef,
    rank: usize,
    near: &features::CellBox,
    grid: &Grid,
    cell: [usize; 3],
) -> Option<[f64; 3]> {
    let solver = qef.solver();
    let mut x = solver.solve(rank);
    if rank == 2 {
        // The line may pass a hair from the cell's corner while its point
        // nearest the mass point lies a cell away along it.
        x = near.slide_into(x, solver.free_direction())?;
    }
    if !near.contains(&x) {
        return None;
    }
    let centre = grid.point(cell).map(|c| c + 0.5 * grid.h);
    let to: [f64; 3] = std::array::from_fn(|a| centre[a] - x[a]);
    let length = to.iter().map(|d| d * d).sum::<f64>().sqrt();
    if length == 0.0 {
        return Some(x);
    }
    Some(std::array::from_fn(|a| {
        x[a] + 1e-3 * grid.h * to[a] / length
    }))
}

/// The proposal for component `root` of a cell from those of its planes
/// `keep` accepts (given whether each came from an edge crossed twice),
/// gathered in `scratch`.
fn propose_from(
    cell_planes: &[(usize, Plane, bool)],
    root: usize,
    keep: impl Fn(bool) -> bool,
    scratch: &mut Vec<Plane>,
    (sharpness, bounds, h): (f64, &features::CellBox, f64),
) -> Proposal {
    scratch.clear();
    scratch.extend(
        cell_planes
            .iter()
            .filter(|(r, _, double)| *r == root && keep(*double))
            .map(|(_, p, _)| *p),
    );
    features::propose(scratch, sharpness, bounds, h)
}

/// Drops the vertices no edge reference uses (those merged into coarser
/// ones), keeping the others' order: most of an adaptive brick's vertices,
/// which would otherwise be carried through the join.
fn drop_unused_vertices(out: &mut BrickOut, vertex_points: &mut Vec<[f64; 3]>) {
    let (new_index, kept) = renumber_used(out.positions.len(), out.refs.iter().map(|r| r.2));
    out.positions = kept.iter().map(|&v| out.positions[v as usize]).collect();
    *vertex_points = kept.iter().map(|&v| vertex_points[v as usize]).collect();
    for r in &mut out.refs {
        r.2 = new_index[r.2 as usize];
    }
    out.pinched.retain_mut(|v| {
        *v = new_index[*v as usize];
        *v != u32::MAX
    });
}

/// Outward normals of the vertices some dual edge uses (any other's is left
/// zero).
fn normals_of_used(
    point: &mut PointEval,
    grads: &mut BatchGradEval,
    vertex_points: &[[f64; 3]],
    refs: &[EdgeRef],
) -> Vec<Vec3> {
    let mut used = vec![false; vertex_points.len()];
    for r in refs {
        used[r.2 as usize] = true;
    }
    let at: Vec<[f64; 3]> = vertex_points
        .iter()
        .zip(&used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| *p)
        .collect();
    let mut found = outward_normals(point, grads, &at).into_iter();
    used.iter()
        .map(|&u| {
            let n = if u {
                found.next().unwrap_or([0.0; 3])
            } else {
                [0.0; 3]
            };
            Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32)
        })
        .collect()
}
