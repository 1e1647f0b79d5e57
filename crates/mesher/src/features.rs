//! Where dual contouring puts a cell's vertex so sharp features survive at
//! any orientation. A cell's own crossing planes are solved at the highest
//! rank whose minimiser lies in the cell (corner, then edge, then face);
//! when the feature they describe lies outside the cell, the point kept is
//! the best of the candidates that lie on the surface (each face's own
//! points, each pair of faces' edge), never a clamped point off it. A
//! corner or edge that passes through a cell whose own edges miss one of
//! its faces is recovered from the planes of the neighbouring cells, and
//! accepted only where every plane involved and the field agree on it.

use crate::qef::Qef;
use geode_frep::eval::GradEval;

pub(crate) use crate::cell::Plane;

/// A cell's bounds shrunk by a margin, so no vertex sits on a cell face (two
/// neighbours' vertices at one point would pinch the mesh).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CellBox {
    pub lo: [f64; 3],
    pub hi: [f64; 3],
}

impl CellBox {
    /// The box grown by `by` on every side.
    pub(crate) fn grown(&self, by: f64) -> CellBox {
        CellBox {
            lo: self.lo.map(|c| c - by),
            hi: self.hi.map(|c| c + by),
        }
    }

    pub(crate) fn contains(&self, x: &[f64; 3]) -> bool {
        (0..3).all(|a| x[a].is_finite() && x[a] >= self.lo[a] && x[a] <= self.hi[a])
    }

    /// The point of the line `x + t d` inside the box nearest `x`, if the
    /// line crosses the box.
    pub(crate) fn slide_into(&self, x: [f64; 3], d: [f64; 3]) -> Option<[f64; 3]> {
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for a in 0..3 {
            if d[a].abs() < 1e-12 {
                if x[a] < self.lo[a] || x[a] > self.hi[a] {
                    return None;
                }
                continue;
            }
            let (ta, tb) = ((self.lo[a] - x[a]) / d[a], (self.hi[a] - x[a]) / d[a]);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            return None;
        }
        let t = 0.0f64.clamp(t0, t1);
        let y = std::array::from_fn(|a| x[a] + t * d[a]);
        self.contains(&y).then_some(y)
    }

    fn clamp(&self, x: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|a| x[a].clamp(self.lo[a], self.hi[a]))
    }
}

/// A vertex placed from its own planes: their rank (0-3) and the rank of
/// the feature the point sits on (lower when the planes meet outside the cell).
pub(crate) struct Placed {
    pub point: [f64; 3],
    pub rank: usize,
    pub achieved: usize,
    pub qef: Qef,
}

/// What the planes alone decide: a point, one still to be checked against
/// the field (an edge's line runs on past the edge's end; the caller checks
/// many at once), or no point in the cell that fits them.
pub(crate) enum Proposal {
    Fits(Placed),
    Verify(Placed),
    Unfit {
        rank: usize,
        achieved: usize,
        qef: Qef,
        reduced: Option<[f64; 3]>,
    },
}

/// Normals closer than this (cosine) belong to one face.
const SAME_FACE: f64 = 0.9;

/// A vertex this close to the surface (in cells) counts as on it.
const ON_SURFACE: f64 = 0.002;

/// An edge or corner point this close to the surface (in cells) is on it:
/// looser than [`ON_SURFACE`], since tangent planes of curved faces meet a
/// little off their crest (0.8% of a cell on the screw's thread at depth 7).
const FEATURE_ON_SURFACE: f64 = 0.01;

/// A crease point off the surface by at most this (in cells) is taken onto
/// it rather than given up (see [`onto_curved_crease`]).
const CURVED_CREASE: f64 = 0.04;

/// Recovered features are accepted only where every plane of the
/// neighbourhood passes this close (RMS, in cells) to them.
const AGREEMENT: f64 = 0.05;

/// Recovery's truncation relative to the cell's own (see `recover`).
const RECOVERY_TRUNCATION: f64 = 0.1;

/// Distance estimate `|f| / |grad f|` from the surface.
fn surface_distance(grad: &mut GradEval, x: [f64; 3]) -> f64 {
    let g = grad.eval(x);
    let len = g.d.iter().map(|d| d * d).sum::<f64>().sqrt();
    if len > 0.0 && len.is_finite() && g.v.is_finite() {
        g.v.abs() / len
    } else {
        f64::INFINITY
    }
}

/// The vertex of one surface component of a cell from its crossing planes,
/// as far as the planes decide it.
pub(crate) fn propose(planes: &[Plane], sharpness: f64, cell: &CellBox, h: f64) -> Proposal {
    let mut qef = Qef::default();
    for &(p, n) in planes {
        qef.add(p, n);
    }
    let solver = qef.solver();
    let rank = solver.rank(sharpness);
    let fits = |x: &[f64; 3]| (qef.error(*x) / qef.count().max(1) as f64).sqrt() <= AGREEMENT * h;
    // A corner whose third face is seen by one crossing among many has a
    // weak direction below `sharpness`: take it where the planes all meet.
    let weak = solver.rank(sharpness * RECOVERY_TRUNCATION);
    if weak > rank {
        let x = solver.solve(weak);
        if cell.contains(&x) && fits(&x) {
            return Proposal::Fits(Placed {
                point: x,
                rank: weak,
                achieved: weak,
                qef,
            });
        }
    }
    let mut reduced = None;
    for r in (0..=rank).rev() {
        let mut x = solver.solve(r);
        if r == 2 {
            // An edge's line: its nearest point to the mass point may lie
            // outside the cell while the line still crosses it.
            x = cell.slide_into(x, solver.free_direction()).unwrap_or(x);
        }
        if cell.contains(&x) {
            if r == rank && fits(&x) {
                let placed = Placed {
                    point: x,
                    rank,
                    achieved: r,
                    qef,
                };
                return if r >= 2 {
                    Proposal::Verify(placed)
                } else {
                    Proposal::Fits(placed)
                };
            }
            reduced = Some((x, r));
            break;
        }
    }
    Proposal::Unfit {
        rank,
        achieved: reduced.map_or(0, |(_, r)| r),
        qef,
        reduced: reduced.map(|(x, _)| x),
    }
}

/// Whether a proposed edge or corner point is on the surface, given the
/// field's value and gradient there.
pub(crate) fn verified(g: &geode_frep::eval::Grad, h: f64) -> bool {
    let len = g.d.iter().map(|d| d * d).sum::<f64>().sqrt();
    len > 0.0 && len.is_finite() && g.v.is_finite() && g.v.abs() / len <= FEATURE_ON_SURFACE * h
}

/// The candidate on the surface that fits the planes best: each face's
/// points projected onto its plane, each pair of faces' edge where it
/// crosses the cell, the reduced-rank minimiser. Pushed onto the surface
/// by Newton steps (inside the cell) when none is on it.
pub(crate) fn best_on_surface(
    planes: &[Plane],
    qef: &Qef,
    reduced: Option<[f64; 3]>,
    sharpness: f64,
    cell: &CellBox,
    grad: &mut GradEval,
    h: f64,
) -> [f64; 3] {
    let faces = group_by_face(planes);
    let mut candidates: Vec<[f64; 3]> = reduced.into_iter().collect();
    for face in &faces {
        candidates.push(cell.clamp(face.solver().solve(1)));
    }
    for (i, a) in faces.iter().enumerate() {
        for b in &faces[i + 1..] {
            let mut pair = *a;
            pair.merge(b);
            let s = pair.solver();
            let x = s.solve(2);
            if s.rank(sharpness) >= 2 && cell.contains(&x) {
                candidates.push(x);
            }
        }
    }
    let scored: Vec<([f64; 3], f64, f64)> = candidates
        .into_iter()
        .map(|x| (x, surface_distance(grad, x) / h, qef.error(x)))
        .collect();
    let best = scored
        .iter()
        .min_by(|a, b| {
            let key = |c: &([f64; 3], f64, f64)| (c.1 > ON_SURFACE, c.2);
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        })
        .copied();
    match best {
        Some((x, d, _)) if d <= ON_SURFACE => x,
        Some((x, _, _)) => project(grad, x, cell),
        None => project(grad, cell.clamp(qef.mass_point()), cell),
    }
}

/// A crease point its planes put just off a curved surface (tangent planes
/// of curved faces meet a little outside the crest: about `1 / (2R)` of a
/// cell for faces of radius `R` cells), taken onto the surface by Newton
/// steps inside `cell`, when it lies within [`CURVED_CREASE`] of it; `None`
/// farther off (an edge's line run on past the edge's end).
pub(crate) fn onto_curved_crease(
    grad: &mut GradEval,
    x: [f64; 3],
    cell: &CellBox,
    h: f64,
) -> Option<[f64; 3]> {
    if surface_distance(grad, x) > CURVED_CREASE * h {
        return None;
    }
    let y = project_until(grad, x, cell, ON_SURFACE * h);
    let moved = (0..3).map(|a| (y[a] - x[a]).powi(2)).sum::<f64>().sqrt();
    (moved <= CURVED_CREASE * h && on_surface(grad, y, h)).then_some(y)
}

/// The vertex of a featureless component whose planes disagree (the surface
/// curves within the cell): the least-squares point, or the mass point,
/// pushed onto the surface by Newton steps inside the cell.
pub(crate) fn smooth_on_surface(
    qef: &Qef,
    reduced: Option<[f64; 3]>,
    cell: &CellBox,
    grad: &mut GradEval,
    h: f64,
) -> [f64; 3] {
    let start = reduced.unwrap_or_else(|| cell.clamp(qef.mass_point()));
    project_until(grad, start, cell, ON_SURFACE * h)
}

/// Planes grouped by direction: one QEF per face the crossings lie on.
fn group_by_face(planes: &[Plane]) -> Vec<Qef> {
    let mut faces: Vec<([f64; 3], Qef)> = Vec::new();
    for &(p, n) in planes {
        let dot = |m: &[f64; 3]| m[0] * n[0] + m[1] * n[1] + m[2] * n[2];
        match faces.iter_mut().find(|(m, _)| dot(m) > SAME_FACE) {
            Some((_, q)) => q.add(p, n),
            None => {
                let mut q = Qef::default();
                q.add(p, n);
                faces.push((n, q));
            }
        }
    }
    faces.into_iter().map(|(_, q)| q).collect()
}

/// Newton steps `x -= f grad / |grad|^2`, each clamped to the cell.
fn project(grad: &mut GradEval, x: [f64; 3], cell: &CellBox) -> [f64; 3] {
    project_until(grad, x, cell, 0.0)
}

/// [`project`], stopping once the point is within `close` of the surface.
fn project_until(grad: &mut GradEval, mut x: [f64; 3], cell: &CellBox, close: f64) -> [f64; 3] {
    for _ in 0..6 {
        let g = grad.eval(x);
        let len2 = g.d.iter().map(|d| d * d).sum::<f64>();
        if !(len2 > 0.0 && len2.is_finite() && g.v.is_finite()) || g.v.abs() <= close * len2.sqrt()
        {
            break;
        }
        x = cell.clamp(std::array::from_fn(|a| x[a] - g.v * g.d[a] / len2));
    }
    x
}

/// A feature of the neighbourhood (its cells' planes summed in `around`)
/// that the cell's own planes (`own`, whose vertex sits on a feature of rank
/// `own_rank`) see only in part:
/// the point where the neighbourhood's planes meet, if it lies in `cell`
/// (the caller decides which cell may take it, then checks it is on the
/// surface) and every plane of the cell and of the neighbourhood passes
/// through it.
pub(crate) fn recover(
    (own, own_rank): (&Qef, usize),
    around: &Qef,
    sharpness: f64,
    cell: &CellBox,
    h: f64,
) -> Option<[f64; 3]> {
    let s = around.solver();
    // A face seen by few crossings of the neighbourhood weighs little
    // against two seen by many: the weak direction still counts here, since
    // the point found must pass the checks below.
    let rank = s.rank(sharpness * RECOVERY_TRUNCATION);
    if rank <= own_rank {
        return None;
    }
    let x = s.solve(rank);
    let rms = |q: &Qef| (q.error(x) / q.count().max(1) as f64).sqrt() / h;
    let agrees = cell.contains(&x) && rms(own) <= ON_SURFACE && rms(around) <= AGREEMENT;
    agrees.then_some(x)
}

/// Whether `x` lies on the surface (within a small fraction of a cell `h`).
pub(crate) fn on_surface(grad: &mut GradEval, x: [f64; 3], h: f64) -> bool {
    surface_distance(grad, x) / h <= ON_SURFACE
}
