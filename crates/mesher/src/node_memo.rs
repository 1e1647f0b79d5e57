//! Node topologies remembered by the signs at their corners, for the
//! inner leaves' candidates (`inner_leaves`): a node's boundary loops and
//! its dual patch's discs depend on those signs alone, and the same signs
//! recur from node to node along a wall or a column.

use std::collections::HashMap;

use crate::boundary::Loops;
use crate::cell::B;
use crate::lattice::Lattice;

/// What the signs at a node's corners alone decide: whether it may be a
/// leaf (its boundary's loops: the sheet of each crossing in
/// `Boundary::crossings`' order), has no surface crossing its boundary, or
/// is refused. Nodes with the same signs recur (a column's or a wall's
/// surface repeats from node to node: colonnade at depth 6 has 198 sign
/// patterns among 719 nodes of 2 cells, 118 among 185 bricks), so each
/// thread remembers them for the mesh at hand.
#[derive(Clone)]
pub(crate) enum Topology {
    Refused,
    Uncrossed,
    Sheets(Loops),
}

/// A node's side and the signs at its corners, a bit each (x fastest).
pub(crate) type Signs = (usize, [u64; SIGN_WORDS]);

/// Words of sign bits enough for a brick's corners.
const SIGN_WORDS: usize = ((B + 1) * (B + 1) * (B + 1)).div_ceil(64);

/// The signs at the corners of the node of `side` cells from the
/// lattice's local corner `lo` (see `Signs`).
pub(crate) fn node_signs(lattice: &Lattice, lo: [usize; 3], side: usize) -> [u64; SIGN_WORDS] {
    let mut words = [0u64; SIGN_WORDS];
    let mut bit = 0;
    for k in lo[2]..=lo[2] + side {
        for j in lo[1]..=lo[1] + side {
            for i in lo[0]..=lo[0] + side {
                let inside = lattice.at([i, j, k].map(|x| x as isize)) >= 0.0;
                words[bit / 64] |= (inside as u64) << (bit % 64);
                bit += 1;
            }
        }
    }
    words
}

thread_local! {
    static MEMO: std::cell::RefCell<TopologyMemo> = std::cell::RefCell::default();
}

/// What this thread remembers of `signs` for mesh `mesh`.
pub(crate) fn recall(mesh: u64, signs: &Signs) -> Option<Topology> {
    MEMO.with(|memo| memo.borrow_mut().get(mesh, signs))
}

/// Remembers `signs`' topology on this thread for mesh `mesh`.
pub(crate) fn remember(mesh: u64, signs: Signs, topology: Topology) {
    MEMO.with(|memo| memo.borrow_mut().insert(mesh, signs, topology));
}

/// Everything this thread remembers (tests check each entry).
#[cfg(test)]
pub(crate) fn remembered() -> Vec<(Signs, Topology)> {
    MEMO.with(|memo| {
        let memo = memo.borrow();
        memo.known.iter().map(|(s, t)| (*s, t.clone())).collect()
    })
}

/// Topologies by signs, for one mesh at a time (`Grid::mesh`): a mesh's
/// cost never depends on what was meshed before, and the memo never holds
/// more than `MEMO_MOST` entries.
#[derive(Default)]
struct TopologyMemo {
    mesh: u64,
    known: HashMap<Signs, Topology>,
}

/// Entries from which the memo starts afresh (a few MB).
const MEMO_MOST: usize = 1 << 14;

impl TopologyMemo {
    fn get(&mut self, mesh: u64, signs: &Signs) -> Option<Topology> {
        self.start(mesh);
        self.known.get(signs).cloned()
    }

    fn insert(&mut self, mesh: u64, signs: Signs, topology: Topology) {
        self.start(mesh);
        if self.known.len() >= MEMO_MOST {
            self.known.clear();
        }
        self.known.insert(signs, topology);
    }

    /// Forgets another mesh's topologies.
    fn start(&mut self, mesh: u64) {
        if self.mesh != mesh {
            self.mesh = mesh;
            self.known.clear();
        }
    }
}
