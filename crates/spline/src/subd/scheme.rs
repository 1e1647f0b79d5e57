//! The Catmark scheme's masks, written once (as OpenSubdiv's
//! `sdc/catmarkScheme.h` does) as weights over a vertex's or an edge's
//! neighbourhood, for refinement, limit positions and face-varying values
//! alike: callers say what each term of the neighbourhood is in their data.

use super::refine::Rule;

/// A term of a vertex's neighbourhood that a mask weighs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Term {
    /// The vertex itself.
    Vertex,
    /// The far end of the vertex's `k`-th edge.
    EdgeEnd(usize),
    /// The face point (child face vertex) of the vertex's `k`-th face.
    FacePoint(usize),
    /// The corner opposite the vertex in its `k`-th face (a quad: the limit
    /// mask's diagonal).
    Opposite(usize),
}

/// Weights of an edge point: each end, and each adjacent face point. A
/// crease weight of 1 (or a boundary edge) is the sharp midpoint, 0 the
/// smooth rule (ends a quarter, faces sharing the other half), between
/// them OpenSubdiv's linear transition.
pub(crate) fn edge_point(crease: f64, faces: usize) -> (f64, f64) {
    if faces == 0 || crease >= 1.0 {
        return (0.5, 0.0);
    }
    let smooth_face = 0.5 / faces as f64;
    (
        crease * 0.5 + (1.0 - crease) * 0.25,
        (1.0 - crease) * smooth_face,
    )
}

/// The crease rule's weights (own, each of the two sharp neighbours): for
/// refinement 3/4 and 1/8, at the limit 2/3 and 1/6.
pub(crate) fn crease(limit: bool) -> (f64, f64) {
    if limit {
        (2.0 / 3.0, 1.0 / 6.0)
    } else {
        (0.75, 0.125)
    }
}

/// The corner and crease rules, alike for refinement and the limit but
/// for the crease weights: a corner stays, a crease weighs itself and its
/// two sharp neighbours.
fn sharp_point(
    rule: Rule,
    limit: bool,
    edges: usize,
    sharp: impl Fn(usize) -> bool,
    scale: f64,
    emit: &mut impl FnMut(Term, f64),
) {
    if rule == Rule::Corner {
        return emit(Term::Vertex, scale);
    }
    let (own, end) = crease(limit);
    emit(Term::Vertex, scale * own);
    for k in (0..edges).filter(|&k| sharp(k)) {
        emit(Term::EdgeEnd(k), scale * end);
    }
}

/// The vertex point of one rule: `edges` incident edges (`sharp(k)` says
/// whether edge `k` is sharp), `faces` incident faces; each weight goes to
/// `emit`, scaled by `scale`.
pub(crate) fn vertex_point(
    rule: Rule,
    edges: usize,
    faces: usize,
    sharp: impl Fn(usize) -> bool,
    scale: f64,
    emit: &mut impl FnMut(Term, f64),
) {
    match rule {
        Rule::Corner | Rule::Crease => sharp_point(rule, false, edges, sharp, scale, emit),
        Rule::Smooth | Rule::Dart => {
            let n = edges as f64;
            emit(Term::Vertex, scale * (n - 2.0) / n);
            let w = scale / (n * n);
            for k in 0..edges {
                emit(Term::EdgeEnd(k), w);
            }
            for k in 0..faces {
                emit(Term::FacePoint(k), w);
            }
        }
    }
}

/// A vertex's mask where the rule changes across the refinement (a
/// semi-sharp feature decaying): OpenSubdiv blends the parent rule's mask,
/// weighted by the fractional weight `w`, with the child rule's. `limit`
/// picks the limit masks instead of the refinement masks.
#[allow(clippy::too_many_arguments)]
pub(crate) fn blended_vertex_point(
    limit: bool,
    (parent, child, w): (Rule, Rule, f64),
    edges: usize,
    faces: usize,
    parent_sharp: impl Fn(usize) -> bool,
    child_sharp: impl Fn(usize) -> bool,
    emit: &mut impl FnMut(Term, f64),
) {
    fn mask<S: Fn(usize) -> bool, E: FnMut(Term, f64)>(
        limit: bool,
        rule: Rule,
        (edges, faces): (usize, usize),
        sharp: S,
        scale: f64,
        emit: &mut E,
    ) {
        if limit {
            limit_point(rule, edges, faces, sharp, scale, emit)
        } else {
            vertex_point(rule, edges, faces, sharp, scale, emit)
        }
    }
    let ring = (edges, faces);
    if matches!(parent, Rule::Smooth | Rule::Dart) || parent == child {
        mask(limit, parent, ring, parent_sharp, 1.0, emit);
    } else {
        mask(limit, parent, ring, &parent_sharp, w, emit);
        mask(limit, child, ring, child_sharp, 1.0 - w, emit);
    }
}

/// The limit position mask of a vertex of an all-quad level: corners stay,
/// creases take 2/3 of themselves and 1/6 of each sharp neighbour, and a
/// smooth vertex of valence n weighs its edge ends 4/(n(n+5)) and its
/// opposite corners 1/(n(n+5)). OpenSubdiv pins a smooth vertex of two
/// faces like a corner.
pub(crate) fn limit_point(
    rule: Rule,
    edges: usize,
    faces: usize,
    sharp: impl Fn(usize) -> bool,
    scale: f64,
    emit: &mut impl FnMut(Term, f64),
) {
    match rule {
        Rule::Corner | Rule::Crease => sharp_point(rule, true, edges, sharp, scale, emit),
        Rule::Smooth | Rule::Dart if faces == 2 => emit(Term::Vertex, scale),
        Rule::Smooth | Rule::Dart => {
            let n = faces as f64;
            let fw = 1.0 / (n * (n + 5.0));
            let ew = 4.0 * fw;
            emit(Term::Vertex, scale * (1.0 - n * (ew + fw)));
            for k in 0..edges {
                emit(Term::EdgeEnd(k), scale * ew);
            }
            for k in 0..faces {
                emit(Term::Opposite(k), scale * fw);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(f: impl FnOnce(&mut dyn FnMut(Term, f64))) -> f64 {
        let mut sum = 0.0;
        f(&mut |_, w| sum += w);
        sum
    }

    #[test]
    fn every_mask_is_an_affine_combination() {
        for rule in [Rule::Smooth, Rule::Dart, Rule::Crease, Rule::Corner] {
            for n in 3..8 {
                let sharp = |k: usize| k < 2;
                let s = total(|e| vertex_point(rule, n, n, sharp, 1.0, &mut |t, w| e(t, w)));
                assert!((s - 1.0).abs() < 1e-12, "{rule:?} n={n}: {s}");
                let s = total(|e| limit_point(rule, n, n, sharp, 1.0, &mut |t, w| e(t, w)));
                assert!((s - 1.0).abs() < 1e-12, "{rule:?} n={n} limit: {s}");
                let s = total(|e| {
                    blended_vertex_point(
                        false,
                        (rule, Rule::Smooth, 0.3),
                        n,
                        n,
                        sharp,
                        |_| false,
                        &mut |t, w| e(t, w),
                    )
                });
                assert!((s - 1.0).abs() < 1e-12);
            }
        }
        for faces in 0..4 {
            for crease in [0.0, 0.4, 1.0] {
                let (end, face) = edge_point(crease, faces);
                assert!((2.0 * end + faces as f64 * face - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn the_regular_smooth_vertex_has_the_textbook_weights() {
        // Valence 4: 1/2 the vertex, 1/16 each edge end and face point.
        let mut got = Vec::new();
        vertex_point(Rule::Smooth, 4, 4, |_| false, 1.0, &mut |t, w| {
            got.push((t, w))
        });
        assert_eq!(got[0], (Term::Vertex, 0.5));
        assert!(got[1..].iter().all(|&(_, w)| w == 1.0 / 16.0));
        // Its limit: 4/9, 4/36 per edge end, 1/36 per opposite corner.
        got.clear();
        limit_point(Rule::Smooth, 4, 4, |_| false, 1.0, &mut |t, w| {
            got.push((t, w))
        });
        assert!((got[0].1 - 4.0 / 9.0).abs() < 1e-15);
        assert!((got[1].1 - 4.0 / 36.0).abs() < 1e-15);
        assert!((got[5].1 - 1.0 / 36.0).abs() < 1e-15);
    }
}
