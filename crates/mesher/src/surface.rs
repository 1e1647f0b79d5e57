//! The field as the adaptive stages read it: each brick's simplified tape
//! ([`RegionTapes`]), gradients, walks and rays to the surface, and the
//! first-order distance `|f| / |∇f|` ([`surface_distances`]). Below
//! `adaptive`, `refine` and `flip`, which all measure with it.

use geode_geo::glam::Vec3;
use rayon::prelude::*;

use crate::parts::par_fill_into;
use geode_frep::eval::{BatchGradEval, Grad};
use geode_frep::tape::Tape;

/// A mesh being changed: positions, normals, triangles.
pub(crate) type Mesh<'a> = (&'a mut Vec<Vec3>, &'a mut Vec<Vec3>, &'a mut Vec<[u32; 3]>);

/// The tapes the mesher simplified for each brick (each valid inside its
/// brick's box) and the field's whole tape for points outside every brick.
pub(crate) struct RegionTapes<'a> {
    root: &'a Tape,
    /// The bricks' tapes, in the order `brick_of` numbers them.
    tapes: Vec<&'a Tape>,
    /// Brick coordinates as (z, y, x), ascending (the tapes' order).
    keys: Vec<[usize; 3]>,
    /// Each grid brick's index in `tapes` (`u32::MAX`: none), z-major;
    /// empty when the grid is too large for one (then `keys` is searched).
    dense: Vec<u32>,
    /// Bricks per axis (x, y, z).
    dims: [usize; 3],
    origin: [f64; 3],
    /// A brick's side in model units.
    brick_side: f64,
}

/// Grid bricks up to which `brick_of` reads a dense table (4 MiB of
/// indices) rather than searching the meshed bricks.
const DENSE_BRICKS: usize = 1 << 20;

impl<'a> RegionTapes<'a> {
    /// The meshed bricks' tapes, keyed by brick coordinates (z, y, x) in
    /// ascending order, on a grid of `dims` bricks (x, y, z) of side
    /// `brick_side` from `origin`.
    pub(crate) fn new(
        root: &'a Tape,
        bricks: Vec<([usize; 3], &'a Tape)>,
        (origin, brick_side, dims): ([f64; 3], f64, [usize; 3]),
    ) -> RegionTapes<'a> {
        let (keys, tapes): (Vec<[usize; 3]>, Vec<&Tape>) = bricks.into_iter().unzip();
        let cells = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
        let dense = match cells {
            Some(n) if n <= DENSE_BRICKS => {
                let mut dense = vec![u32::MAX; n];
                for (i, k) in keys.iter().enumerate() {
                    if k[0] < dims[2] && k[1] < dims[1] && k[2] < dims[0] {
                        dense[(k[0] * dims[1] + k[1]) * dims[0] + k[2]] = i as u32;
                    }
                }
                dense
            }
            _ => Vec::new(),
        };
        RegionTapes {
            root,
            tapes,
            keys,
            dense,
            dims,
            origin,
            brick_side,
        }
    }

    /// One tape for every point.
    pub(crate) fn whole(root: &'a Tape) -> RegionTapes<'a> {
        RegionTapes::new(root, Vec::new(), ([0.0; 3], 1.0, [0; 3]))
    }

    /// The index of the brick holding `p`, or `u32::MAX` for the root tape.
    pub(crate) fn brick_of(&self, p: Vec3) -> u32 {
        let c: [f64; 3] =
            std::array::from_fn(|k| ((p[k] as f64 - self.origin[k]) / self.brick_side).floor());
        if c.iter().any(|x| !(*x >= 0.0 && *x < u32::MAX as f64)) {
            return u32::MAX;
        }
        let [x, y, z] = c.map(|x| x as usize);
        if !self.dense.is_empty() {
            let inside = x < self.dims[0] && y < self.dims[1] && z < self.dims[2];
            return if inside {
                self.dense[(z * self.dims[1] + y) * self.dims[0] + x]
            } else {
                u32::MAX
            };
        }
        self.keys
            .binary_search(&[z, y, x])
            .map_or(u32::MAX, |i| i as u32)
    }

    fn tape(&self, brick: u32) -> &'a Tape {
        self.tapes.get(brick as usize).copied().unwrap_or(self.root)
    }
}

/// Values and gradients at `points`, each evaluated with its brick's
/// simplified tape (points grouped by brick, groups in parallel).
pub(crate) fn grads_at<'a>(tapes: &RegionTapes<'a>, points: &[Vec3]) -> Vec<Grad> {
    // A handful of points (late passes of reduction) costs less on the
    // calling thread than waking the pool.
    let serial = points.len() < SERIAL_POINTS;
    let brick: Vec<u32> = if serial {
        points.iter().map(|p| tapes.brick_of(*p)).collect()
    } else {
        points.par_iter().map(|p| tapes.brick_of(*p)).collect()
    };
    let (order, lens) = group_by_brick(&brick, tapes.tapes.len());
    let mut sorted = vec![Grad::default(); points.len()];
    // An evaluator and a buffer of points, reused from group to group.
    type Scratch<'a> = (Option<BatchGradEval<'a>>, Vec<[f64; 3]>);
    let by_brick = |(eval, at): &mut Scratch<'a>, group: &[u32], out: &mut [Grad]| {
        let tape = tapes.tape(brick[group[0] as usize]);
        let eval = match eval {
            Some(e) => {
                e.set_tape(tape);
                e
            }
            // Made for the first group's tape (the root tape's registers
            // would be far more than a brick's needs).
            None => eval.insert(BatchGradEval::new(tape)),
        };
        at.clear();
        at.extend(
            group
                .iter()
                .map(|&i| points[i as usize].as_dvec3().to_array()),
        );
        eval.eval(at, out);
    };
    let mut starts = Vec::with_capacity(lens.len());
    let mut start = 0;
    for &len in &lens {
        starts.push(start);
        start += len;
    }
    let group = |i: usize| &order[starts[i]..starts[i] + lens[i]];
    if serial {
        let mut scratch = (None, Vec::new());
        for (i, &start) in starts.iter().enumerate() {
            by_brick(&mut scratch, group(i), &mut sorted[start..start + lens[i]]);
        }
    } else {
        par_fill_into(
            &mut sorted,
            &lens,
            || (None, Vec::new()),
            |scratch, i, out| by_brick(scratch, group(i), out),
        );
    }
    let mut out = vec![Grad::default(); points.len()];
    for (&i, g) in order.iter().zip(sorted) {
        out[i as usize] = g;
    }
    out
}

/// The points' indices grouped by brick (bricks ascending, the root
/// tape's group last, indices ascending within each: a counting sort),
/// and each non-empty group's length.
fn group_by_brick(brick: &[u32], bricks: usize) -> (Vec<u32>, Vec<usize>) {
    let slot = |b: u32| (b as usize).min(bricks);
    let mut counts = vec![0usize; bricks + 2];
    for &b in brick {
        counts[slot(b) + 1] += 1;
    }
    let lens: Vec<usize> = counts[1..].iter().copied().filter(|&n| n > 0).collect();
    for i in 0..=bricks {
        counts[i + 1] += counts[i];
    }
    let mut order = vec![0u32; brick.len()];
    for (i, &b) in brick.iter().enumerate() {
        let at = &mut counts[slot(b)];
        order[*at] = i as u32;
        *at += 1;
    }
    (order, lens)
}

/// Points below which values are computed on the calling thread. A pass of
/// reduction measures about a thousand points over hundreds of bricks,
/// which two threads share in about two thirds of the time (colonnade at
/// depth 7: 11-13 ms of measuring on one, 7-9.5 ms on two); below a few
/// hundred, waking the pool costs more than it saves.
const SERIAL_POINTS: usize = 256;

/// Newton steps of a walk to the surface.
const WALK_STEPS: usize = 3;

/// Where each point's walk along the gradient reaches the surface (Newton
/// steps `x - f ∇f / |∇f|²`, each evaluated with the tape of the brick it
/// is in), from the points and their values and gradients; returns the
/// feet with theirs.
pub(crate) fn walk_to_surface(
    tapes: &RegionTapes,
    points: &[Vec3],
    at_points: &[Grad],
) -> (Vec<Vec3>, Vec<Grad>) {
    let mut feet = points.to_vec();
    let mut grads = at_points.to_vec();
    for _ in 0..WALK_STEPS {
        feet.par_iter_mut()
            .zip(&grads)
            .for_each(|(x, g)| *x = newton(*x, g));
        grads = grads_at(tapes, &feet);
    }
    (feet, grads)
}

/// Probes each way along a line before bisecting its first sign change.
const RAY_STEPS: usize = 8;

/// Halvings of a bracketed sign change: 2^-12 of a probe step.
const RAY_HALVINGS: usize = 12;

/// Where the line through each start along its direction first meets the
/// surface within `reach` either way (the sign change of the field nearest
/// the start, bisected), with the value and gradient there; `None` where
/// the line meets none. Unlike a walk along the gradient, this finds the
/// nearest surface across the line even where the gradient leads to a
/// farther one (a field whose parts are scaled differently, joined by
/// min or max: the part deciding the value need not own the nearest
/// surface).
pub(crate) fn ray_feet(
    tapes: &RegionTapes,
    (starts, at_starts): (&[Vec3], &[Grad]),
    dirs: &[Vec3],
    reach: &[f32],
) -> Vec<Option<(Vec3, Grad)>> {
    let inside = |g: &Grad| g.v >= 0.0;
    let at = |i: usize, t: f32| starts[i] + dirs[i] * t;
    // Probes at growing distance, alternating sides: the first whose side
    // differs from the start's brackets the nearest crossing.
    let offsets: Vec<f32> = (1..=RAY_STEPS)
        .flat_map(|k| [k as f32, -(k as f32)])
        .map(|k| k / RAY_STEPS as f32)
        .collect();
    let probes: Vec<Vec3> = (0..starts.len())
        .flat_map(|i| offsets.iter().map(move |k| at(i, k * reach[i])))
        .collect();
    let at_probes = grads_at(tapes, &probes);
    // (last t on the start's side, first t past it) per bracketed start.
    let mut brackets: Vec<Option<(f32, f32)>> = (0..starts.len())
        .map(|i| {
            let side = inside(&at_starts[i]);
            let row = &at_probes[i * offsets.len()..(i + 1) * offsets.len()];
            let k = row
                .iter()
                .position(|g| g.v.is_finite() && inside(g) != side)?;
            let far = offsets[k] * reach[i];
            Some((far - offsets[k].signum() * reach[i] / RAY_STEPS as f32, far))
        })
        .collect();
    for _ in 0..RAY_HALVINGS {
        let mids: Vec<Vec3> = brackets
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.map(|(near, far)| at(i, 0.5 * (near + far))))
            .collect();
        let at_mids = grads_at(tapes, &mids);
        let mut next = at_mids.iter();
        for (i, b) in brackets.iter_mut().enumerate() {
            let Some((near, far)) = b.as_mut() else {
                continue;
            };
            let Some(g) = next.next() else { break };
            let mid = 0.5 * (*near + *far);
            if inside(g) == inside(&at_starts[i]) {
                *near = mid;
            } else {
                *far = mid;
            }
        }
    }
    let feet: Vec<Vec3> = brackets
        .iter()
        .enumerate()
        .filter_map(|(i, b)| b.map(|(near, far)| at(i, 0.5 * (near + far))))
        .collect();
    let mut at_feet = grads_at(tapes, &feet).into_iter().zip(feet);
    brackets
        .iter()
        .map(|b| b.and_then(|_| at_feet.next().map(|(g, p)| (p, g))))
        .collect()
}

/// One Newton step toward `f = 0` along the gradient (none where it vanishes).
fn newton(x: Vec3, g: &Grad) -> Vec3 {
    let d = geode_geo::glam::DVec3::from_array(g.d);
    let slope = d.length_squared();
    if slope > 0.0 && g.v.is_finite() {
        (x.as_dvec3() - d * (g.v / slope)).as_vec3()
    } else {
        x
    }
}

/// How far each point is from the surface of the field `tape` computes,
/// to first order: `|f| / |∇f|` (exact on a distance field; on others it
/// can read a few times too far or too near where the gradient turns, in
/// smooth blends). The measure adaptive output keeps within its tolerance,
/// public so a mesh from any mesher can be held to the same yardstick.
pub fn surface_distances(tape: &Tape, points: &[Vec3]) -> Vec<f32> {
    let whole = RegionTapes::whole(tape);
    let mut out = vec![0.0; points.len()];
    field_distances(&whole, points, &mut out);
    out
}

/// `|f| / |∇f|` at each point, with its brick's tape.
pub(crate) fn field_distances(tapes: &RegionTapes, points: &[Vec3], out: &mut [f32]) {
    for (o, g) in out.iter_mut().zip(grads_at(tapes, points)) {
        *o = distance_estimate(&g).abs();
    }
}

pub(crate) fn distance_estimate(g: &Grad) -> f32 {
    let slope = (g.d[0] * g.d[0] + g.d[1] * g.d[1] + g.d[2] * g.d[2]).sqrt();
    if slope > 0.0 && g.v.is_finite() {
        (g.v / slope) as f32
    } else {
        f32::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_frep::shapes::sphere;

    /// A ball of radius 0.5 joined to one of radius 0.3 whose field is
    /// scaled by 4: at `m`, 0.05 outside the first and 0.03 outside the
    /// second, the first decides the value (-0.05 against -0.12), so the
    /// walk along the gradient ends on the farther ball.
    #[test]
    fn a_ray_finds_the_nearer_surface_the_gradient_walk_misses() {
        let f = sphere([0.0; 3], 0.5).max(sphere([0.6, 0.0, 0.0], 0.3) * 4.0);
        let tape = Tape::compile(&f);
        let tapes = RegionTapes::whole(&tape);
        let x = (0.55f64 * 0.55 - 0.33 * 0.33 + 0.36) / 1.2;
        let m = Vec3::new(x as f32, (0.55f64 * 0.55 - x * x).sqrt() as f32, 0.0);
        let at_m = grads_at(&tapes, &[m]);
        assert!((at_m[0].v + 0.05).abs() < 1e-5, "{}", at_m[0].v);
        let (walked, _) = walk_to_surface(&tapes, &[m], &at_m);
        assert!((walked[0].distance(m) - 0.05).abs() < 1e-4);
        let toward = (Vec3::new(0.6, 0.0, 0.0) - m).normalize();
        let away = Vec3::new(0.0, 0.0, 1.0);
        let feet = ray_feet(
            &tapes,
            (&[m, m], &[at_m[0]; 2]),
            &[toward, away],
            &[0.1, 0.01],
        );
        let (foot, at_foot) = feet[0].expect("the second ball is 0.03 away along the ray");
        assert!(
            (foot.distance(m) - 0.03).abs() < 1e-4,
            "{}",
            foot.distance(m)
        );
        assert!(at_foot.v.abs() < 1e-4, "{}", at_foot.v);
        assert!(feet[1].is_none(), "nothing within 0.01 across the gap");
    }

    /// Bricks at (x, y, z) = (1, 0, 0), (0, 2, 0) and (3, 1, 2) of side 0.5
    /// from the origin, found by the dense table on a small grid and by
    /// searching on one too large for a table; outside them, the root.
    #[test]
    fn bricks_are_found_alike_by_table_and_by_search() {
        let tape = Tape::compile(&sphere([0.0; 3], 0.5));
        let keys = [[0, 0, 1], [0, 2, 0], [2, 1, 3]];
        let bricks = || keys.iter().map(|&k| (k, &tape)).collect::<Vec<_>>();
        let small = RegionTapes::new(&tape, bricks(), ([0.0; 3], 0.5, [4, 3, 3]));
        let huge = RegionTapes::new(&tape, bricks(), ([0.0; 3], 0.5, [1 << 11, 1 << 10, 4]));
        assert!(!small.dense.is_empty() && huge.dense.is_empty());
        let at = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let cases = [
            (at(0.6, 0.1, 0.2), 0),
            (at(0.2, 1.4, 0.49), 1),
            (at(1.7, 0.5, 1.0), 2),
            (at(0.2, 0.2, 0.2), u32::MAX),
            (at(-0.1, 1.2, 0.1), u32::MAX),
            (at(9.0, 0.2, 0.2), u32::MAX),
        ];
        for (p, want) in cases {
            assert_eq!(small.brick_of(p), want, "table at {p}");
            assert_eq!(huge.brick_of(p), want, "search at {p}");
        }
    }

    /// Points grouped by brick: bricks ascending, the root tape's last,
    /// indices ascending within each group, empty groups left out.
    #[test]
    fn points_group_by_brick_in_order() {
        let brick = [2, u32::MAX, 0, 2, 0, u32::MAX, 2];
        let (order, lens) = group_by_brick(&brick, 4);
        assert_eq!(order, [2, 4, 0, 3, 6, 1, 5]);
        assert_eq!(lens, [2, 3, 2]);
    }
}
