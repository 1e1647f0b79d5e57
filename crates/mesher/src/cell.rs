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
