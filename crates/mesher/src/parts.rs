//! One buffer filled from many parts in parallel: each part writes its own
//! slice, laid out in the parts' order, so the result does not depend on
//! threads.

use rayon::prelude::*;

/// A buffer of `lens` summed, part `i` filling its `lens[i]` elements (in
/// order) with `fill(i, slice)`, parts in parallel.
pub(crate) fn par_fill<T: Clone + Default + Send>(
    lens: &[usize],
    fill: impl Fn(usize, &mut [T]) + Sync + Send,
) -> Vec<T> {
    let mut out = vec![T::default(); lens.iter().sum()];
    par_fill_into(&mut out, lens, || (), |_, i, s| fill(i, s));
    out
}

/// `out` cut into consecutive slices of `lens`, each filled by
/// `fill(scratch, i, slice)` in parallel, with a scratch made by `init`
/// per task and reused across the parts it fills.
pub(crate) fn par_fill_into<T: Send, S>(
    out: &mut [T],
    lens: &[usize],
    init: impl Fn() -> S + Sync + Send,
    fill: impl Fn(&mut S, usize, &mut [T]) + Sync + Send,
) {
    let mut slices = Vec::with_capacity(lens.len());
    let mut rest = out;
    for &len in lens {
        let (head, tail) = rest.split_at_mut(len);
        slices.push(head);
        rest = tail;
    }
    slices
        .into_par_iter()
        .enumerate()
        .for_each_init(init, |scratch, (i, s)| fill(scratch, i, s));
}
