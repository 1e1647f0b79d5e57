//! Dual contouring of one brick of 8^3 cells: corner samples, edge
//! crossings solved in batches, one vertex per connected surface component
//! of a cell placed on its features (see `features`), and the dual-edge
//! references from which the mesher builds quads.

use geode_geo::glam::Vec3;
use geode_geo::ops::renumber_used;

use crate::cluster::{merge_cells, Clustering, Node};
use crate::eval::{BatchEval, BatchGradEval, GradEval, PointEval};
use crate::features::{self, Plane, Proposal};
use crate::lattice::{outward_normals, Crossings, Lattice};
use crate::parts::par_fill;
use crate::polygonise::Grid;
use crate::recovery::{
    cell_box, cell_slot, recover_features, verify_features, Candidate, CellTable, Check,
};
use crate::tape::Tape;
use crate::thin;

/// Cells per brick edge.
pub(crate) const B: usize = 8;

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
    /// Cells holding surface that none of their corners shows (see `thin`).
    pub missed: Vec<[usize; 3]>,
}

/// A cell's reference to a crossed grid edge: (edge key, slot around the
/// edge, local vertex, outward is +axis).
pub(crate) type EdgeRef = (u64, u8, u32, bool);

/// The dual quads, oriented outward, of the edges all four of whose cells
/// `refs` (sorted by key and slot) holds; `refs` keeps the others.
pub(crate) fn take_quads(refs: &mut Vec<EdgeRef>) -> Vec<[u32; 4]> {
    let mut quads = Vec::with_capacity(refs.len() / 4);
    let mut rest = Vec::new();
    for group in refs.chunk_by(|a, b| a.0 == b.0) {
        if group.len() == 4 && group.iter().enumerate().all(|(i, r)| r.1 as usize == i) {
            let mut q = [group[0].2, group[1].2, group[2].2, group[3].2];
            if !group[0].3 {
                q.reverse();
            }
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
    }
}

pub(crate) fn edge_key(axis: usize, c: [usize; 3]) -> u64 {
    (axis as u64) << 60 | (c[0] as u64) << 40 | (c[1] as u64) << 20 | c[2] as u64
}

/// Local edge id (0..12) of the cube edge along `axis` whose lower corner
/// has offsets `p` (0 or 1 on the other axes).
pub(crate) const fn local_edge(axis: usize, p: [usize; 3]) -> usize {
    axis * 4 + p[(axis + 1) % 3] + 2 * p[(axis + 2) % 3]
}

const fn corner_index(p: [usize; 3]) -> usize {
    p[0] + 2 * p[1] + 4 * p[2]
}

/// The six faces of a cube, each as its corners in cyclic order (corner
/// indices) and the local edges joining them (edge `i` joins corners `i`
/// and `i + 1`): computed once, since every surface cell asks.
const FACES: [([usize; 4], [usize; 4]); 6] = face_table();

const fn face_table() -> [([usize; 4], [usize; 4]); 6] {
    // Corners in cyclic order (0,0), (1,0), (1,1), (0,1) over (u, w).
    const CYC: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
    let mut table = [([0; 4], [0; 4]); 6];
    let mut face = 0;
    while face < 6 {
        let (axis, side) = (face / 2, face % 2);
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let mut pos = [[0usize; 3]; 4];
        let mut i = 0;
        while i < 4 {
            pos[i][axis] = side;
            pos[i][u] = CYC[i].0;
            pos[i][w] = CYC[i].1;
            table[face].0[i] = corner_index(pos[i]);
            i += 1;
        }
        let mut i = 0;
        while i < 4 {
            let (p, q) = (pos[i], pos[(i + 1) % 4]);
            // Adjacent corners differ on exactly one axis.
            let ax = if p[u] != q[u] { u } else { w };
            let lo = if p[ax] < q[ax] { p } else { q };
            table[face].1[i] = local_edge(ax, lo);
            i += 1;
        }
        face += 1;
    }
    table
}

/// A cell's edge: its axis, lower corner (offsets), local id, the corner
/// indices of its ends, and the cell's slot around it (counter-clockwise
/// about +axis, as the edge's four cells are ordered).
#[derive(Clone, Copy)]
pub(crate) struct CellEdge {
    pub axis: usize,
    pub offset: [usize; 3],
    pub id: usize,
    pub lo: usize,
    pub hi: usize,
    pub slot: u8,
}

/// The twelve edges of a cell in the order its crossings enter the QEF
/// (axis by axis, lower corners in corner order), computed once.
pub(crate) const CELL_EDGES: [CellEdge; 12] = cell_edges();

const fn cell_edges() -> [CellEdge; 12] {
    let blank = CellEdge {
        axis: 0,
        offset: [0; 3],
        id: 0,
        lo: 0,
        hi: 0,
        slot: 0,
    };
    let mut edges = [blank; 12];
    let (mut n, mut axis) = (0, 0);
    while axis < 3 {
        let mut c = 0;
        while c < 8 {
            let p = [c & 1, c >> 1 & 1, c >> 2 & 1];
            if p[axis] == 0 {
                let mut q = p;
                q[axis] = 1;
                let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
                edges[n] = CellEdge {
                    axis,
                    offset: p,
                    id: local_edge(axis, p),
                    lo: corner_index(p),
                    hi: corner_index(q),
                    slot: match (p[u] == 0, p[w] == 0) {
                        (false, false) => 0,
                        (true, false) => 1,
                        (true, true) => 2,
                        (false, true) => 3,
                    },
                };
                n += 1;
            }
            c += 1;
        }
        axis += 1;
    }
    edges
}

/// Pairs of local edges joined across each face, from the asymptotic
/// decider; for each ambiguous face, one edge of each of its two segments.
pub(crate) fn face_pairs(
    v: &[f32; 8],
    pairs: &mut Vec<(usize, usize)>,
    ambiguous: &mut Vec<(usize, usize)>,
) {
    for (corners, edge) in &FACES {
        let f: [f32; 4] = corners.map(|c| v[c]);
        let inside = f.map(|x| x >= 0.0);
        let mut crossed = [0usize; 4];
        let mut count = 0;
        for i in 0..4 {
            if inside[i] != inside[(i + 1) % 4] {
                crossed[count] = i;
                count += 1;
            }
        }
        match count {
            2 => pairs.push((edge[crossed[0]], edge[crossed[1]])),
            4 => {
                ambiguous.push((edge[0], edge[2]));
                let denom = f[0] + f[2] - f[1] - f[3];
                let saddle = if denom != 0.0 {
                    (f[0] * f[2] - f[1] * f[3]) / denom
                } else {
                    (f[0] + f[1] + f[2] + f[3]) * 0.25
                };
                if (saddle >= 0.0) == inside[0] {
                    // Corners 0 and 2 connect through the face: 1 and 3 are cut off.
                    pairs.push((edge[0], edge[1]));
                    pairs.push((edge[2], edge[3]));
                } else {
                    pairs.push((edge[3], edge[0]));
                    pairs.push((edge[1], edge[2]));
                }
            }
            _ => {}
        }
    }
}

pub(crate) fn find(parent: &mut [usize; 12], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
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
    let roots = lattice.crossed_edges(grid, (0, B as isize));
    crossings.add(&mut batch, &mut point, &mut grads, roots);
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
        missed,
    };
    let mut vertex_points: Vec<[f64; 3]> = Vec::with_capacity(edges);
    let mut cells = CellTable::new();
    let mut cell_planes: Vec<(usize, Plane)> = Vec::with_capacity(12);
    let mut roots_seen: Vec<usize> = Vec::with_capacity(4);
    let mut scratch: Vec<Plane> = Vec::with_capacity(12);
    let mut edge_info: Vec<(usize, u64, u8, bool)> = Vec::with_capacity(12);
    // Edge and corner points still to check against the field, all at once:
    // (vertex, its planes in `unverified_planes`, cell, candidate index).
    let mut unverified: Vec<Check> = Vec::new();
    let mut unverified_planes: Vec<Plane> = Vec::new();
    let mut candidates: Vec<Candidate> = Vec::new();
    let mut pairs = Vec::with_capacity(12);
    let mut ambiguous = Vec::with_capacity(6);
    // What each cell holds, for merging cells (adaptive output).
    let mut nodes = vec![Node::Empty; B * B * B];
    for k in 0..B {
        for j in 0..B {
            for i in 0..B {
                let cell = [base[0] + i, base[1] + j, base[2] + k];
                let node = i + B * (j + B * k);
                if (0..3).any(|a| cell[a] + 1 >= grid.corners[a]) {
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
                if signs == 0 || signs == u8::MAX {
                    continue;
                }
                out.cells += 1;
                // Crossed edges and their connected components.
                pairs.clear();
                ambiguous.clear();
                face_pairs(&v, &mut pairs, &mut ambiguous);
                let mut parent: [usize; 12] = std::array::from_fn(|e| e);
                for &(a, b) in &pairs {
                    let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                    parent[ra] = rb;
                }
                let mut component_vertex: [u32; 12] = [u32::MAX; 12];
                cell_planes.clear();
                roots_seen.clear();
                edge_info.clear();
                for edge in &CELL_EDGES {
                    let (lo_inside, hi_inside) = (signs >> edge.lo & 1, signs >> edge.hi & 1);
                    if lo_inside == hi_inside {
                        continue;
                    }
                    let (axis, p, e) = (edge.axis, edge.offset, edge.id);
                    let lo = [cell[0] + p[0], cell[1] + p[1], cell[2] + p[2]];
                    let key = edge_key(axis, lo);
                    // Every crossed edge of the brick was solved above.
                    let corner = [i + p[0], j + p[1], k + p[2]].map(|x| x as isize);
                    let Some(&plane) = crossings.get(axis, corner) else {
                        continue;
                    };
                    let root = find(&mut parent, e);
                    if !roots_seen.contains(&root) {
                        roots_seen.push(root);
                    }
                    cell_planes.push((root, plane));
                    edge_info.push((e, key, edge.slot, lo_inside == 1));
                }
                let bounds = cell_box(grid, cell, 0);
                let slot = cell_slot(local);
                for root in &roots_seen {
                    scratch.clear();
                    scratch.extend(
                        cell_planes
                            .iter()
                            .filter(|(r, _)| r == root)
                            .map(|(_, p)| *p),
                    );
                    let vertex = out.positions.len();
                    let placed = match features::propose(&scratch, sharpness, &bounds, grid.h) {
                        Proposal::Fits(placed) => placed,
                        Proposal::Verify(placed) => {
                            let planes = unverified_planes.len()..;
                            unverified_planes.extend_from_slice(&scratch);
                            let planes = planes.start..unverified_planes.len();
                            let candidate = (roots_seen.len() == 1).then_some(candidates.len());
                            unverified.push((vertex, planes, bounds, candidate));
                            placed
                        }
                        Proposal::Unfit {
                            rank,
                            achieved,
                            qef,
                            reduced,
                        } => {
                            let point = if rank <= 1 {
                                // No feature: the surface curves within the cell.
                                features::smooth_on_surface(
                                    &qef, reduced, &bounds, &mut grad, grid.h,
                                )
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
                    let rank = if roots_seen.len() == 1 {
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
                    nodes[node] = if roots_seen.len() == 1 && ambiguous.is_empty() {
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
                for &(a, b) in &ambiguous {
                    let root = find(&mut parent, a);
                    if root == find(&mut parent, b)
                        && !out.pinched.contains(&component_vertex[root])
                    {
                        out.pinched.push(component_vertex[root]);
                    }
                }
                for &(e, key, slot, plus) in &edge_info {
                    let root = find(&mut parent, e);
                    out.refs.push((key, slot, component_vertex[root], plus));
                }
            }
        }
    }
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
    out.quads = take_quads(&mut out.refs);
    out
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
