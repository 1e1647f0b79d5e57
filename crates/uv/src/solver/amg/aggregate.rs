//! Aggregation for smoothed-aggregation multigrid (Vaněk, Mandel, Brezina
//! 1996): unknowns grouped with their strongly connected neighbours,
//! each group one coarse unknown.

use super::super::{Complex, Csr};

const NONE: u32 = u32::MAX;

/// The aggregate of each unknown and the number of aggregates, in three
/// sequential passes (deterministic):
/// 1. an unknown whose strong neighbours are all free starts an
///    aggregate with them (a lone unknown makes one by itself);
/// 2. each unknown still free joins the aggregate of its strongest
///    neighbour from pass 1;
/// 3. what is left groups with its free strong neighbours.
///
/// `j` is a strong neighbour of `i` when `|a_ij|^2 >= theta^2 a_ii a_jj`.
pub fn aggregate(a: &Csr, theta: f64) -> (Vec<u32>, usize) {
    let n = a.rows();
    let diagonal = a.diagonal();
    let strong = |i: usize, j: u32, v: Complex| {
        j as usize != i
            && v.norm_sqr() >= theta * theta * (diagonal[i] * diagonal[j as usize]).abs()
    };
    let mut of = vec![NONE; n];
    let mut count = 0u32;
    for i in 0..n {
        let (cols, values) = a.row(i);
        let mut neighbours = cols.iter().zip(values).filter(|&(&j, &v)| strong(i, j, v));
        if of[i] != NONE || !neighbours.all(|(&j, _)| of[j as usize] == NONE) {
            continue;
        }
        of[i] = count;
        for (&j, &v) in cols.iter().zip(values) {
            if strong(i, j, v) {
                of[j as usize] = count;
            }
        }
        count += 1;
    }
    let first_pass = of.clone();
    for (i, own) in of.iter_mut().enumerate() {
        if *own != NONE {
            continue;
        }
        let (cols, values) = a.row(i);
        let mut best: Option<(f64, u32)> = None;
        for (&j, &v) in cols.iter().zip(values) {
            let target = first_pass[j as usize];
            if target != NONE && strong(i, j, v) && best.is_none_or(|b| v.norm_sqr() > b.0) {
                best = Some((v.norm_sqr(), target));
            }
        }
        if let Some((_, target)) = best {
            *own = target;
        }
    }
    for i in 0..n {
        if of[i] != NONE {
            continue;
        }
        of[i] = count;
        let (cols, values) = a.row(i);
        for (&j, &v) in cols.iter().zip(values) {
            if strong(i, j, v) && of[j as usize] == NONE {
                of[j as usize] = count;
            }
        }
        count += 1;
    }
    (of, count as usize)
}

/// The tentative prolongator: one column per aggregate, `1 / sqrt(size)`
/// on its unknowns (orthonormal columns reproducing constants, the
/// null space of the conformal energy).
pub fn tentative_prolongator(of: &[u32], aggregates: usize) -> Csr {
    let mut size = vec![0u32; aggregates];
    for &g in of {
        size[g as usize] += 1;
    }
    Csr {
        ncols: aggregates,
        offsets: (0..=of.len()).collect(),
        cols: of.to_vec(),
        values: of
            .iter()
            .map(|&g| Complex::new(1.0 / (size[g as usize] as f64).sqrt(), 0.0))
            .collect(),
    }
}
