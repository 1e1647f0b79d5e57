//! Interval arithmetic: conservative bounds of every operation over a box.

use crate::field::{Binary, Unary};

/// A closed interval `[lo, hi]`; NaN bounds mean "may be undefined here".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

pub(crate) const EVERYTHING: Interval = Interval {
    lo: f64::NEG_INFINITY,
    hi: f64::INFINITY,
};

impl Interval {
    pub fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    pub fn point(v: f64) -> Interval {
        Interval { lo: v, hi: v }
    }

    pub fn contains(&self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }

    pub fn has_nan(&self) -> bool {
        self.lo.is_nan() || self.hi.is_nan()
    }

    pub(crate) fn hull(a: Interval, b: Interval) -> Interval {
        if a.has_nan() || b.has_nan() {
            return EVERYTHING;
        }
        Interval::new(a.lo.min(b.lo), a.hi.max(b.hi))
    }

    fn monotonic_up(self, f: impl Fn(f64) -> f64) -> Interval {
        Interval::new(f(self.lo), f(self.hi))
    }
}

/// Whether `[lo, hi]` contains a point `phase + k * period` for an integer k.
fn contains_periodic(lo: f64, hi: f64, phase: f64, period: f64) -> bool {
    let k = ((lo - phase) / period).ceil();
    phase + k * period <= hi
}

fn sin_bounds(a: Interval, shift: f64) -> Interval {
    // sin(x + shift): maxima at pi/2 - shift + 2k pi, minima at -pi/2 - shift + 2k pi.
    use std::f64::consts::{FRAC_PI_2, TAU};
    if a.has_nan() || a.hi - a.lo >= TAU || (a.hi - a.lo).is_nan() {
        return Interval::new(-1.0, 1.0);
    }
    let (s0, s1) = ((a.lo + shift).sin(), (a.hi + shift).sin());
    let hi = if contains_periodic(a.lo, a.hi, FRAC_PI_2 - shift, TAU) {
        1.0
    } else {
        s0.max(s1)
    };
    let lo = if contains_periodic(a.lo, a.hi, -FRAC_PI_2 - shift, TAU) {
        -1.0
    } else {
        s0.min(s1)
    };
    Interval::new(lo, hi)
}

pub fn unary(op: Unary, a: Interval) -> Interval {
    if a.has_nan() {
        return EVERYTHING;
    }
    match op {
        Unary::Neg => Interval::new(-a.hi, -a.lo),
        Unary::Abs => {
            if a.lo >= 0.0 {
                a
            } else if a.hi <= 0.0 {
                Interval::new(-a.hi, -a.lo)
            } else {
                Interval::new(0.0, (-a.lo).max(a.hi))
            }
        }
        Unary::Square => {
            let m = unary(Unary::Abs, a);
            Interval::new(m.lo * m.lo, m.hi * m.hi)
        }
        Unary::Sqrt => {
            if a.hi < 0.0 {
                Interval::new(f64::NAN, f64::NAN)
            } else if a.lo < 0.0 {
                // Part of the box is undefined: keep the defined part's bound
                // but mark it, so no pruning trusts it.
                Interval::new(f64::NAN, a.hi.sqrt())
            } else {
                a.monotonic_up(f64::sqrt)
            }
        }
        Unary::Sin => sin_bounds(a, 0.0),
        Unary::Cos => sin_bounds(a, std::f64::consts::FRAC_PI_2),
        Unary::Tan => {
            use std::f64::consts::{FRAC_PI_2, PI};
            if a.hi - a.lo >= PI || contains_periodic(a.lo, a.hi, FRAC_PI_2, PI) {
                EVERYTHING
            } else {
                a.monotonic_up(f64::tan)
            }
        }
        Unary::Asin | Unary::Acos => {
            if a.lo < -1.0 || a.hi > 1.0 {
                let inner = Interval::new(a.lo.max(-1.0), a.hi.min(1.0));
                let b = if inner.lo > inner.hi {
                    Interval::new(f64::NAN, f64::NAN)
                } else {
                    unary(op, inner)
                };
                Interval::new(f64::NAN, b.hi)
            } else if op == Unary::Asin {
                a.monotonic_up(f64::asin)
            } else {
                Interval::new(a.hi.acos(), a.lo.acos())
            }
        }
        Unary::Atan => a.monotonic_up(f64::atan),
        Unary::Exp => a.monotonic_up(f64::exp),
        Unary::Ln => {
            if a.hi < 0.0 {
                Interval::new(f64::NAN, f64::NAN)
            } else if a.lo < 0.0 {
                Interval::new(f64::NAN, a.hi.ln())
            } else {
                a.monotonic_up(f64::ln)
            }
        }
        Unary::Floor => a.monotonic_up(f64::floor),
        Unary::Ceil => a.monotonic_up(f64::ceil),
        Unary::Round => a.monotonic_up(f64::round),
        Unary::Not => {
            if a.contains(0.0) {
                if a.lo == 0.0 && a.hi == 0.0 {
                    Interval::point(1.0)
                } else {
                    Interval::new(0.0, 1.0)
                }
            } else {
                Interval::point(0.0)
            }
        }
    }
}

pub(crate) fn mul(a: Interval, b: Interval) -> Interval {
    let p = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
    if p.iter().any(|x| x.is_nan()) {
        // 0 * inf: the product may be anything.
        return EVERYTHING;
    }
    Interval::new(
        p.iter().copied().fold(f64::INFINITY, f64::min),
        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// The interval of a binary operation; for `min`/`max` also which argument
/// decides everywhere in the box (for tape simplification).
pub fn binary(op: Binary, a: Interval, b: Interval) -> (Interval, crate::tape::Choice) {
    use crate::tape::Choice;
    if a.has_nan() || b.has_nan() {
        return (EVERYTHING, Choice::Both);
    }
    let r = match op {
        Binary::Add => Interval::new(a.lo + b.lo, a.hi + b.hi),
        Binary::Sub => Interval::new(a.lo - b.hi, a.hi - b.lo),
        Binary::Mul => mul(a, b),
        Binary::Div => {
            if b.contains(0.0) {
                EVERYTHING
            } else {
                mul(a, Interval::new(1.0 / b.hi, 1.0 / b.lo))
            }
        }
        Binary::Min => {
            return if a.hi < b.lo {
                (a, Choice::Left)
            } else if b.hi < a.lo {
                (b, Choice::Right)
            } else {
                (Interval::new(a.lo.min(b.lo), a.hi.min(b.hi)), Choice::Both)
            }
        }
        Binary::Max => {
            return if a.lo > b.hi {
                (a, Choice::Left)
            } else if b.lo > a.hi {
                (b, Choice::Right)
            } else {
                (Interval::new(a.lo.max(b.lo), a.hi.max(b.hi)), Choice::Both)
            }
        }
        Binary::Atan2 => Interval::new(-std::f64::consts::PI, std::f64::consts::PI),
        Binary::Mod => {
            let m = b.lo.abs().max(b.hi.abs());
            if b.contains(0.0) {
                Interval::new(f64::NAN, m)
            } else if b.lo == b.hi && (a.lo / m).floor() == (a.hi / m).floor() {
                // Within one period the remainder is a shift of a.
                let k = (a.lo / m).floor() * m;
                Interval::new(a.lo - k, a.hi - k)
            } else {
                Interval::new(0.0, m)
            }
        }
        Binary::Compare => {
            if a.hi < b.lo {
                Interval::point(-1.0)
            } else if a.lo > b.hi {
                Interval::point(1.0)
            } else {
                Interval::new(-1.0, 1.0)
            }
        }
        Binary::And => {
            if !a.contains(0.0) {
                b
            } else if a.lo == 0.0 && a.hi == 0.0 {
                a
            } else {
                Interval::hull(Interval::point(0.0), b)
            }
        }
        Binary::Or => {
            if !a.contains(0.0) {
                a
            } else if a.lo == 0.0 && a.hi == 0.0 {
                b
            } else {
                Interval::hull(a, b)
            }
        }
    };
    (r, Choice::Both)
}
