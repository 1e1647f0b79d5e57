//! Thin features: surface inside a cell whose eight corners all share a sign
//! (a wall, a pin or a gap thinner than a cell). Proven, not guessed: from
//! each corner where the lattice predicts a crossing its next corner does
//! not show, a Newton step along the gradient reaches past the zero
//! crossing the gradient predicts; a point of the other sign inside a cell
//! whose corners all miss it is proof of surface there, and a point a cell
//! deeper along the probe's gradient, back on the corner's side, shows the
//! feature is thinner than a cell. Where an edge of the cell is crossed
//! twice the mesher meshes the feature (see `double`); the cells left (a
//! speck or a pin no grid edge meets) are reported, a warning naming the
//! region, instead of letting the feature vanish silently.

use crate::cell::Grid;
use crate::cell::B;
use crate::lattice::{lattice_index, Lattice, L};
use geode_frep::eval::{BatchEval, BatchGradEval, Grad};

/// How far past the predicted crossing the probes land, in cells: a feature
/// thinner than the smallest step can still slip between them.
const OVERSHOOT: [f64; 2] = [0.1, 0.25];

/// Crossings predicted further than this, in cells, are other cells' to find.
const REACH: f64 = 1.5;

/// Whether the lattice predicts a crossing next to a corner of value `v`
/// that it does not show, from its neighbours `prev` and `next` along an
/// axis: the field rises towards zero from the one behind enough to cross
/// before the one ahead, yet the one ahead has the corner's sign (either
/// way along the axis). A surface the corners show never does this where
/// the field is locally linear; a feature between the corners does.
/// (Without branches: a brick asks it of every corner along every axis.)
#[inline(always)]
fn crossing_missed(v: f32, prev: f32, next: f32) -> bool {
    // Towards zero is up from outside, down from inside.
    let up = if v < 0.0 { 1.0 } else { -1.0 };
    let inside = v >= 0.0;
    let predicts = |behind: f32, ahead: f32| {
        let rise = up * (v - behind);
        (rise > 0.0) & (up * v + rise >= 0.0) & ((ahead >= 0.0) == inside)
    };
    predicts(prev, next) | predicts(next, prev)
}

/// The brick's corners (local, in increasing order) next to which the
/// lattice predicts a crossing it does not show along some axis (only
/// corners with a neighbour either way along that axis can tell).
fn corners_missing_crossings(lattice: &Lattice) -> Vec<[isize; 3]> {
    let values = &lattice.values[..];
    let inner = |x: usize| (1..B).contains(&x);
    // A row of corners as an array (fixed length: the comparisons then run
    // in vector lanes); the lattice's ring gives the row's ends neighbours.
    let row_at = |at: usize| <&[f32; B + 1]>::try_from(values.get(at..at + B + 1)?).ok();
    let mut corners = Vec::new();
    for k in 0..=B {
        for j in 0..=B {
            let row = lattice_index([0, j as isize, k as isize]);
            let Some(here) = row_at(row) else { continue };
            let mut missed = [false; B + 1];
            for (stride, counts) in [(1, true), (L, inner(j)), (L * L, inner(k))] {
                if !counts {
                    continue;
                }
                let (Some(prev), Some(next)) = (row_at(row - stride), row_at(row + stride)) else {
                    continue;
                };
                for i in 0..B + 1 {
                    // Along x only the row's inner corners have both.
                    let along = stride != 1 || (i != 0 && i != B);
                    missed[i] |= along & crossing_missed(here[i], prev[i], next[i]);
                }
            }
            let found = (0..=B).filter(|&i| missed[i]);
            corners.extend(found.map(|i| [i as isize, j as isize, k as isize]));
        }
    }
    corners
}

/// The brick's cells (global coordinates) that hold surface none of their
/// corners shows, in increasing order.
pub(crate) fn missed_cells(
    (batch, grads): (&mut BatchEval, &mut BatchGradEval),
    lattice: &Lattice,
    grid: &Grid,
    base: [usize; 3],
) -> Vec<[usize; 3]> {
    let corners = corners_missing_crossings(lattice);
    let points: Vec<[f64; 3]> = corners
        .iter()
        .map(|c| grid.point_signed(std::array::from_fn(|a| base[a] as isize + c[a])))
        .collect();
    let mut at = vec![Grad::default(); points.len()];
    grads.eval(&points, &mut at);
    // Probes past each predicted crossing, each with its corner's side and
    // the blind cell it lands in.
    // Up to one probe per overshoot per corner.
    let most = OVERSHOOT.len() * at.len();
    let (mut xs, mut ys, mut zs, mut from) = (
        Vec::with_capacity(most),
        Vec::with_capacity(most),
        Vec::with_capacity(most),
        Vec::with_capacity(most),
    );
    for (i, g) in at.iter().enumerate() {
        let length = (g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]).sqrt();
        if !(length > 0.0 && length.is_finite()) {
            continue;
        }
        let reach = g.v.abs() / length;
        // Towards zero: up the gradient from outside, down it from inside.
        let toward = if g.v < 0.0 { 1.0 } else { -1.0 } / length;
        let corner_inside = lattice.at(corners[i]) >= 0.0;
        for extra in OVERSHOOT {
            let step = reach + extra * grid.h;
            if step > REACH * grid.h {
                continue;
            }
            let probe = std::array::from_fn(|a| (points[i][a] + toward * g.d[a] * step) as f32);
            // Only a probe in a cell of the brick whose corners all show
            // the corner's side can prove a missed surface: the others are
            // not sampled at all.
            if let Some(cell) = blind_cell(lattice, grid, base, probe, corner_inside) {
                xs.push(probe[0]);
                ys.push(probe[1]);
                zs.push(probe[2]);
                from.push((corner_inside, cell));
            }
        }
    }
    let mut values = vec![0.0f32; xs.len()];
    batch.eval(&xs, &ys, &zs, &mut values);
    // Probes of the other sign, each with the point a cell deeper into the
    // feature along the probe's own gradient: if that point is back on the
    // corner's side, the feature is thinner than a cell there (a wall or a
    // gap; a thick solid's edge clipping the cell is deep along its normal).
    let hits: Vec<usize> = (0..values.len())
        .filter(|&probe| (values[probe] >= 0.0) != from[probe].0)
        .collect();
    let inside: Vec<[f64; 3]> = hits
        .iter()
        .map(|&probe| [xs[probe], ys[probe], zs[probe]].map(f64::from))
        .collect();
    let mut there = vec![Grad::default(); inside.len()];
    grads.eval(&inside, &mut there);
    let n = hits.len();
    let (mut bx, mut by, mut bz) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    );
    for (p, g) in inside.iter().zip(&there) {
        // Deeper: up the gradient inside the solid, down it inside a gap.
        let length = (g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]).sqrt();
        let deeper = if g.v >= 0.0 { 1.0 } else { -1.0 } * grid.h / length.max(f64::MIN_POSITIVE);
        bx.push((p[0] + deeper * g.d[0]) as f32);
        by.push((p[1] + deeper * g.d[1]) as f32);
        bz.push((p[2] + deeper * g.d[2]) as f32);
    }
    let mut beyond = vec![0.0f32; hits.len()];
    batch.eval(&bx, &by, &bz, &mut beyond);
    let mut missed: Vec<[usize; 3]> = hits
        .iter()
        .zip(&beyond)
        .filter(|&(&probe, &b)| (b >= 0.0) == from[probe].0)
        .map(|(&probe, _)| from[probe].1)
        .collect();
    missed.sort_unstable_by_key(|c: &[usize; 3]| (c[2], c[1], c[0]));
    missed.dedup();
    missed
}

/// The cell (global coordinates) of the brick that holds `p`, if all its
/// corners are on the side `inside` says: a surface there is one the
/// lattice cannot show.
fn blind_cell(
    lattice: &Lattice,
    grid: &Grid,
    base: [usize; 3],
    p: [f32; 3],
    inside: bool,
) -> Option<[usize; 3]> {
    let local: [isize; 3] = std::array::from_fn(|a| {
        ((p[a] as f64 - grid.origin[a]) / grid.h).floor() as isize - base[a] as isize
    });
    let global: [isize; 3] = std::array::from_fn(|a| local[a] + base[a] as isize);
    if local.iter().any(|&x| !(0..B as isize).contains(&x))
        || (0..3).any(|a| global[a] as usize + 1 >= grid.corners[a])
    {
        return None;
    }
    let blind = (0..8).all(|c| {
        let q = [
            local[0] + (c & 1),
            local[1] + (c >> 1 & 1),
            local[2] + (c >> 2 & 1),
        ];
        (lattice.at(q) >= 0.0) == inside
    });
    blind.then(|| global.map(|x| x as usize))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corners as the predicate reads them one at a time, axis by axis.
    fn one_by_one(lattice: &Lattice) -> Vec<[isize; 3]> {
        let mut corners = Vec::new();
        for k in 0..=B as isize {
            for j in 0..=B as isize {
                for i in 0..=B as isize {
                    let c = [i, j, k];
                    let missed = (0..3).any(|axis| {
                        let (mut prev, mut next) = (c, c);
                        prev[axis] -= 1;
                        next[axis] += 1;
                        (1..B as isize).contains(&c[axis])
                            && crossing_missed(lattice.at(c), lattice.at(prev), lattice.at(next))
                    });
                    if missed {
                        corners.push(c);
                    }
                }
            }
        }
        corners
    }

    /// Rows at once find the corners one at a time does, on lattices of
    /// waves (many predicted crossings), with zeros (snapped corners),
    /// NaNs and values on the ring that no corner of the brick may read.
    #[test]
    fn rows_at_once_find_the_corners_one_at_a_time_does() {
        for (n, scale) in [(0usize, 1.0f32), (1, 3.0), (2, 0.3), (3, 7.0)] {
            let mut lattice = Lattice {
                base: [0; 3],
                values: vec![0.0; L * L * L],
            };
            for (i, v) in lattice.values.iter_mut().enumerate() {
                let t = i as f32 * 0.37 + n as f32;
                *v = (t * scale).sin() + 0.4 * (t * 0.11).cos() - 0.2;
                if i % 23 == n {
                    *v = 0.0;
                }
                if i % 97 == n {
                    *v = f32::NAN;
                }
            }
            let found = corners_missing_crossings(&lattice);
            assert!(found.len() > 10, "{}", found.len());
            assert_eq!(found, one_by_one(&lattice));
        }
    }
}
