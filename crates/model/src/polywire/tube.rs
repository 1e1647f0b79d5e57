//! One chain's tube: its shape (directions, arc length, parallel-transported
//! frames, radii) and its rings of points, from the ring that starts it to
//! the one that ends it, joined by quads.

use std::f64::consts::TAU;

use geode_geo::glam::{DQuat, DVec3, Vec2, Vec3};

use super::graph::{Chain, Edge};
use crate::carry::Blend;

/// A chain's geometry in f64.
pub(super) struct Shape {
    pub pos: Vec<DVec3>,
    /// Per edge: unit direction along the chain, length, and frame
    /// `(u, v)` with `u x v = dir`.
    pub dir: Vec<DVec3>,
    pub len: Vec<f64>,
    pub frame: Vec<(DVec3, DVec3)>,
    /// Arc length at each chain point.
    pub s: Vec<f64>,
    /// Radius at each chain point.
    pub radius: Vec<f64>,
    /// Per edge: the source points and vertices at its start and end (in
    /// the chain's direction), and its primitive.
    pub src: Vec<([u32; 2], [u32; 2], u32)>,
    pub closed: bool,
}

/// One ring of `n` points around a chain.
pub(super) struct Ring {
    pub pts: Vec<Vec3>,
    pub point_blend: Blend,
    pub vertex_blend: Blend,
    pub prim: u32,
    /// Arc-length fraction along the chain (the `v` of `uv`).
    pub v: f32,
}

impl Shape {
    pub fn new(chain: &Chain, edges: &[Edge], p: &[Vec3], radius: &dyn Fn(u32) -> f64) -> Shape {
        let pos: Vec<DVec3> = chain
            .points
            .iter()
            .map(|&i| p[i as usize].as_dvec3())
            .collect();
        let m = chain.edges.len();
        let mut dir = Vec::with_capacity(m);
        let mut len = Vec::with_capacity(m);
        let mut s = vec![0.0];
        let mut src = Vec::with_capacity(m);
        for (k, &(e, backwards)) in chain.edges.iter().enumerate() {
            let d = pos[k + 1] - pos[k];
            len.push(d.length());
            dir.push(d / d.length());
            s.push(s[k] + d.length());
            let e = &edges[e as usize];
            src.push(if backwards {
                ([e.b, e.a], [e.vb, e.va], e.prim)
            } else {
                ([e.a, e.b], [e.va, e.vb], e.prim)
            });
        }
        let frame = frames(&dir, chain.closed);
        let radius = chain.points.iter().map(|&i| radius(i)).collect();
        Shape {
            pos,
            dir,
            len,
            frame,
            s,
            radius,
            src,
            closed: chain.closed,
        }
    }

    pub fn length(&self) -> f64 {
        *self.s.last().expect("a chain has a point")
    }

    /// The edge holding arc length `sigma` and the fraction along it; at a
    /// chain point, the edge after it when `after`, else the one before.
    pub fn locate(&self, sigma: f64, after: bool) -> (usize, f64) {
        let m = self.len.len();
        let k = if after {
            self.s[1..m].partition_point(|&x| x <= sigma)
        } else {
            self.s[1..m].partition_point(|&x| x < sigma)
        };
        let f = ((sigma - self.s[k]) / self.len[k]).clamp(0.0, 1.0);
        (k, f)
    }

    /// A ring across edge `k` at fraction `f`, its radius times `scale`.
    pub fn plain(&self, k: usize, f: f64, scale: f64, n: usize) -> Ring {
        let c = self.pos[k].lerp(self.pos[k + 1], f);
        let r = scale * (self.radius[k] + (self.radius[k + 1] - self.radius[k]) * f);
        let (u, v) = self.frame[k];
        let (pa, va, prim) = self.src[k];
        Ring {
            pts: circle(n)
                .map(|(c0, s0)| (c + r * (c0 * u + s0 * v)).as_vec3())
                .collect(),
            point_blend: (pa[0], pa[1], f as f32),
            vertex_blend: (va[0], va[1], f as f32),
            prim,
            v: ((self.s[k] + self.len[k] * f) / self.length()) as f32,
        }
    }

    /// The mitred ring at chain point `k` (between edges `k - 1` and `k`;
    /// point 0 of a loop joins its last edge to its first): the previous
    /// edge's circle carried along that edge onto the plane that bisects
    /// the bend, so both tubes meet it without a gap.
    pub fn miter(&self, k: usize, n: usize) -> Ring {
        let m = self.len.len();
        let before = if k == 0 { m - 1 } else { k - 1 };
        let (a, b) = (self.dir[before], self.dir[k % m]);
        let sum = a + b;
        let normal = if sum.length() < 1e-9 {
            a
        } else {
            sum.normalize()
        };
        // A hairpin's mitre would reach far out: its stretch is bounded.
        let along = a.dot(normal).max(0.25);
        let (u, v) = self.frame[before];
        let c = self.pos[k];
        let r = self.radius[k].min(self.miter_room(before, k % m, a.dot(b)));
        let (pa, va, prim) = self.src[k % m];
        Ring {
            pts: circle(n)
                .map(|(c0, s0)| {
                    let e = r * (c0 * u + s0 * v);
                    (c + e - a * (e.dot(normal) / along)).as_vec3()
                })
                .collect(),
            point_blend: (pa[0], pa[0], 0.0),
            vertex_blend: (va[0], va[0], 0.0),
            prim,
            v: (self.s[k] / self.length()) as f32,
        }
    }

    /// The widest radius a mitre between edges `before` and `after` (whose
    /// directions' dot product is `cos`) may have: its inner side reaches
    /// back `r tan(bend / 2)` along both edges, which must stay within half
    /// of each (the other half is the next ring's: a joint's rings keep
    /// within 0.45 of an edge) or the tube folds through itself. Narrower
    /// than the radius, the bend is pinched, as a joint's rings are.
    fn miter_room(&self, before: usize, after: usize, cos: f64) -> f64 {
        let cos = cos.clamp(-1.0, 1.0);
        let half_bend_tan = (1.0 - cos).max(0.0).sqrt() / (1.0 + cos).max(1e-12).sqrt();
        let room = 0.5 * self.len[before].min(self.len[after]);
        if half_bend_tan <= 1e-12 {
            f64::INFINITY
        } else {
            room / half_bend_tan
        }
    }

    /// The rings from arc length `from` to `to` (an open chain; the ends
    /// scaled by `scales`), or around a loop: mitres at the chain's
    /// points, `segments - 1` more across each edge (or the part of it
    /// the tube covers). A loop's first ring is not repeated at its end.
    pub fn rings(
        &self,
        from: f64,
        to: f64,
        scales: [f64; 2],
        n: usize,
        segments: usize,
    ) -> Vec<Ring> {
        let mut out = Vec::new();
        let m = self.len.len();
        if self.closed {
            for k in 0..m {
                out.push(self.miter(k, n));
                for q in 1..segments {
                    out.push(self.plain(k, q as f64 / segments as f64, 1.0, n));
                }
            }
            return out;
        }
        let (k0, f0) = self.locate(from, true);
        let (k1, f1) = self.locate(to, false);
        out.push(self.plain(k0, f0, scales[0], n));
        for k in k0..=k1 {
            let lo = if k == k0 { f0 } else { 0.0 };
            let hi = if k == k1 { f1 } else { 1.0 };
            for q in 1..segments {
                out.push(self.plain(k, lo + (hi - lo) * q as f64 / segments as f64, 1.0, n));
            }
            if k < k1 {
                out.push(self.miter(k + 1, n));
            }
        }
        out.push(self.plain(k1, f1, scales[1], n));
        out
    }
}

/// `(cos, sin)` of `n` angles evenly around the circle.
fn circle(n: usize) -> impl Iterator<Item = (f64, f64)> {
    (0..n).map(move |j| {
        let a = TAU * j as f64 / n as f64;
        (a.cos(), a.sin())
    })
}

/// Frames carried along the edges by the smallest rotation between
/// successive directions (parallel transport, so tubes do not twist); a
/// loop's leftover turn is spread evenly over its edges.
fn frames(dir: &[DVec3], closed: bool) -> Vec<(DVec3, DVec3)> {
    let d0 = dir[0];
    let axis = if d0.x.abs() <= d0.y.abs() && d0.x.abs() <= d0.z.abs() {
        DVec3::X
    } else if d0.y.abs() <= d0.z.abs() {
        DVec3::Y
    } else {
        DVec3::Z
    };
    let mut u = vec![(axis - d0 * axis.dot(d0)).normalize()];
    for k in 1..dir.len() {
        let next = transport(u[k - 1], dir[k - 1], dir[k]);
        u.push(next);
    }
    if closed {
        let m = dir.len();
        let back = transport(u[m - 1], dir[m - 1], d0);
        let turn = u[0].cross(back).dot(d0).atan2(u[0].dot(back));
        for (k, uk) in u.iter_mut().enumerate() {
            *uk = DQuat::from_axis_angle(dir[k], -turn * k as f64 / m as f64) * *uk;
        }
    }
    u.iter().zip(dir).map(|(&u, &d)| (u, d.cross(u))).collect()
}

/// `u` (perpendicular to `from`) turned by the smallest rotation taking
/// `from` to `to`, made exactly perpendicular to `to`.
fn transport(u: DVec3, from: DVec3, to: DVec3) -> DVec3 {
    let turned = DQuat::from_rotation_arc(from, to) * u;
    let w = turned - to * turned.dot(to);
    if w.length() > 1e-12 {
        w.normalize()
    } else {
        to.any_orthonormal_vector()
    }
}

/// The `uv` of ring point `j` of `n`, `seam` giving u = 1 for j = 0.
pub(super) fn uv(ring: &Ring, j: usize, n: usize, seam: bool) -> Vec2 {
    let u = if seam && j == 0 {
        1.0
    } else {
        j as f32 / n as f32
    };
    Vec2::new(u, ring.v)
}
