//! Ramps (Houdini's ramp parameters): keys at positions with a float or RGB
//! value and a basis each, evaluated anywhere along 0..1. Knows nothing of
//! nodes: parameters, wrangles (`chramp`) and the studio's port
//! (`studio/src/ramp.ts`) evaluate the same curve.
//!
//! Houdini's semantics, as its documentation gives them (`hou.Ramp`,
//! `hou.rampBasis`, VEX `spline`):
//!
//! - Keys are sorted by position (stably: keys at one position keep their
//!   order, and the last of them wins at and after it, a step).
//! - The basis of a key governs the segment from it to the next key; the
//!   last key's basis governs nothing.
//! - Before the first key and after the last, the end key's value holds,
//!   whatever the basis. No keys give 0; one key gives its value everywhere.
//! - `constant` holds the key's value until the next key; `linear` is the
//!   straight line.
//! - `catmull-rom` passes through every key with the finite-difference
//!   (Catmull-Rom) slope `(v[k+1] - v[k-1]) / (x[k+1] - x[k-1])` at each
//!   key, so the curve is tangent-continuous across keys however unevenly
//!   they are spaced (VEX `spline` with positions promises this). At the
//!   first and last key the missing neighbour is the end key reflected
//!   through it, which makes the slope there the end segment's own: two
//!   keys give a straight line.
//! - `monotonecubic` passes through every key without overshoot: a cubic
//!   Hermite whose slopes are Fritsch and Butland's weighted harmonic mean
//!   of the neighbouring secants (SciPy's PCHIP), 0 where the data turns
//!   (a key below or above both neighbours) and at the two end keys, so a
//!   value never leaves the range of the segment's two keys. Two keys give
//!   an ease-in-out (Houdini's "Smooth" preset is a two-key monotone cubic
//!   ramp, which would otherwise be its "Linear").
//! - `bspline` approximates: a run of consecutive B-spline keys (and the
//!   key that ends the run's last segment) are the control points of a
//!   uniform cubic B-spline in (position, value), its ends reflected so it
//!   starts and ends exactly on the run's first and last keys and stays in
//!   their convex hull. The position curve is inverted numerically (it is
//!   monotone, since the positions are sorted).
//!
//! Values and positions are `f64`; per-key slopes and the B-spline spans'
//! cubics are computed once when the ramp is built, so an evaluation is a
//! search and one cubic (a B-spline's also a few Newton steps).

use std::fmt;

/// How a key interpolates towards the next one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RampBasis {
    Constant,
    Linear,
    CatmullRom,
    MonotoneCubic,
    BSpline,
}

impl RampBasis {
    /// Every basis, in the order of [`RampBasis::NAMES`].
    pub const ALL: [RampBasis; 5] = [
        RampBasis::Constant,
        RampBasis::Linear,
        RampBasis::CatmullRom,
        RampBasis::MonotoneCubic,
        RampBasis::BSpline,
    ];

    /// The names networks write (Houdini's ramp interpolation tokens).
    pub const NAMES: &'static [&'static str] = &[
        "constant",
        "linear",
        "catmull-rom",
        "monotonecubic",
        "bspline",
    ];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    pub fn from_name(name: &str) -> Option<RampBasis> {
        Self::NAMES
            .iter()
            .position(|n| *n == name)
            .map(|k| Self::ALL[k])
    }
}

impl fmt::Display for RampBasis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What a ramp's keys hold: one float, or an RGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RampKind {
    Float,
    Color,
}

impl RampKind {
    /// Numbers per value: 1 or 3.
    pub fn components(self) -> usize {
        match self {
            RampKind::Float => 1,
            RampKind::Color => 3,
        }
    }
}

/// One key: a position, a value (a float ramp uses `value[0]`; the rest
/// are 0) and the basis of the segment after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RampKey {
    pub pos: f64,
    pub value: [f64; 3],
    pub basis: RampBasis,
}

impl RampKey {
    pub const fn float(pos: f64, value: f64, basis: RampBasis) -> RampKey {
        RampKey {
            pos,
            value: [value, 0.0, 0.0],
            basis,
        }
    }

    pub const fn color(pos: f64, rgb: [f64; 3], basis: RampBasis) -> RampKey {
        RampKey {
            pos,
            value: rgb,
            basis,
        }
    }
}

/// Why keys make no ramp.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RampError {
    #[error("key {key}: the position {pos} is not a finite number")]
    Position { key: usize, pos: f64 },
    #[error("key {key}: the value {value:?} is not finite")]
    Value { key: usize, value: [f64; 3] },
}

/// A ramp: keys sorted by position and the slopes its cubic bases use.
#[derive(Clone, Debug)]
pub struct Ramp {
    kind: RampKind,
    keys: Vec<RampKey>,
    /// Per key, per component: the Catmull-Rom slope (value per position).
    catmull: Vec<[f64; 3]>,
    /// Per key, per component: the monotone cubic slope.
    monotone: Vec<[f64; 3]>,
    /// The spans of the B-spline runs, in position order.
    bspans: Vec<BSpan>,
}

impl PartialEq for Ramp {
    fn eq(&self, o: &Ramp) -> bool {
        self.kind == o.kind && self.keys == o.keys
    }
}

impl Ramp {
    /// A ramp of these keys, sorted by position (stably). Positions and
    /// values must be finite; a float ramp ignores `value[1..]`.
    pub fn new(kind: RampKind, mut keys: Vec<RampKey>) -> Result<Ramp, RampError> {
        for (k, key) in keys.iter_mut().enumerate() {
            if !key.pos.is_finite() {
                return Err(RampError::Position {
                    key: k,
                    pos: key.pos,
                });
            }
            if kind == RampKind::Float {
                key.value[1] = 0.0;
                key.value[2] = 0.0;
            }
            if !key.value.iter().all(|v| v.is_finite()) {
                return Err(RampError::Value {
                    key: k,
                    value: key.value,
                });
            }
        }
        // -0 and 0 are one position (before sorting, which keeps the order
        // of equal positions).
        for key in &mut keys {
            key.pos += 0.0;
        }
        keys.sort_by(|a, b| a.pos.total_cmp(&b.pos));
        let catmull = (0..keys.len()).map(|k| catmull_slope(&keys, k)).collect();
        let monotone = (0..keys.len()).map(|k| monotone_slope(&keys, k)).collect();
        let bspans = bspline_spans(&keys);
        Ok(Ramp {
            kind,
            keys,
            catmull,
            monotone,
            bspans,
        })
    }

    pub fn kind(&self) -> RampKind {
        self.kind
    }

    /// The keys, sorted by position.
    pub fn keys(&self) -> &[RampKey] {
        &self.keys
    }

    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// The value at `x` (a float ramp's in component 0, the others 0).
    pub fn eval(&self, x: f64) -> [f64; 3] {
        match self.kind {
            RampKind::Float => [self.sample::<1>(x)[0], 0.0, 0.0],
            RampKind::Color => self.sample::<3>(x),
        }
    }

    /// The first component of the value at `x` (a float ramp's value).
    pub fn eval_float(&self, x: f64) -> f64 {
        self.sample::<1>(x)[0]
    }

    /// The first `N` components of the value at `x`.
    fn sample<const N: usize>(&self, x: f64) -> [f64; N] {
        let keys = &self.keys;
        let value = |k: usize| -> [f64; N] { std::array::from_fn(|c| keys[k].value[c]) };
        let (Some(first), Some(last)) = (keys.first(), keys.last()) else {
            return [0.0; N];
        };
        // NaN lands here too: the first key's value.
        if x <= first.pos || x.is_nan() {
            return value(0);
        }
        if x >= last.pos {
            return value(keys.len() - 1);
        }
        // x[i] <= x < x[i + 1], so the segment has width.
        let i = keys.partition_point(|k| k.pos <= x) - 1;
        let (a, b) = (&keys[i], &keys[i + 1]);
        let h = b.pos - a.pos;
        let t = (x - a.pos) / h;
        match a.basis {
            RampBasis::Constant => value(i),
            RampBasis::Linear => {
                std::array::from_fn(|c| a.value[c] + (b.value[c] - a.value[c]) * t)
            }
            RampBasis::CatmullRom => hermite(a, b, &self.catmull[i], &self.catmull[i + 1], h, t),
            RampBasis::MonotoneCubic => {
                hermite(a, b, &self.monotone[i], &self.monotone[i + 1], h, t)
            }
            RampBasis::BSpline => self.bspline(x),
        }
    }

    /// The B-spline span holding `x` (inside a run, see the module's doc):
    /// its position cubic solved for `x`, its value cubic at that parameter.
    fn bspline<const N: usize>(&self, x: f64) -> [f64; N] {
        // The last span starting at or before x (spans are in position
        // order, and a run's first span starts at its first key, so one is).
        let s = &self.bspans[self.bspans.partition_point(|s| s.x[3] <= x).max(1) - 1];
        let u = solve_monotone_cubic(s.x, x);
        std::array::from_fn(|c| {
            let k = &s.value[c];
            ((k[0] * u + k[1]) * u + k[2]) * u + k[3]
        })
    }
}

/// One span of a B-spline run: position and value cubics in the span's
/// parameter (power basis, highest first).
#[derive(Clone, Debug)]
struct BSpan {
    x: [f64; 4],
    value: [[f64; 4]; 3],
}

/// The spans of every run of B-spline keys, in position order. A run is
/// keys a..e-1 of basis B-spline and the key e that ends its last segment;
/// its control points are those keys (position, value) with one phantom
/// beyond each end, the end key reflected through it.
fn bspline_spans(keys: &[RampKey]) -> Vec<BSpan> {
    let mut spans = Vec::new();
    let mut a = 0;
    while a + 1 < keys.len() {
        if keys[a].basis != RampBasis::BSpline {
            a += 1;
            continue;
        }
        let mut e = a + 1;
        while e + 1 < keys.len() && keys[e].basis == RampBasis::BSpline {
            e += 1;
        }
        // Control point j of the run, counted from key a (-1 ..= e - a + 1);
        // component 0 is the position, 1.. the value.
        let last = (e - a) as isize;
        let point = |j: isize, c: usize| -> f64 {
            let get = |k: usize| {
                if c == 0 {
                    keys[k].pos
                } else {
                    keys[k].value[c - 1]
                }
            };
            if j < 0 {
                2.0 * get(a) - get(a + 1)
            } else if j > last {
                2.0 * get(e) - get(e - 1)
            } else {
                get(a + j as usize)
            }
        };
        // Span s has control points s - 1 ..= s + 2; its constant term is
        // where it starts, (c[s-1] + 4 c[s] + c[s+1]) / 6.
        for s in 0..last {
            let cubic = |c: usize| {
                let p = [
                    point(s - 1, c),
                    point(s, c),
                    point(s + 1, c),
                    point(s + 2, c),
                ];
                [
                    (-p[0] + 3.0 * p[1] - 3.0 * p[2] + p[3]) / 6.0,
                    (3.0 * p[0] - 6.0 * p[1] + 3.0 * p[2]) / 6.0,
                    (-3.0 * p[0] + 3.0 * p[2]) / 6.0,
                    (p[0] + 4.0 * p[1] + p[2]) / 6.0,
                ]
            };
            spans.push(BSpan {
                x: cubic(0),
                value: [cubic(1), cubic(2), cubic(3)],
            });
        }
        a = e;
    }
    spans
}

/// The cubic Hermite of segment `a`..`b` (width `h`) at `t` in 0..1, with
/// slopes in value per position.
fn hermite<const N: usize>(
    a: &RampKey,
    b: &RampKey,
    ma: &[f64; 3],
    mb: &[f64; 3],
    h: f64,
    t: f64,
) -> [f64; N] {
    let t2 = t * t;
    let t3 = t2 * t;
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = -2.0 * t3 + 3.0 * t2;
    let h11 = t3 - t2;
    std::array::from_fn(|c| h00 * a.value[c] + h10 * h * ma[c] + h01 * b.value[c] + h11 * h * mb[c])
}

/// The slope between keys `a` and `b` per component; none where they share
/// a position (a step).
fn secant(keys: &[RampKey], a: usize, b: usize) -> Option<[f64; 3]> {
    let h = keys[b].pos - keys[a].pos;
    (h > 0.0).then(|| std::array::from_fn(|c| (keys[b].value[c] - keys[a].value[c]) / h))
}

/// Catmull-Rom's slope at key `k`: the neighbours' finite difference (an end
/// key's neighbour is itself, which is its reflection's difference).
fn catmull_slope(keys: &[RampKey], k: usize) -> [f64; 3] {
    let l = k.saturating_sub(1);
    let r = (k + 1).min(keys.len() - 1);
    secant(keys, l, r).unwrap_or([0.0; 3])
}

/// The monotone cubic slope at key `k` (Fritsch and Butland: 0 at the ends,
/// at turns and beside steps, else the weighted harmonic mean of the two
/// secants, which never exceeds three times the smaller).
fn monotone_slope(keys: &[RampKey], k: usize) -> [f64; 3] {
    if k == 0 || k + 1 >= keys.len() {
        return [0.0; 3];
    }
    let (Some(d0), Some(d1)) = (secant(keys, k - 1, k), secant(keys, k, k + 1)) else {
        return [0.0; 3];
    };
    let h0 = keys[k].pos - keys[k - 1].pos;
    let h1 = keys[k + 1].pos - keys[k].pos;
    let w0 = 2.0 * h1 + h0;
    let w1 = h1 + 2.0 * h0;
    std::array::from_fn(|c| {
        if d0[c] * d1[c] <= 0.0 {
            0.0
        } else {
            (w0 + w1) / (w0 / d0[c] + w1 / d1[c])
        }
    })
}

/// The `u` in 0..1 where the non-decreasing cubic
/// `k[0] u³ + k[1] u² + k[2] u + k[3]` equals `x` (clamped to the ends):
/// Newton's steps kept inside a shrinking bracket, bisecting where a step
/// would leave it.
fn solve_monotone_cubic(k: [f64; 4], x: f64) -> f64 {
    let f = |u: f64| ((k[0] * u + k[1]) * u + k[2]) * u + k[3];
    let (x0, x1) = (k[3], k.iter().sum::<f64>());
    if x <= x0 || x.is_nan() || x1 <= x0 {
        return 0.0;
    }
    if x >= x1 {
        return 1.0;
    }
    let tolerance = (x1 - x0) * 1e-13;
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut u = (x - x0) / (x1 - x0);
    for _ in 0..64 {
        let r = f(u) - x;
        if r.abs() <= tolerance {
            break;
        }
        if r < 0.0 {
            lo = u;
        } else {
            hi = u;
        }
        let d = (3.0 * k[0] * u + 2.0 * k[1]) * u + k[2];
        let next = u - r / d;
        u = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= f64::EPSILON {
            break;
        }
    }
    u
}

#[cfg(test)]
mod tests {
    use super::RampBasis::*;
    use super::*;

    fn float(keys: &[(f64, f64, RampBasis)]) -> Ramp {
        Ramp::new(
            RampKind::Float,
            keys.iter()
                .map(|&(p, v, b)| RampKey::float(p, v, b))
                .collect(),
        )
        .unwrap()
    }

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() < 1e-12, "{a} != {b}");
    }

    #[test]
    fn basis_names_round_trip() {
        for b in RampBasis::ALL {
            assert_eq!(RampBasis::from_name(b.name()), Some(b));
        }
        assert_eq!(RampBasis::from_name("cubic"), None);
    }

    #[test]
    fn no_keys_give_zero_and_one_key_its_value() {
        let empty = Ramp::new(RampKind::Color, Vec::new()).unwrap();
        assert_eq!(empty.eval(0.5), [0.0; 3]);
        let one = float(&[(0.3, 2.0, CatmullRom)]);
        for x in [-1.0, 0.0, 0.3, 0.9, f64::NAN] {
            assert_eq!(one.eval_float(x), 2.0);
        }
    }

    #[test]
    fn linear_midpoints_and_held_ends() {
        let r = float(&[(0.0, 2.5, Linear), (1.0, 4.5, Linear)]);
        // hou.Ramp's documented example: 2.5 to 4.5, 3.5 halfway.
        close(r.eval_float(0.0), 2.5);
        close(r.eval_float(0.5), 3.5);
        close(r.eval_float(1.0), 4.5);
        let r = float(&[(0.2, 1.0, Linear), (0.6, 3.0, Linear)]);
        close(r.eval_float(0.4), 2.0);
        close(r.eval_float(0.3), 1.5);
        // Outside the keys the end values hold, whatever the basis.
        close(r.eval_float(0.0), 1.0);
        close(r.eval_float(-5.0), 1.0);
        close(r.eval_float(1.0), 3.0);
    }

    #[test]
    fn constant_steps_at_the_next_key() {
        let r = float(&[
            (0.0, 1.0, Constant),
            (0.5, 2.0, Constant),
            (1.0, 3.0, Constant),
        ]);
        close(r.eval_float(0.25), 1.0);
        close(r.eval_float(0.4999), 1.0);
        close(r.eval_float(0.5), 2.0);
        close(r.eval_float(0.99), 2.0);
        close(r.eval_float(1.0), 3.0);
    }

    #[test]
    fn the_basis_of_a_key_governs_the_segment_after_it() {
        let r = float(&[
            (0.0, 0.0, Constant),
            (0.5, 1.0, Linear),
            (1.0, 0.0, Constant),
        ]);
        close(r.eval_float(0.25), 0.0);
        close(r.eval_float(0.75), 0.5);
    }

    #[test]
    fn keys_are_sorted_stably_and_a_shared_position_steps() {
        let r = float(&[(1.0, 3.0, Linear), (0.0, 1.0, Linear), (0.5, 2.0, Linear)]);
        let pos: Vec<f64> = r.keys().iter().map(|k| k.pos).collect();
        assert_eq!(pos, [0.0, 0.5, 1.0]);
        close(r.eval_float(0.75), 2.5);
        let step = float(&[
            (0.0, 0.0, Linear),
            (0.5, 1.0, Linear),
            (0.5, 5.0, Linear),
            (1.0, 5.0, Linear),
        ]);
        close(step.eval_float(0.25), 0.5);
        close(step.eval_float(0.5), 5.0);
        close(step.eval_float(0.4999999), 0.9999998);
    }

    #[test]
    fn non_finite_keys_are_refused() {
        assert!(matches!(
            Ramp::new(RampKind::Float, vec![RampKey::float(f64::NAN, 0.0, Linear)]),
            Err(RampError::Position { key: 0, .. })
        ));
        assert!(matches!(
            Ramp::new(
                RampKind::Color,
                vec![
                    RampKey::color(0.0, [0.0; 3], Linear),
                    RampKey::color(1.0, [0.0, f64::INFINITY, 0.0], Linear)
                ]
            ),
            Err(RampError::Value { key: 1, .. })
        ));
    }

    #[test]
    fn catmull_rom_passes_through_keys_with_finite_difference_slopes() {
        let keys = [(0.0, 0.0), (0.3, 1.0), (0.5, 0.2), (1.0, 0.8)];
        let r = float(&keys.map(|(p, v)| (p, v, CatmullRom)));
        for (p, v) in keys {
            close(r.eval_float(p), v);
        }
        // The slope at key 1 is (0.2 - 0) / (0.5 - 0), from both sides.
        let d = 1e-6;
        let left = (r.eval_float(0.3) - r.eval_float(0.3 - d)) / d;
        let right = (r.eval_float(0.3 + d) - r.eval_float(0.3)) / d;
        assert!((left - 0.4).abs() < 1e-4, "{left}");
        assert!((right - 0.4).abs() < 1e-4, "{right}");
        // At the first key, the first segment's own slope (1 / 0.3).
        let start = (r.eval_float(d) - r.eval_float(0.0)) / d;
        assert!((start - 1.0 / 0.3).abs() < 1e-4, "{start}");
        // Midway on the uniform middle of equally spaced keys, the
        // Catmull-Rom formula: (-p0 + 9 p1 + 9 p2 - p3) / 16.
        let u = float(&[
            (0.0, 0.0, CatmullRom),
            (0.25, 1.0, CatmullRom),
            (0.5, 3.0, CatmullRom),
            (0.75, 2.0, CatmullRom),
            (1.0, 0.0, CatmullRom),
        ]);
        close(
            u.eval_float(0.375),
            (-0.0 + 9.0 * 1.0 + 9.0 * 3.0 - 2.0) / 16.0,
        );
    }

    #[test]
    fn two_catmull_rom_keys_are_a_straight_line() {
        let r = float(&[(0.2, 1.0, CatmullRom), (0.8, 4.0, CatmullRom)]);
        for k in 0..=10 {
            let x = 0.2 + 0.06 * f64::from(k);
            close(r.eval_float(x), 1.0 + 5.0 * (x - 0.2));
        }
    }

    #[test]
    fn catmull_rom_overshoots_a_step_and_monotone_cubic_does_not() {
        let step = [(0.0, 0.0), (0.4, 0.0), (0.6, 1.0), (1.0, 1.0)];
        let cr = float(&step.map(|(p, v)| (p, v, CatmullRom)));
        let mono = float(&step.map(|(p, v)| (p, v, MonotoneCubic)));
        let xs: Vec<f64> = (0..=1000).map(|k| f64::from(k) / 1000.0).collect();
        assert!(xs.iter().any(|&x| cr.eval_float(x) < -1e-3));
        assert!(xs.iter().any(|&x| cr.eval_float(x) > 1.0 + 1e-3));
        let mut last = f64::NEG_INFINITY;
        for &x in &xs {
            let v = mono.eval_float(x);
            assert!((0.0..=1.0).contains(&v), "{v} at {x}");
            assert!(v >= last, "not monotone at {x}");
            last = v;
        }
        // Flat beside the step: the ease between 0.4 and 0.6 is smoothstep.
        let t: f64 = 0.25;
        close(mono.eval_float(0.45), t * t * (3.0 - 2.0 * t));
    }

    #[test]
    fn monotone_cubic_keeps_extrema_at_keys_and_eases_two_keys() {
        let hill = float(&[
            (0.0, 0.0, MonotoneCubic),
            (0.5, 1.0, MonotoneCubic),
            (1.0, 0.0, MonotoneCubic),
        ]);
        for k in 0..=100 {
            let v = hill.eval_float(f64::from(k) / 100.0);
            assert!((0.0..=1.0).contains(&v));
        }
        close(hill.eval_float(0.5), 1.0);
        let smooth = float(&[(0.0, 0.0, MonotoneCubic), (1.0, 1.0, MonotoneCubic)]);
        for k in 0..=10 {
            let t = f64::from(k) / 10.0;
            close(smooth.eval_float(t), t * t * (3.0 - 2.0 * t));
        }
        // Interior slope: the weighted harmonic mean of the secants 2 and 0.5
        // over widths 0.5 and 0.25: (w0 + w1) / (w0 / 2 + w1 / 0.5) with
        // w0 = 2 * 0.25 + 0.5 = 1, w1 = 0.25 + 1 = 1.25 -> 2.25 / 3 = 0.75.
        let r = float(&[
            (0.0, 0.0, MonotoneCubic),
            (0.5, 1.0, MonotoneCubic),
            (0.75, 1.125, MonotoneCubic),
        ]);
        let d = 1e-6;
        let slope = (r.eval_float(0.5 + d) - r.eval_float(0.5 - d)) / (2.0 * d);
        assert!((slope - 0.75).abs() < 1e-5, "{slope}");
    }

    #[test]
    fn bspline_starts_and_ends_on_its_keys_inside_their_hull() {
        let keys = [(0.0, 0.0), (0.2, 1.0), (0.5, -1.0), (0.7, 2.0), (1.0, 0.5)];
        let r = float(&keys.map(|(p, v)| (p, v, BSpline)));
        close(r.eval_float(0.0), 0.0);
        close(r.eval_float(1.0), 0.5);
        // It approximates: the curve does not reach an interior key.
        assert!(r.eval_float(0.2) < 1.0 - 1e-3);
        let mut last = 0.0;
        for k in 0..=1000 {
            let v = r.eval_float(f64::from(k) / 1000.0);
            assert!((-1.0..=2.0).contains(&v), "{v}");
            // Continuous: no jump between neighbouring samples.
            if k > 0 {
                assert!((v - last).abs() < 0.02, "jump at {k}");
            }
            last = v;
        }
        // Evenly spaced keys: a span starts at (c0 + 4 c1 + c2) / 6, at the
        // matching position.
        let even = float(&[
            (0.0, 0.0, BSpline),
            (0.25, 0.0, BSpline),
            (0.5, 6.0, BSpline),
            (0.75, 0.0, BSpline),
            (1.0, 0.0, BSpline),
        ]);
        close(even.eval_float(0.5), (0.0 + 4.0 * 6.0 + 0.0) / 6.0);
        close(even.eval_float(0.25), (0.0 + 0.0 + 6.0) / 6.0);
    }

    #[test]
    fn two_bspline_keys_are_a_straight_line() {
        let r = float(&[(0.0, 1.0, BSpline), (0.5, 2.0, BSpline)]);
        for k in 0..=10 {
            let x = 0.05 * f64::from(k);
            assert!((r.eval_float(x) - (1.0 + 2.0 * x)).abs() < 1e-9);
        }
    }

    #[test]
    fn a_bspline_run_joins_its_neighbours_continuously() {
        let r = float(&[
            (0.0, 0.0, Linear),
            (0.3, 1.0, BSpline),
            (0.5, 0.0, BSpline),
            (0.7, 1.0, Linear),
            (1.0, 0.0, Linear),
        ]);
        close(r.eval_float(0.3), 1.0);
        close(r.eval_float(0.7), 1.0);
        close(r.eval_float(0.15), 0.5);
        close(r.eval_float(0.85), 0.5);
        let d = 1e-9;
        assert!((r.eval_float(0.7 - d) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn colour_ramps_interpolate_each_channel() {
        let r = Ramp::new(
            RampKind::Color,
            vec![
                RampKey::color(0.0, [0.0, 0.0, 0.0], Linear),
                RampKey::color(1.0, [1.0, 0.0, 0.2], Linear),
            ],
        )
        .unwrap();
        let v = r.eval(0.5);
        close(v[0], 0.5);
        close(v[1], 0.0);
        close(v[2], 0.1);
        close(r.eval_float(0.25), 0.25);
    }

    #[test]
    fn float_ramps_drop_extra_components() {
        let r = Ramp::new(
            RampKind::Float,
            vec![RampKey::color(0.0, [1.0, 2.0, 3.0], Linear)],
        )
        .unwrap();
        assert_eq!(r.keys()[0].value, [1.0, 0.0, 0.0]);
        assert_eq!(r.eval(0.0), [1.0, 0.0, 0.0]);
    }
}
