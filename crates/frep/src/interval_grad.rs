//! Bounds of the gradient over a box (forward-mode automatic
//! differentiation in interval arithmetic): where one component's bound
//! excludes zero, every line along that axis crosses the surface at most
//! once, and the bounds give the cone the surface's normals stay in.

use crate::field::{Binary, Unary};
use crate::interval::{self, Interval, EVERYTHING};
use crate::tape::{Choice, Instr, Tape};

/// Gradient bounds of one smooth piece: an interval per partial derivative.
pub type GradBox = [Interval; 3];

/// One smooth piece: the value the field has where it is the piece that
/// decides (every `min` and `max` taking the same sides), and its gradient
/// bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    pub v: Interval,
    pub d: GradBox,
}

/// The most pieces kept apart; beyond it the nearest are merged into their hull.
pub const MAX_PIECES: usize = 4;

/// An interval value with bounds of its gradient: where a `min` or `max`
/// may pick either side, the gradient is one side's or the other's, kept
/// as separate pieces (a box's corner has three exact ones) rather than
/// one hull that would hold the zero vector.
#[derive(Clone, Copy, Debug)]
pub struct IntervalGrad {
    pub v: Interval,
    pieces: [Piece; MAX_PIECES],
    count: u8,
}

const ZERO: GradBox = [Interval { lo: 0.0, hi: 0.0 }; 3];

fn hull_box(a: &GradBox, b: &GradBox) -> GradBox {
    std::array::from_fn(|k| Interval::hull(a[k], b[k]))
}

fn hull_piece(a: &Piece, b: &Piece) -> Piece {
    Piece {
        v: Interval::hull(a.v, b.v),
        d: hull_box(&a.d, &b.d),
    }
}

impl IntervalGrad {
    fn new(v: Interval, pieces: &[Piece]) -> IntervalGrad {
        let mut g = IntervalGrad {
            v,
            pieces: [Piece { v, d: ZERO }; MAX_PIECES],
            count: 0,
        };
        for p in pieces {
            g.push(*p);
        }
        g
    }

    /// Adds a piece; a full set merges it into the piece whose hull grows least.
    fn push(&mut self, p: Piece) {
        if self.pieces[..self.count as usize].contains(&p) {
            return;
        }
        if (self.count as usize) < MAX_PIECES {
            self.pieces[self.count as usize] = p;
            self.count += 1;
            return;
        }
        let size = |b: &Piece| b.d.iter().map(|i| i.hi - i.lo).sum::<f64>();
        let best = (0..MAX_PIECES)
            .min_by(|&i, &j| {
                let grow =
                    |k: usize| size(&hull_piece(&self.pieces[k], &p)) - size(&self.pieces[k]);
                grow(i).total_cmp(&grow(j))
            })
            .unwrap_or(0);
        self.pieces[best] = hull_piece(&self.pieces[best], &p);
    }

    /// Each smooth piece with its value and gradient bounds.
    pub fn pieces(&self) -> &[Piece] {
        &self.pieces[..self.count as usize]
    }

    fn constant(v: Interval) -> IntervalGrad {
        IntervalGrad::new(v, &[Piece { v, d: ZERO }])
    }

    /// Each piece through a unary operation whose slope over the piece's
    /// values is `slope` (None: unbounded).
    fn chain(v: Interval, op: Unary, a: &IntervalGrad) -> IntervalGrad {
        let mut g = IntervalGrad::new(v, &[]);
        for p in a.pieces() {
            let pv = interval::unary(op, p.v);
            let d = match unary_slope(op, p.v, pv) {
                Some(k) => p.d.map(|d| interval::mul(k, d)),
                None => [EVERYTHING; 3],
            };
            g.push(Piece { v: pv, d });
        }
        g
    }

    fn unbounded(v: Interval) -> IntervalGrad {
        IntervalGrad::new(
            v,
            &[Piece {
                v,
                d: [EVERYTHING; 3],
            }],
        )
    }
}

fn add(a: Interval, b: Interval) -> Interval {
    interval::binary(Binary::Add, a, b).0
}

/// Bounds of the derivative of a unary operation over `a`, None where the
/// operation jumps (floor and the like) or its slope is unbounded there.
fn unary_slope(op: Unary, a: Interval, v: Interval) -> Option<Interval> {
    let one = Interval::point(1.0);
    let slope = match op {
        Unary::Neg => Interval::point(-1.0),
        Unary::Abs => {
            if a.lo > 0.0 {
                one
            } else if a.hi < 0.0 {
                Interval::point(-1.0)
            } else {
                Interval::new(-1.0, 1.0)
            }
        }
        Unary::Square => Interval::new(2.0 * a.lo, 2.0 * a.hi),
        Unary::Sqrt => {
            if v.lo <= 0.0 || v.has_nan() {
                return None;
            }
            Interval::new(0.5 / v.hi, 0.5 / v.lo)
        }
        Unary::Sin => interval::unary(Unary::Cos, a),
        Unary::Cos => interval::unary(Unary::Neg, interval::unary(Unary::Sin, a)),
        Unary::Tan => add(one, interval::unary(Unary::Square, v)),
        Unary::Atan => {
            let d = add(one, interval::unary(Unary::Square, a));
            Interval::new(1.0 / d.hi, 1.0 / d.lo)
        }
        Unary::Exp => v,
        Unary::Ln => {
            if a.lo <= 0.0 {
                return None;
            }
            Interval::new(1.0 / a.hi, 1.0 / a.lo)
        }
        Unary::Asin | Unary::Acos | Unary::Floor | Unary::Ceil | Unary::Round | Unary::Not => {
            return None
        }
    };
    (!slope.has_nan() && slope.lo.is_finite() && slope.hi.is_finite()).then_some(slope)
}

fn unary(op: Unary, a: &IntervalGrad) -> IntervalGrad {
    let v = interval::unary(op, a.v);
    if op != Unary::Abs {
        return IntervalGrad::chain(v, op, a);
    }
    // |a|: a's pieces where a may be positive, negated where it may be negative.
    let mut g = IntervalGrad::new(v, &[]);
    for p in a.pieces() {
        if p.v.hi >= 0.0 {
            g.push(Piece {
                v: Interval::new(p.v.lo.max(0.0), p.v.hi),
                d: p.d,
            });
        }
        if p.v.lo <= 0.0 {
            g.push(Piece {
                v: Interval::new((-p.v.hi).max(0.0), -p.v.lo),
                d: p.d.map(|d| interval::unary(Unary::Neg, d)),
            });
        }
    }
    g
}

/// Over every pair of pieces: the value `op(p, q)` and the gradient
/// `gradient(p, q, value)`.
fn pairwise(
    v: Interval,
    op: Binary,
    (a, b): (&IntervalGrad, &IntervalGrad),
    gradient: impl Fn(&Piece, &Piece, Interval) -> GradBox,
) -> IntervalGrad {
    let mut g = IntervalGrad::new(v, &[]);
    for p in a.pieces() {
        for q in b.pieces() {
            let pv = interval::binary(op, p.v, q.v).0;
            g.push(Piece {
                v: pv,
                d: gradient(p, q, pv),
            });
        }
    }
    g
}

/// `ka * p' + kb * q'` component by component.
fn linear(ka: Interval, p: &GradBox, kb: Interval, q: &GradBox) -> GradBox {
    std::array::from_fn(|i| add(interval::mul(ka, p[i]), interval::mul(kb, q[i])))
}

/// The pieces of `a` that may win a `min` (`max`: `lower` false) against
/// every value `b` takes.
fn may_win(a: &IntervalGrad, b: Interval, lower: bool, into: &mut IntervalGrad) {
    for p in a.pieces() {
        if wins(p.v, b, lower) {
            into.push(*p);
        }
    }
}

/// Whether values in `v` may win a `min` (`max`: `lower` false) against
/// some value in `other`.
fn wins(v: Interval, other: Interval, lower: bool) -> bool {
    if lower {
        v.lo <= other.hi
    } else {
        v.hi >= other.lo
    }
}

fn binary(op: Binary, a: &IntervalGrad, b: &IntervalGrad) -> IntervalGrad {
    let (v, choice) = interval::binary(op, a.v, b.v);
    let one = Interval::point(1.0);
    let pair = (a, b);
    match op {
        // A sum's gradient is the sum (exactly `1 * p' + 1 * q'`, without
        // the products: a third of the cost of proving a node one sheet).
        Binary::Add => pairwise(v, op, pair, |p, q, _| {
            std::array::from_fn(|i| add(p.d[i], q.d[i]))
        }),
        Binary::Sub => pairwise(v, op, pair, |p, q, _| {
            std::array::from_fn(|i| interval::binary(Binary::Sub, p.d[i], q.d[i]).0)
        }),
        Binary::Mul => pairwise(v, op, pair, |p, q, _| linear(q.v, &p.d, p.v, &q.d)),
        Binary::Div => {
            if b.v.contains(0.0) || b.v.has_nan() {
                return IntervalGrad::unbounded(v);
            }
            pairwise(v, op, pair, |p, q, pv| {
                let inv = interval::binary(Binary::Div, one, q.v).0;
                let kb = interval::unary(Unary::Neg, interval::mul(pv, inv));
                linear(inv, &p.d, kb, &q.d)
            })
        }
        // Where either side may win, the gradient is either side's.
        Binary::Min | Binary::Max => match choice {
            Choice::Left => IntervalGrad { v, ..*a },
            Choice::Right => IntervalGrad { v, ..*b },
            Choice::Both => {
                let lower = op == Binary::Min;
                let mut g = IntervalGrad::new(v, &[]);
                may_win(a, b.v, lower, &mut g);
                may_win(b, a.v, lower, &mut g);
                g
            }
        },
        Binary::Atan2 | Binary::Mod | Binary::Compare | Binary::And | Binary::Or => {
            IntervalGrad::unbounded(v)
        }
    }
}

/// Evaluates value and gradient bounds of a tape over a box. Datasets have
/// no gradient bound (they report unbounded derivatives).
pub struct IntervalGradEval<'t> {
    tape: &'t Tape,
    regs: Vec<IntervalGrad>,
    /// `unbounded_values`' registers.
    plain: Vec<(Interval, Option<Interval>)>,
}

impl Default for IntervalGrad {
    fn default() -> IntervalGrad {
        IntervalGrad::constant(Interval::point(0.0))
    }
}

thread_local! {
    /// Register files of dropped evaluators, for the next ones made on
    /// this thread: the octree makes one per node it tries as a coarse
    /// leaf, and a fresh file is a few hundred bytes a register, each
    /// written before the first instruction runs.
    static SPARE_REGS: std::cell::RefCell<Vec<Vec<IntervalGrad>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

impl Drop for IntervalGradEval<'_> {
    fn drop(&mut self) {
        crate::eval::keep_file(&SPARE_REGS, std::mem::take(&mut self.regs));
    }
}

impl<'t> IntervalGradEval<'t> {
    pub fn new(tape: &'t Tape) -> IntervalGradEval<'t> {
        IntervalGradEval {
            tape,
            regs: crate::eval::spare_file(&SPARE_REGS, tape.slots()),
            plain: Vec::new(),
        }
    }

    /// The values over the box of the pieces `eval` would leave without a
    /// bound on their gradient (a `sqrt` whose argument reaches zero, as
    /// where the box holds a cylinder's axis; a division by an interval
    /// holding zero), as one hull; None where every piece is bounded. Found
    /// with plain intervals, each register split in two (its steep pieces'
    /// hull and the whole), at a fifth of `eval`'s cost: the steep part
    /// goes through each operation as `eval`'s pieces do, and through a
    /// `min` or `max` only where it may win. Where `eval` leaves an
    /// unbounded piece, its value lies in this hull.
    pub fn unbounded_values(&mut self, x: Interval, y: Interval, z: Interval) -> Option<Interval> {
        let axes = [x, y, z];
        let hull = |a: Option<Interval>, b: Option<Interval>| match (a, b) {
            (Some(a), Some(b)) => Some(Interval::hull(a, b)),
            (a, b) => a.or(b),
        };
        // (the whole value, the steep pieces' values)
        let v = &mut self.plain;
        v.clear();
        v.resize(self.tape.slots(), (Interval::point(0.0), None));
        for ins in self.tape.instrs() {
            let at = |r: u32| v[r as usize];
            let out = match *ins {
                Instr::Var { axis, .. } => (axes[axis as usize], None),
                Instr::Const { value, .. } => (Interval::point(value), None),
                Instr::Unary { op, a, .. } => {
                    let (a, steep) = at(a);
                    let value = interval::unary(op, a);
                    let unbounded = op != Unary::Abs && unary_slope(op, a, value).is_none();
                    let steep = if unbounded {
                        Some(value)
                    } else {
                        steep.map(|s| interval::unary(op, s))
                    };
                    (value, steep)
                }
                Instr::Binary { op, a, b, .. } => {
                    let ((a, sa), (b, sb)) = (at(a), at(b));
                    let (value, choice) = interval::binary(op, a, b);
                    let with = |x: Interval, y: Interval| interval::binary(op, x, y).0;
                    let steep = match op {
                        Binary::Add | Binary::Sub | Binary::Mul => {
                            hull(sa.map(|s| with(s, b)), sb.map(|s| with(a, s)))
                        }
                        Binary::Div if !(b.contains(0.0) || b.has_nan()) => {
                            hull(sa.map(|s| with(s, b)), sb.map(|s| with(a, s)))
                        }
                        Binary::Min | Binary::Max => {
                            let lower = op == Binary::Min;
                            match choice {
                                Choice::Left => sa,
                                Choice::Right => sb,
                                Choice::Both => hull(
                                    sa.filter(|s| wins(*s, b, lower)),
                                    sb.filter(|s| wins(*s, a, lower)),
                                ),
                            }
                        }
                        _ => Some(value),
                    };
                    (value, steep)
                }
                Instr::Dataset { set, x, y, z, .. } => {
                    let set = self.tape.dataset(set);
                    let (value, _) = set.interval(at(x).0, at(y).0, at(z).0);
                    (value, Some(value))
                }
            };
            v[ins.out() as usize] = out;
        }
        v[self.tape.output()].1
    }

    pub fn eval(&mut self, x: Interval, y: Interval, z: Interval) -> IntervalGrad {
        let axes = [x, y, z];
        let r = &mut self.regs;
        for ins in self.tape.instrs() {
            match *ins {
                Instr::Var { out, axis } => {
                    let (mut d, v) = (ZERO, axes[axis as usize]);
                    d[axis as usize] = Interval::point(1.0);
                    r[out as usize] = IntervalGrad::new(v, &[Piece { v, d }]);
                }
                Instr::Const { out, value } => {
                    r[out as usize] = IntervalGrad::constant(Interval::point(value))
                }
                Instr::Unary { op, out, a } => r[out as usize] = unary(op, &r[a as usize]),
                Instr::Binary { op, out, a, b } => {
                    r[out as usize] = binary(op, &r[a as usize], &r[b as usize])
                }
                Instr::Dataset { set, out, x, y, z } => {
                    let set = self.tape.dataset(set);
                    let (v, _) = set.interval(r[x as usize].v, r[y as usize].v, r[z as usize].v);
                    r[out as usize] = IntervalGrad::unbounded(v);
                }
            }
        }
        r[self.tape.output()]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::GradEval;
    use crate::field::Field;

    /// Every sampled gradient of a few fields lies within the bounds over
    /// the box it was sampled in.
    #[test]
    fn bounds_hold_the_sampled_gradients() {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let sphere = (x.clone() * x.clone() + y.clone() * y.clone() + z.clone() * z.clone()).sqrt()
            - Field::constant(1.0);
        let wavy = z.clone() - (x.clone() * Field::constant(3.0)).sin() * Field::constant(0.2);
        let boxy = x.clone().abs().max(y.clone().abs()).max(z.clone().abs()) - Field::constant(0.5);
        let blend = sphere.clone().min(wavy.clone()) / (Field::constant(2.0) + x.clone() * x);
        for f in [sphere, wavy, boxy.clone(), blend] {
            let tape = Tape::compile(&f);
            let mut iv = IntervalGradEval::new(&tape);
            let mut point = GradEval::new(&tape);
            for (lo, side) in [
                ([0.3, 0.2, 0.7], 0.25),
                ([-0.9, 0.1, -0.2], 0.5),
                ([0.6, 0.6, 0.6], 0.1),
            ] {
                let b = iv.eval(
                    Interval::new(lo[0], lo[0] + side),
                    Interval::new(lo[1], lo[1] + side),
                    Interval::new(lo[2], lo[2] + side),
                );
                for s in 0..125 {
                    let t = [s % 5, s / 5 % 5, s / 25].map(|i| i as f64 / 4.0 * side);
                    let g = point.eval([lo[0] + t[0], lo[1] + t[1], lo[2] + t[2]]);
                    assert!(b.v.lo <= g.v + 1e-12 && g.v <= b.v.hi + 1e-12);
                    let within = |p: &Piece| {
                        (0..3).all(|k| p.d[k].lo <= g.d[k] + 1e-12 && g.d[k] <= p.d[k].hi + 1e-12)
                            && p.v.lo <= g.v + 1e-12
                            && g.v <= p.v.hi + 1e-12
                    };
                    assert!(
                        b.pieces().iter().any(within),
                        "{:?} in none of {:?}",
                        g.d,
                        b.pieces()
                    );
                }
            }
        }
    }

    /// A box's corner keeps its three faces' exact gradients apart.
    /// Where the plain-interval pass says no piece is unbounded, `eval`'s
    /// pieces all have finite gradient bounds; a box holding a sphere's
    /// centre (where `sqrt`'s slope is unbounded) is found.
    #[test]
    fn unbounded_pieces_are_found_before_the_gradients() {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let sphere = (x.clone() * x.clone() + y.clone() * y.clone() + z.clone() * z.clone()).sqrt()
            - Field::constant(0.5);
        let cylinder =
            (x.clone() * x.clone() + y.clone() * y.clone()).sqrt() - Field::constant(0.2);
        let slab = z.clone().abs() - Field::constant(0.3);
        let shapes = [
            sphere.clone(),
            cylinder.clone().max(slab.clone()),
            sphere.min(cylinder.max(slab)),
        ];
        let mut found = 0;
        for f in &shapes {
            let tape = Tape::compile(f);
            let mut eval = IntervalGradEval::new(&tape);
            for i in 0..8 {
                for j in 0..8 {
                    for k in 0..8 {
                        let lo = [i, j, k].map(|c| -1.0 + 0.25 * c as f64);
                        let [x, y, z] = lo.map(|l| Interval::new(l, l + 0.25));
                        let steep = eval.unbounded_values(x, y, z);
                        let g = eval.eval(x, y, z);
                        let finite = g
                            .pieces()
                            .iter()
                            .flat_map(|p| p.d)
                            .all(|d| d.lo.is_finite() && d.hi.is_finite());
                        assert!(steep.is_some() || finite, "{lo:?}");
                        found += usize::from(steep.is_some());
                    }
                }
            }
        }
        // The boxes with a corner at the sphere's centre, and those along
        // the cylinder's axis.
        assert!(found >= 8, "{found}");
    }

    #[test]
    fn a_corner_has_three_exact_pieces() {
        let (x, y, z) = (Field::x(), Field::y(), Field::z());
        let boxy = x.max(y).max(z);
        let tape = Tape::compile(&boxy);
        let g = IntervalGradEval::new(&tape).eval(
            Interval::new(-0.1, 0.1),
            Interval::new(-0.1, 0.1),
            Interval::new(-0.1, 0.1),
        );
        let mut pieces: Vec<[f64; 3]> = g.pieces().iter().map(|p| p.d.map(|d| d.lo)).collect();
        pieces.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(pieces, [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]);
        assert!(g.pieces().iter().all(|p| p.d.iter().all(|d| d.lo == d.hi)));
    }
}
