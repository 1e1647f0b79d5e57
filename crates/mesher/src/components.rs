//! A cell's crossings grouped into connected surface components: the
//! crossings of its sign-changing edges and of its edges crossed twice
//! (see `double`), paired around each face (see `cell`), with the plane and
//! the dual-edge reference of each.

use crate::cell::{crossing_key, doubled_face_pairs, face_pairs, find, FaceCentre, Plane};
use crate::cell::{CELL_EDGES, SECOND};
use crate::lattice::Crossings;

/// A cell's components, rebuilt per cell in buffers reused across cells.
pub(crate) struct Components {
    /// Union-find over crossing ids (see `cell::SECOND`).
    pub parent: [usize; 2 * SECOND],
    /// Each component's root, in the order first met.
    pub roots: Vec<usize>,
    /// (component, plane, from an edge crossed twice) per crossing.
    pub planes: Vec<(usize, Plane, bool)>,
    /// (crossing id, key, slot around the edge, outward is +axis) per crossing.
    pub refs: Vec<(usize, u64, u8, bool)>,
    /// For each face the corners or the crossings left ambiguous, one
    /// crossing of each of two of its segments.
    pub ambiguous: Vec<(usize, usize)>,
    pairs: Vec<(usize, usize)>,
}

/// What one cell contributes: its corner values and signs (bit per
/// corner), its position (grid cell and brick-local corner offset).
pub(crate) struct CellAt {
    pub values: [f32; 8],
    pub signs: u8,
    pub cell: [usize; 3],
    pub local: [isize; 3],
    /// Whether some edge of the cell is crossed twice.
    pub doubled: bool,
}

impl Components {
    pub(crate) fn new() -> Components {
        Components {
            parent: [0; 2 * SECOND],
            roots: Vec::with_capacity(4),
            planes: Vec::with_capacity(2 * SECOND),
            refs: Vec::with_capacity(2 * SECOND),
            ambiguous: Vec::with_capacity(6),
            pairs: Vec::with_capacity(12),
        }
    }

    /// Groups the crossings of `at` (all solved in `crossings`) into
    /// components; `centre` samples the field at a face's centre.
    pub(crate) fn build(&mut self, at: &CellAt, crossings: &Crossings, centre: FaceCentre) {
        let corner_of = |p: [usize; 3]| std::array::from_fn(|a| at.local[a] + p[a] as isize);
        self.pairs.clear();
        self.ambiguous.clear();
        if at.doubled {
            let mut crossed: [&[Plane]; 12] = [&[]; 12];
            for edge in &CELL_EDGES {
                let corner = corner_of(edge.offset);
                crossed[edge.id] = match crossings.get_double(edge.axis, corner) {
                    Some(two) => two,
                    None => crossings
                        .get(edge.axis, corner)
                        .map_or(&[], std::slice::from_ref),
                };
            }
            doubled_face_pairs(
                &at.values,
                &crossed,
                centre,
                &mut self.pairs,
                &mut self.ambiguous,
            );
        } else {
            face_pairs(&at.values, centre, &mut self.pairs, &mut self.ambiguous);
        }
        self.parent = std::array::from_fn(|e| e);
        for &(a, b) in &self.pairs {
            let (ra, rb) = (find(&mut self.parent, a), find(&mut self.parent, b));
            self.parent[ra] = rb;
        }
        self.planes.clear();
        self.roots.clear();
        self.refs.clear();
        for edge in &CELL_EDGES {
            let (lo_inside, hi_inside) = (at.signs >> edge.lo & 1, at.signs >> edge.hi & 1);
            let (axis, p) = (edge.axis, edge.offset);
            let corner = corner_of(p);
            let planes: &[Plane] = if lo_inside != hi_inside {
                crossings
                    .get(axis, corner)
                    .map_or(&[], std::slice::from_ref)
            } else if at.doubled {
                crossings.get_double(axis, corner).map_or(&[], |two| two)
            } else {
                &[]
            };
            let lo = std::array::from_fn(|a| at.cell[a] + p[a]);
            for (n, &plane) in planes.iter().enumerate() {
                let id = edge.id + n * SECOND;
                let root = find(&mut self.parent, id);
                if !self.roots.contains(&root) {
                    self.roots.push(root);
                }
                self.planes.push((root, plane, lo_inside == hi_inside));
                // The solid lies before a crossing (along +axis) where the
                // lower corner is inside, up to the second.
                let outward_plus = (lo_inside == 1) != (n == 1);
                self.refs
                    .push((id, crossing_key(axis, lo, n == 1), edge.slot, outward_plus));
            }
        }
    }
}
