//! Sweeping a cross-section along a curve: a ring of the section per curve
//! point, placed in that point's frame (section X along the bitangent, Y
//! along the normal) and scaled; quads between rings (no twisting: the
//! frames are rotation-minimizing), end caps, and UVs around and along.

use geode_geo::glam::{Vec2, Vec3};

use crate::frames::Frame;
use crate::polyline::{
    arc_lengths,
    glam_d::{DVec2, DVec3},
};

#[derive(Clone, Debug, PartialEq)]
pub struct SweepOptions {
    /// The cross-section in its own XY plane (a closed one is made
    /// counter-clockwise so the tube faces outward).
    pub section: Vec<DVec2>,
    pub section_closed: bool,
    /// Close an open curve's ends with the section (closed sections only).
    pub caps: bool,
}

impl SweepOptions {
    /// A circle of `sides` around, radius 1 (scaled per point).
    pub fn circle(sides: usize, caps: bool) -> SweepOptions {
        let sides = sides.max(3);
        SweepOptions {
            section: (0..sides)
                .map(|j| {
                    let a = std::f64::consts::TAU * j as f64 / sides as f64;
                    DVec2::new(a.cos(), a.sin())
                })
                .collect(),
            section_closed: true,
            caps,
        }
    }
}

/// A swept surface as flat arrays: positions, polygon point indices with a
/// count per polygon, and a `uv` per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tube {
    pub positions: Vec<Vec3>,
    pub faces: Vec<u32>,
    pub counts: Vec<u32>,
    pub uvs: Vec<Vec2>,
}

impl Tube {
    /// Appends another tube (its indices shifted).
    pub fn append(&mut self, other: Tube) {
        let offset = self.positions.len() as u32;
        self.positions.extend(other.positions);
        self.faces
            .extend(other.faces.into_iter().map(|i| i + offset));
        self.counts.extend(other.counts);
        self.uvs.extend(other.uvs);
    }
}

fn signed_area(s: &[DVec2]) -> f64 {
    (0..s.len())
        .map(|i| {
            let (a, b) = (s[i], s[(i + 1) % s.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

/// Sweeps `opts.section` along one curve. `scales` multiplies the section
/// per point (a radius); `frames` come from [`crate::frames`]. `None` when
/// `cancel` (polled every 1024 rings) asks to stop.
pub fn sweep(
    points: &[DVec3],
    frames: &[Frame],
    scales: &[f64],
    closed: bool,
    opts: &SweepOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Option<Tube> {
    let n = points.len().min(frames.len()).min(scales.len());
    let mut section = opts.section.clone();
    if opts.section_closed && signed_area(&section) < 0.0 {
        section.reverse();
    }
    let m = section.len();
    let mut tube = Tube::default();
    if n < 2 || m < 2 {
        return Some(tube);
    }
    for i in 0..n {
        if i.is_multiple_of(1024) && cancel() {
            return None;
        }
        let f = &frames[i];
        for s in &section {
            let p = points[i] + scales[i] * (s.x * f.bitangent + s.y * f.normal);
            tube.positions.push(p.as_vec3());
        }
    }
    let (along, total) = arc_lengths(&points[..n], closed);
    let v = |i: usize| {
        if i == n {
            1.0
        } else if total > 0.0 {
            (along[i] / total) as f32
        } else {
            0.0
        }
    };
    // Around: fraction of the section's perimeter, 1 at the seam.
    let (around, perimeter) = arc_lengths(
        &section
            .iter()
            .map(|s| DVec3::new(s.x, s.y, 0.0))
            .collect::<Vec<_>>(),
        opts.section_closed,
    );
    let u = |j: usize| {
        if j == m {
            1.0
        } else if perimeter > 0.0 {
            (around[j] / perimeter) as f32
        } else {
            0.0
        }
    };
    let id = |i: usize, j: usize| ((i % n) * m + j % m) as u32;
    let rings = if closed { n } else { n - 1 };
    let columns = if opts.section_closed { m } else { m - 1 };
    for i in 0..rings {
        if i.is_multiple_of(1024) && cancel() {
            return None;
        }
        for j in 0..columns {
            tube.faces
                .extend_from_slice(&[id(i, j), id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)]);
            tube.uvs.extend_from_slice(&[
                Vec2::new(u(j), v(i)),
                Vec2::new(u(j + 1), v(i)),
                Vec2::new(u(j + 1), v(i + 1)),
                Vec2::new(u(j), v(i + 1)),
            ]);
            tube.counts.push(4);
        }
    }
    if opts.caps && !closed && opts.section_closed && m >= 3 {
        let (lo, hi) = section.iter().fold(
            (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
            |(a, b), s| (a.min(*s), b.max(*s)),
        );
        let size = (hi - lo).max(DVec2::splat(1e-300));
        let cap_uv = |j: usize| ((section[j] - lo) / size).as_vec2();
        // The start cap faces back along the curve, the end cap forward.
        for j in (0..m).rev() {
            tube.faces.push(id(0, j));
            tube.uvs.push(cap_uv(j));
        }
        for j in 0..m {
            tube.faces.push(id(n - 1, j));
            tube.uvs.push(cap_uv(j));
        }
        tube.counts.extend_from_slice(&[m as u32, m as u32]);
    }
    Some(tube)
}
