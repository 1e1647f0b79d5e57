//! The terms the mesher's parts share, below all of them: the sampling
//! grid, bricks of B^3 cells, and a cell's edges and faces (computed once,
//! as const tables).

/// Cells per brick edge.
pub(crate) const B: usize = 8;

/// The sampling grid: corners `origin + c h`, in bricks of B^3 cells.
pub(crate) struct Grid {
    pub origin: [f64; 3],
    pub h: f64,
    /// Corner count per axis (cells + 1).
    pub corners: [usize; 3],
    pub bricks: [usize; 3],
    /// This mesh's number, unique per `polygonise` call: what a mesher
    /// memoises holds for one mesh at a time (see `inner_leaves`).
    pub mesh: u64,
}

impl Grid {
    pub fn point(&self, c: [usize; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.coordinate(k, c[k] as isize))
    }

    /// The coordinate along `axis` of the corners with index `c` there
    /// (also just outside the grid).
    pub fn coordinate(&self, axis: usize, c: isize) -> f64 {
        self.origin[axis] + c as f64 * self.h
    }

    /// A corner's position, also for corners just outside the grid.
    pub fn point_signed(&self, c: [isize; 3]) -> [f64; 3] {
        std::array::from_fn(|k| self.coordinate(k, c[k]))
    }
}

/// A point where the surface crosses a grid edge and the outward unit normal there.
pub(crate) type Plane = ([f64; 3], [f64; 3]);

pub(crate) fn edge_key(axis: usize, c: [usize; 3]) -> u64 {
    (axis as u64) << 60 | (c[0] as u64) << 40 | (c[1] as u64) << 20 | c[2] as u64
}

/// The key of an edge's crossing: its edge's key and, in the lowest bit,
/// whether it is the second of an edge crossed twice (see `double`), so
/// an edge's two crossings sort side by side.
pub(crate) fn crossing_key(axis: usize, c: [usize; 3], second: bool) -> u64 {
    edge_key(axis, c) << 1 | second as u64
}

/// A cell's crossings are numbered by local edge (`e`), the second of an
/// edge crossed twice `e + SECOND`.
pub(crate) const SECOND: usize = 12;

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
pub(crate) const FACES: [([usize; 4], [usize; 4]); 6] = face_table();

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

/// Whether the field is inside at the centre of a cell's face (by face
/// index: axis times two plus side), where the caller can sample it.
pub(crate) type FaceCentre<'a> = &'a mut dyn FnMut(usize) -> Option<bool>;

/// Pairs of local edges joined across each face; for each ambiguous face
/// (corners alternating in sign), one edge of each of its two segments.
/// An ambiguous face's diagonal corners connect where `centre` finds the
/// face's centre on their side, else where the asymptotic decider says
/// (the bilinear guess, which a wall thinner than a cell along the
/// diagonal defeats).
pub(crate) fn face_pairs(
    v: &[f32; 8],
    centre: FaceCentre,
    pairs: &mut Vec<(usize, usize)>,
    ambiguous: &mut Vec<(usize, usize)>,
) {
    for (face, (corners, edge)) in FACES.iter().enumerate() {
        pair_by_corners(v, (face, corners, edge), centre, pairs, ambiguous);
    }
}

/// One face's pairs from its corners' signs (see [`face_pairs`]).
fn pair_by_corners(
    v: &[f32; 8],
    (face, corners, edge): (usize, &[usize; 4], &[usize; 4]),
    centre: FaceCentre,
    pairs: &mut Vec<(usize, usize)>,
    ambiguous: &mut Vec<(usize, usize)>,
) {
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
            let saddle_inside = centre(face).unwrap_or_else(|| {
                let denom = f[0] + f[2] - f[1] - f[3];
                let saddle = if denom != 0.0 {
                    (f[0] * f[2] - f[1] * f[3]) / denom
                } else {
                    (f[0] + f[1] + f[2] + f[3]) * 0.25
                };
                saddle >= 0.0
            });
            if saddle_inside == inside[0] {
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

/// The lower corner (corner index) of each local edge, by edge id.
const EDGE_LO: [usize; 12] = edge_lows();

const fn edge_lows() -> [usize; 12] {
    let mut table = [0; 12];
    let mut n = 0;
    while n < 12 {
        table[CELL_EDGES[n].id] = CELL_EDGES[n].lo;
        n += 1;
    }
    table
}

/// A crossing on a face's border: its id, and its point and outward
/// normal in the face's plane.
struct OnFace {
    id: usize,
    at: [f64; 2],
    outward: [f64; 2],
}

/// [`face_pairs`] for a cell some of whose edges are crossed twice:
/// `crossed[e]` holds edge `e`'s crossings (nearer its lower corner first),
/// numbered as [`SECOND`] says. A face none of whose edges is crossed twice
/// pairs by its corners; any other by the matching of its crossings, in
/// order around the face, whose segments best follow the surface (see
/// [`best_matching`]).
pub(crate) fn doubled_face_pairs(
    v: &[f32; 8],
    crossed: &[&[Plane]; 12],
    centre: FaceCentre,
    pairs: &mut Vec<(usize, usize)>,
    ambiguous: &mut Vec<(usize, usize)>,
) {
    for (face, (corners, edge)) in FACES.iter().enumerate() {
        if edge.iter().all(|&e| crossed[e].len() < 2) {
            pair_by_corners(v, (face, corners, edge), centre, pairs, ambiguous);
            continue;
        }
        let (u, w) = ((face / 2 + 1) % 3, (face / 2 + 2) % 3);
        let mut ring = Vec::with_capacity(8);
        for i in 0..4 {
            let e = edge[i];
            let forward = EDGE_LO[e] == corners[i];
            let n = crossed[e].len();
            for k in 0..n {
                let k = if forward { k } else { n - 1 - k };
                let (p, normal) = crossed[e][k];
                let flat = [normal[u], normal[w]];
                let length = flat[0].hypot(flat[1]);
                ring.push(OnFace {
                    id: e + k * SECOND,
                    at: [p[u], p[w]],
                    outward: if length > 1e-9 {
                        flat.map(|x| x / length)
                    } else {
                        [0.0; 2]
                    },
                });
            }
        }
        let (_, matched) = best_matching(&ring);
        for pair in matched.windows(2) {
            ambiguous.push((pair[0].0, pair[1].0));
        }
        pairs.extend(matched);
    }
}

/// How badly the segment from `p` to `q` follows the surface: the surface
/// runs across the normal at either end, and the outside lies on one side.
fn segment_cost(p: &OnFace, q: &OnFace) -> f64 {
    let d = [q.at[0] - p.at[0], q.at[1] - p.at[1]];
    let length = d[0].hypot(d[1]);
    if length < 1e-12 {
        return 0.0;
    }
    let d = d.map(|x| x / length);
    let along = |n: [f64; 2]| (n[0] * d[0] + n[1] * d[1]).abs();
    let side = |n: [f64; 2]| d[0] * n[1] - d[1] * n[0];
    let turned = if side(p.outward) * side(q.outward) < 0.0 {
        1.0
    } else {
        0.0
    };
    along(p.outward) + along(q.outward) + turned
}

/// The non-crossing pairing of crossings in order around a face (at most
/// eight) whose segments follow the surface best. Any such pairing joins
/// crossings an odd number apart, so each segment has the solid on one
/// side: every one is a valid contour, and this picks the likeliest.
fn best_matching(ring: &[OnFace]) -> (f64, Vec<(usize, usize)>) {
    if ring.is_empty() {
        return (0.0, Vec::new());
    }
    let mut best = (f64::INFINITY, Vec::new());
    for j in (1..ring.len()).step_by(2) {
        let (inner, inner_pairs) = best_matching(&ring[1..j]);
        let (outer, outer_pairs) = best_matching(&ring[j + 1..]);
        let cost = segment_cost(&ring[0], &ring[j]) + inner + outer;
        if cost < best.0 {
            let mut pairs = vec![(ring[0].id, ring[j].id)];
            pairs.extend(inner_pairs);
            pairs.extend(outer_pairs);
            best = (cost, pairs);
        }
    }
    best
}

pub(crate) fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Joins the sets of `a` and `b` (the lower root stays the root).
pub(crate) fn union(parent: &mut [usize], a: usize, b: usize) {
    let (a, b) = (find(parent, a), find(parent, b));
    parent[a.max(b)] = a.min(b);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The components of a cell's crossings after `doubled_face_pairs`.
    fn components(v: &[f32; 8], crossed: &[&[Plane]; 12]) -> Vec<Vec<usize>> {
        let (mut pairs, mut ambiguous) = (Vec::new(), Vec::new());
        doubled_face_pairs(v, crossed, &mut |_| None, &mut pairs, &mut ambiguous);
        let mut parent: [usize; 2 * SECOND] = std::array::from_fn(|e| e);
        for (a, b) in pairs {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            parent[ra] = rb;
        }
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for (e, planes) in crossed.iter().enumerate() {
            for n in 0..planes.len() {
                let id = e + n * SECOND;
                let root = find(&mut parent, id);
                match groups.iter_mut().find(|g| find(&mut parent, g[0]) == root) {
                    Some(g) => g.push(id),
                    None => groups.push(vec![id]),
                }
            }
        }
        groups
    }

    /// A wall across x (from 0.4 to 0.6 of the cell) whose corners are all
    /// outside: every edge along x is crossed twice, and each side of the
    /// wall is a component of its own.
    #[test]
    fn a_wall_through_a_cell_makes_two_sheets() {
        let planes: Vec<[Plane; 2]> = (0..4)
            .map(|e| {
                let (y, z) = ((e & 1) as f64, (e >> 1) as f64);
                [
                    ([0.4, y, z], [-1.0, 0.0, 0.0]),
                    ([0.6, y, z], [1.0, 0.0, 0.0]),
                ]
            })
            .collect();
        let mut crossed: [&[Plane]; 12] = [&[]; 12];
        for (e, two) in planes.iter().enumerate() {
            crossed[local_edge(0, [0, e & 1, e >> 1])] = two;
        }
        let mut groups = components(&[-1.0; 8], &crossed);
        groups.iter_mut().for_each(|g| g.sort_unstable());
        groups.sort();
        assert_eq!(groups, [vec![0, 1, 2, 3], vec![12, 13, 14, 15]]);
    }

    /// A ridge across one face: the face's edge crossed twice, by the two
    /// flanks, which meet inside the cell: one component.
    #[test]
    fn a_ridge_poking_into_a_cell_is_one_sheet() {
        let two: [Plane; 2] = [
            ([0.3, 0.0, 0.0], [-0.7, -0.7, 0.0]),
            ([0.7, 0.0, 0.0], [0.7, -0.7, 0.0]),
        ];
        let mut crossed: [&[Plane]; 12] = [&[]; 12];
        crossed[local_edge(0, [0, 0, 0])] = &two;
        assert_eq!(components(&[-1.0; 8], &crossed), [vec![0, 12]]);
    }
}
