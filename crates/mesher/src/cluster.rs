//! Octree simplification inside a brick (adaptive output): eight cells, or
//! eight merged cells, become one cell with one vertex when a coarser
//! vertex represents their surface within the tolerance (Ju et al., "Dual
//! Contouring of Hermite Data", 2002, section 4; fidget does the same).
//! A merge needs every child to hold one surface component (or none), the
//! coarse cell to hold exactly one, the signs in the middle of its edges,
//! faces and body to agree with a corner of that edge, face or body (the
//! topological safety test), and the summed QEF's minimiser to lie in the
//! cell, within the tolerance of every plane and of the field's surface.
//! The mesher then maps each fine cell's vertex to its merged cell's: quads
//! whose cells merged lose their repeated corners or vanish, and what is
//! left is the dual of the simplified octree, closed and manifold.

use crate::cell::Grid;
use crate::cell::{face_pairs, find, B, CELL_EDGES};
use crate::lattice::Lattice;
use crate::qef::Qef;
use geode_frep::eval::GradEval;

/// What a (merged) cell holds.
#[derive(Clone, Debug)]
pub(crate) enum Node {
    /// No surface.
    Empty,
    /// One surface component with this vertex and the planes of all the
    /// fine cells it stands for.
    Surface {
        vertex: u32,
        qef: Qef,
        /// A feature point the cell's own planes do not hold (a corner
        /// recovered from neighbours' planes): the merged vertex must be it.
        feature: Option<[f64; 3]>,
    },
    /// Cannot merge: several components, an ambiguous face, outside the grid.
    Blocked,
}

/// The brick's cells and where merged vertices go.
pub(crate) struct Clustering<'a> {
    pub lattice: &'a Lattice,
    pub grid: &'a Grid,
    /// The brick's first corner in grid coordinates.
    pub base: [usize; 3],
    pub tolerance: f64,
    pub sharpness: f64,
}

impl Clustering<'_> {
    /// Corner value at a local corner (0..=B on each axis).
    fn value(&self, c: [usize; 3]) -> f32 {
        self.lattice.at(c.map(|x| x as isize))
    }

    /// Model-space position of a local corner.
    fn point(&self, c: [usize; 3]) -> [f64; 3] {
        self.grid
            .point(std::array::from_fn(|a| self.base[a] + c[a]))
    }
}

/// Merges the brick's `cells` (indexed `i + B (j + B k)`) level by level;
/// new vertices are appended to `points`. Returns, for every vertex (old
/// and new), the vertex that now stands for it.
pub(crate) fn merge_cells(
    c: &Clustering,
    mut cells: Vec<Node>,
    grad: &mut GradEval,
    points: &mut Vec<[f64; 3]>,
) -> Vec<u32> {
    // The vertex each fine cell's surface now has (fine cells in order).
    let fine: Vec<Option<u32>> = cells
        .iter()
        .map(|n| match n {
            Node::Surface { vertex, .. } => Some(*vertex),
            _ => None,
        })
        .collect();
    let mut stands_for = fine.clone();
    let (mut side, mut size) = (B, 1);
    while side > 1 {
        let half = side / 2;
        let mut coarse = Vec::with_capacity(half * half * half);
        for k in 0..half {
            for j in 0..half {
                for i in 0..half {
                    let children: [&Node; 8] = std::array::from_fn(|n| {
                        let at = [2 * i + (n & 1), 2 * j + (n >> 1 & 1), 2 * k + (n >> 2 & 1)];
                        &cells[at[0] + side * (at[1] + side * at[2])]
                    });
                    let origin = [i, j, k].map(|x| x * 2 * size);
                    let node = merge(c, origin, 2 * size, children, grad, points);
                    if let Node::Surface { vertex, .. } = node {
                        for_fine_cells(origin, 2 * size, |f| stands_for[f] = Some(vertex));
                    }
                    coarse.push(node);
                }
            }
        }
        cells = coarse;
        side = half;
        size *= 2;
    }
    let mut remap: Vec<u32> = (0..points.len() as u32).collect();
    for (old, new) in fine.iter().zip(&stands_for) {
        if let (Some(old), Some(new)) = (old, new) {
            remap[*old as usize] = *new;
        }
    }
    remap
}

/// Calls `f` with the index of every fine cell in the cube of side `size`
/// at `origin`.
fn for_fine_cells(origin: [usize; 3], size: usize, mut f: impl FnMut(usize)) {
    for k in origin[2]..origin[2] + size {
        for j in origin[1]..origin[1] + size {
            for i in origin[0]..origin[0] + size {
                f(i + B * (j + B * k));
            }
        }
    }
}

/// One coarse cell of side `size` (fine cells) at local corner `origin`
/// from its eight children.
fn merge(
    c: &Clustering,
    origin: [usize; 3],
    size: usize,
    children: [&Node; 8],
    grad: &mut GradEval,
    points: &mut Vec<[f64; 3]>,
) -> Node {
    if children.iter().any(|n| matches!(n, Node::Blocked)) {
        return Node::Blocked;
    }
    if children.iter().all(|n| matches!(n, Node::Empty)) {
        return Node::Empty;
    }
    if !topology_is_safe(c, origin, size) {
        return Node::Blocked;
    }
    let mut qef = Qef::default();
    let mut feature = None;
    for n in children {
        if let Node::Surface {
            qef: q, feature: f, ..
        } = n
        {
            qef.merge(q);
            if let Some(f) = f {
                if feature.is_some_and(|g| g != *f) {
                    // Two features cannot share one vertex.
                    return Node::Blocked;
                }
                feature = Some(*f);
            }
        }
    }
    let x = feature.unwrap_or_else(|| {
        let solver = qef.solver();
        solver.solve(solver.rank(c.sharpness))
    });
    let (lo, hi) = (c.point(origin), c.point(origin.map(|o| o + size)));
    let inside = (0..3).all(|a| x[a] >= lo[a] && x[a] <= hi[a]);
    let tol2 = c.tolerance * c.tolerance;
    if !inside || qef.error(x) > tol2 || !on_surface(grad, x, c.tolerance) {
        return Node::Blocked;
    }
    let vertex = points.len() as u32;
    points.push(x);
    Node::Surface {
        vertex,
        qef,
        feature,
    }
}

/// Within `tolerance` of the field's surface, to first order.
fn on_surface(grad: &mut GradEval, x: [f64; 3], tolerance: f64) -> bool {
    let g = grad.eval(x);
    let slope = (g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]).sqrt();
    slope > 0.0 && (g.v / slope).abs() <= tolerance
}

/// The coarse cell holds one component, and the sign in the middle of each
/// of its edges, faces and body agrees with one of that element's corners.
fn topology_is_safe(c: &Clustering, origin: [usize; 3], size: usize) -> bool {
    let h = size / 2;
    let at = |o: [usize; 3]| c.value([origin[0] + o[0], origin[1] + o[1], origin[2] + o[2]]) >= 0.0;
    let corner = |n: usize| [n & 1, n >> 1 & 1, n >> 2 & 1].map(|b| b * size);
    let signs: [bool; 8] = std::array::from_fn(|n| at(corner(n)));
    if signs.iter().all(|&s| s == signs[0]) {
        // No crossing on the coarse cell: nothing one vertex could stand for.
        return false;
    }
    // Edges: both ends alike and the middle different is a lost crossing pair.
    for edge in &CELL_EDGES {
        let (a, b) = (signs[edge.lo], signs[edge.hi]);
        let mut m = edge.offset.map(|o| o * size);
        m[edge.axis] = h;
        if a == b && at(m) != a {
            return false;
        }
    }
    // Faces and body: all corners alike and the middle different.
    for axis in 0..3 {
        for side in [0, size] {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut face = [0usize; 3];
            face[axis] = side;
            let mut mid = face;
            mid[u] = h;
            mid[w] = h;
            let mut first = None;
            let mut alike = true;
            for (du, dw) in [(0, 0), (size, 0), (0, size), (size, size)] {
                let mut p = face;
                p[u] = du;
                p[w] = dw;
                let s = at(p);
                alike &= *first.get_or_insert(s) == s;
            }
            if alike && first != Some(at(mid)) {
                return false;
            }
        }
    }
    one_component(c, origin, size)
}

/// Whether the coarse cell's crossed edges form one component (joined
/// across faces by the asymptotic decider, as the fine cells are).
fn one_component(c: &Clustering, origin: [usize; 3], size: usize) -> bool {
    let v: [f32; 8] = std::array::from_fn(|n| {
        c.value([
            origin[0] + (n & 1) * size,
            origin[1] + (n >> 1 & 1) * size,
            origin[2] + (n >> 2 & 1) * size,
        ])
    });
    let (mut pairs, mut ambiguous) = SCRATCH.with_borrow_mut(std::mem::take);
    pairs.clear();
    ambiguous.clear();
    face_pairs(&v, &mut |_| None, &mut pairs, &mut ambiguous);
    let one = joined(&v, &pairs, &ambiguous);
    SCRATCH.with_borrow_mut(|s| *s = (pairs, ambiguous));
    one
}

/// Edges joined across faces, and one edge of each ambiguous face's pairs.
type FacePairs = (Vec<(usize, usize)>, Vec<(usize, usize)>);

thread_local! {
    /// Face-pair buffers reused across coarse cells.
    static SCRATCH: std::cell::RefCell<FacePairs> =
        const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
}

/// Whether the crossed edges of the cell with corner values `v`, joined by
/// `pairs` across faces, form one component (and no face is ambiguous).
fn joined(v: &[f32; 8], pairs: &[(usize, usize)], ambiguous: &[(usize, usize)]) -> bool {
    if !ambiguous.is_empty() {
        return false;
    }
    let mut parent: [usize; 12] = std::array::from_fn(|e| e);
    for &(a, b) in pairs {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra] = rb;
    }
    let mut root = None;
    for edge in &CELL_EDGES {
        if (v[edge.lo] >= 0.0) != (v[edge.hi] >= 0.0) {
            let r = find(&mut parent, edge.id);
            if *root.get_or_insert(r) != r {
                return false;
            }
        }
    }
    root.is_some()
}
