//! Edges the surface crosses twice: a wall, a gap or a ridge thinner than a
//! cell passes between two corners of one sign, which corner signs cannot
//! show. Each such edge is found by a Lipschitz search between its corners
//! (the field rises at most [`LIPSCHITZ`] per unit, so a sample of value `v`
//! clears `|v| / LIPSCHITZ` either side of it), and its two crossings are
//! solved like any other; dual contouring then meshes both sides of the
//! feature (see `cell::doubled_face_pairs`).
//!
//! Which edges are searched: those whose corners lie close enough to the
//! surface that it could fit between them, next to which the lattice
//! predicts a crossing that the far corner does not show, from the
//! neighbours along the edge's axis that lie in the brick (a smooth surface
//! running beside the edge predicts none; a wall or ridge across it, from
//! either side). Every decision reads only the edge's own corners and
//! samples, and those neighbours, which the bricks sharing the edge see
//! alike (they share its position along its axis), so they agree on its
//! crossings.

use crate::cell::{Grid, B};
use crate::lattice::{edge_slot, lattice_index, Lattice, Root, L};
use geode_frep::eval::BatchEval;

/// The steepest rise of the field the search trusts (per model unit):
/// distance fields rise 1; the seed screw's thread about 1.56.
const LIPSCHITZ: f64 = 1.6;

/// Batches of samples an edge may take before the search gives up on it.
const ROUNDS: usize = 6;

/// Stretches of an edge narrower than this (fraction of a cell) are not
/// searched: a feature that thin cannot be meshed at this resolution.
const NARROWEST: f64 = 0.03;

/// One edge being searched: its ends, values, and the stretches of it
/// (parameters 0..1) where the surface may still be.
struct Search {
    slot: usize,
    a: [f64; 3],
    b: [f64; 3],
    fa: f64,
    fb: f64,
    open: Vec<(f64, f64)>,
}

/// Whether the line from `behind` through `v` (one cell apart) reaches zero
/// within the next cell: the field rises towards zero, steeply enough.
fn predicts_crossing(behind: f32, v: f32) -> bool {
    let up = if v < 0.0 { 1.0 } else { -1.0 };
    let rise = up * (v - behind);
    rise > 0.0 && up * v + rise >= 0.0
}

/// Whether the edge along `axis` from local corner `c` (lattice index
/// `at`; values `va` at `c` and `vb` at its other end, of one sign) may
/// hold two crossings: a surface the corners miss rises towards the edge
/// from outside it, as seen from the neighbours along the axis that lie in
/// the brick (one of them always does).
fn rises_towards(
    lattice: &Lattice,
    (axis, c, at): (usize, [isize; 3], usize),
    va: f32,
    vb: f32,
) -> bool {
    let stride = [1, L, L * L][axis];
    let from_before = c[axis] >= 1 && predicts_crossing(lattice.values[at - stride], va);
    let from_after =
        c[axis] + 2 <= B as isize && predicts_crossing(lattice.values[at + 2 * stride], vb);
    from_before || from_after
}

/// The search for the edge along `axis` from local corner `c` (values
/// `va`, `vb` at its ends), if its ends lie in the grid and the surface
/// could fit between them.
fn candidate(
    lattice: &Lattice,
    grid: &Grid,
    (axis, c): (usize, [isize; 3]),
    (va, vb): (f32, f32),
) -> Option<Search> {
    let mut d = c;
    d[axis] += 1;
    let (ga, gb) = (lattice.global(grid, c)?, lattice.global(grid, d)?);
    Search::between(edge_slot(axis, c), grid, (ga, gb), (va, vb))
}

impl Search {
    /// The search of the edge from grid corner `ga` to `gb` (values `va`,
    /// `vb`, of one sign), if the surface could fit between them: the
    /// stretch the ends' values do not clear is wider than [`NARROWEST`].
    fn between(
        slot: usize,
        grid: &Grid,
        (ga, gb): ([usize; 3], [usize; 3]),
        (va, vb): (f32, f32),
    ) -> Option<Search> {
        let reach = |v: f32| v.abs() as f64 / (LIPSCHITZ * grid.h);
        let open = (reach(va), 1.0 - reach(vb));
        (open.1 - open.0 >= NARROWEST).then(|| Search {
            slot,
            a: grid.point(ga),
            b: grid.point(gb),
            fa: va as f64,
            fb: vb as f64,
            open: vec![open],
        })
    }
}

/// The sum of an edge's end values (absolute) below which the surface
/// could fit between them (see [`LIPSCHITZ`]).
fn near_enough(grid: &Grid) -> f32 {
    (LIPSCHITZ * grid.h * (1.0 - NARROWEST)) as f32
}

/// The brick's edges (both ends in the brick) crossed twice, each as the
/// two brackets to solve (the crossing nearer the edge's lower end first),
/// in edge order.
pub(crate) fn doubly_crossed_edges(
    batch: &mut BatchEval,
    lattice: &Lattice,
    grid: &Grid,
) -> Vec<Root> {
    // Most corners lie too far from the surface for any edge of theirs to
    // hold one: skipped on their value alone, by stride as `crossed_edges`.
    let reach = near_enough(grid);
    let strides = [1, L, L * L];
    let mut searches = Vec::new();
    for k in 0..=B as isize {
        for j in 0..=B as isize {
            let row = lattice_index([0, j, k]);
            for i in 0..=B as isize {
                let (c, at) = ([i, j, k], row + i as usize);
                let v = lattice.values[at];
                if v.abs() >= reach {
                    continue;
                }
                for axis in 0..3 {
                    if c[axis] == B as isize {
                        continue;
                    }
                    let w = lattice.values[at + strides[axis]];
                    if (v >= 0.0) == (w >= 0.0)
                        && v.abs() + w.abs() < reach
                        && rises_towards(lattice, (axis, c, at), v, w)
                    {
                        searches.extend(candidate(lattice, grid, (axis, c), (v, w)));
                    }
                }
            }
        }
    }
    let found = search(batch, grid, &mut searches);
    let mut roots = Vec::with_capacity(2 * found.len());
    for (s, t, ft) in found {
        let bracket = |(t0, f0), (t1, f1)| Root {
            slot: s.slot,
            a: s.a,
            b: s.b,
            t0,
            f0,
            t1,
            f1,
            side: 0,
        };
        roots.push(bracket((0.0, s.fa), (t, ft)));
        roots.push(bracket((t, ft), (1.0, s.fb)));
    }
    roots
}

/// Whether any of `edges` (axis, lower corner (grid), values at its ends)
/// with ends of one sign is crossed twice: each near enough the surface is
/// searched as bricks search theirs, without the prediction by which
/// bricks skip most (a brick's searches are a subset, run the same way, so
/// whatever a brick finds on one of these edges is found here too). For a
/// node meshed whole (`coarse`), whose boundary a neighbouring brick may
/// mesh through an edge crossed twice.
pub(crate) fn any_crossed_twice(
    batch: &mut BatchEval,
    grid: &Grid,
    edges: &[(usize, [usize; 3], f32, f32)],
) -> bool {
    let limit = near_enough(grid);
    let mut searches: Vec<Search> = edges
        .iter()
        .filter(|(_, _, va, vb)| (*va >= 0.0) == (*vb >= 0.0) && va.abs() + vb.abs() < limit)
        .filter_map(|&(axis, corner, va, vb)| {
            let mut far = corner;
            far[axis] += 1;
            Search::between(0, grid, (corner, far), (va, vb))
        })
        .collect();
    !search(batch, grid, &mut searches).is_empty()
}

/// Samples the widest open stretch of every search, a batch per round,
/// until a sample of the other sign turns up or nothing is left open.
/// Returns the searches that found one, with its parameter and value.
fn search(
    batch: &mut BatchEval,
    grid: &Grid,
    searches: &mut Vec<Search>,
) -> Vec<(Search, f64, f64)> {
    let mut found = Vec::new();
    let (mut xs, mut ys, mut zs, mut ts) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut values = Vec::new();
    for _ in 0..ROUNDS {
        searches.retain(|s| !s.open.is_empty());
        if searches.is_empty() {
            break;
        }
        xs.clear();
        ys.clear();
        zs.clear();
        ts.clear();
        for s in searches.iter_mut() {
            let widest = (0..s.open.len())
                .max_by(|&x, &y| {
                    let w = |i: usize| s.open[i].1 - s.open[i].0;
                    w(x).total_cmp(&w(y))
                })
                .unwrap_or(0);
            let (lo, hi) = s.open.swap_remove(widest);
            let t = 0.5 * (lo + hi);
            ts.push((t, lo, hi));
            xs.push((s.a[0] + (s.b[0] - s.a[0]) * t) as f32);
            ys.push((s.a[1] + (s.b[1] - s.a[1]) * t) as f32);
            zs.push((s.a[2] + (s.b[2] - s.a[2]) * t) as f32);
        }
        values.resize(xs.len(), 0.0f32);
        batch.eval(&xs, &ys, &zs, &mut values);
        let mut next = Vec::with_capacity(searches.len());
        for ((mut s, &(t, lo, hi)), &v) in searches.drain(..).zip(&ts).zip(&values) {
            let v = v as f64;
            if (v >= 0.0) != (s.fa >= 0.0) {
                found.push((s, t, v));
                continue;
            }
            // Nothing within |v| / LIPSCHITZ of the sample.
            let clear = v.abs() / (LIPSCHITZ * grid.h);
            for part in [(lo, t - clear), (t + clear, hi)] {
                if part.1 - part.0 >= NARROWEST {
                    s.open.push(part);
                }
            }
            next.push(s);
        }
        *searches = next;
    }
    found.sort_unstable_by_key(|f| f.0.slot);
    found
}
