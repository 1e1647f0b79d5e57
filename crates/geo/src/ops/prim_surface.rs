//! Primitives as a searchable surface with Houdini's parametric
//! coordinates ("Primitive parametric spaces"): a triangle is
//! `P0 (1-u-v) + P1 u + P2 v`; a quad the bilinear patch
//! `P0 (1-u)(1-v) + P1 (1-u) v + P2 u v + P3 u (1-v)`; an n-gon a fan
//! around its vertices' average where each edge spans `1/n` of u and v runs
//! from the centre (0) to the boundary (1); a polyline has u uniform per
//! segment. The surface is triangles in a hierarchy (quads split on 0-2,
//! polylines as segments); a non-planar quad answers on those triangles,
//! its (u, v) fitted on the patch. The wrangle's `xyzdist`, `intersect`
//! and `primuv` and the ray node read it.

use glam::Vec3;

use super::raycast::{RayHit, TriangleBvh};
use crate::{Geometry, PrimKind};

impl PrimSurface {
    /// The surface of `prims` (in that order: ties go to the earlier).
    pub fn new(g: &Geometry, prims: &[usize]) -> PrimSurface {
        let (positions, tris, owner) = pieces(g, prims);
        PrimSurface {
            bvh: TriangleBvh::new(&positions, &tris),
            owner,
        }
    }

    /// The primitive of a triangle hit and its parametric (u, v) at
    /// `point`, from the triangle's barycentric weights.
    pub fn locate(
        &self,
        g: &Geometry,
        triangle: u32,
        point: Vec3,
        b1: f32,
        b2: f32,
    ) -> (u32, f32, f32) {
        let (prim, piece) = self.owner[triangle as usize];
        let (u, v) = prim_uv(g, prim, piece, point, b1, b2);
        (prim, u, v)
    }

    /// The first hit of the ray `orig + t dir`, t in (t_min, t_max), or
    /// with `farthest` the last (the first of the ray run backwards from
    /// t_max), with the point hit.
    pub fn hit(
        &self,
        orig: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        farthest: bool,
    ) -> Option<(RayHit, Vec3)> {
        if farthest {
            let end = orig + dir * t_max;
            let span = t_max - t_min;
            let hit = self
                .bvh
                .first_hit(end, -dir, -f32::MIN_POSITIVE, span, |_| false)?;
            let t = t_max - hit.t;
            (t > t_min).then(|| (RayHit { t, ..hit }, end - dir * hit.t))
        } else {
            let hit = self.bvh.first_hit(orig, dir, t_min, t_max, |_| false)?;
            Some((hit, orig + dir * hit.t))
        }
    }
}

/// The polygon's corners, in vertex order.
pub fn corners(g: &Geometry, prim: usize) -> Vec<Vec3> {
    g.prim_points(prim)
        .iter()
        .map(|&p| g.positions()[p as usize])
        .collect()
}

/// What a triangle of the searched surface is part of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Piece {
    Triangle,
    /// Quad triangle (0, 1, 2) or (0, 2, 3).
    QuadFirst,
    QuadSecond,
    /// n-gon: the fan triangle (centre, k, k + 1) of `sides` edges.
    Sector {
        k: u32,
        sides: u32,
    },
    /// Polyline segment k of `segments`, as the triangle (k, k+1, k+1).
    Segment {
        k: u32,
        segments: u32,
    },
}

/// A geometry's primitives as triangles in a hierarchy, each triangle
/// knowing its primitive and which piece of it it is.
pub struct PrimSurface {
    pub bvh: TriangleBvh,
    pub owner: Vec<(u32, Piece)>,
}

/// Primitives as triangles: the positions they use (the input's and each
/// n-gon's centre), the triangles, and what each is part of.
pub type Pieces = (Vec<Vec3>, Vec<[u32; 3]>, Vec<(u32, Piece)>);

/// The primitives' pieces (see `Pieces`).
pub fn pieces(g: &Geometry, prims: &[usize]) -> Pieces {
    let mut positions: Vec<Vec3> = g.positions().to_vec();
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let mut owner = Vec::new();
    for &prim in prims {
        let pts = g.prim_points(prim);
        let p = prim as u32;
        match (g.prim_kind(prim), pts.len()) {
            (PrimKind::Polygon, 3) => {
                tris.push([pts[0], pts[1], pts[2]]);
                owner.push((p, Piece::Triangle));
            }
            (PrimKind::Polygon, 4) => {
                tris.push([pts[0], pts[1], pts[2]]);
                owner.push((p, Piece::QuadFirst));
                tris.push([pts[0], pts[2], pts[3]]);
                owner.push((p, Piece::QuadSecond));
            }
            (PrimKind::Polygon, n) if n > 4 => {
                let centre = pts.iter().map(|&i| positions[i as usize]).sum::<Vec3>() / n as f32;
                let c = positions.len() as u32;
                positions.push(centre);
                for k in 0..n {
                    tris.push([c, pts[k], pts[(k + 1) % n]]);
                    owner.push((
                        p,
                        Piece::Sector {
                            k: k as u32,
                            sides: n as u32,
                        },
                    ));
                }
            }
            (PrimKind::Polyline, n) if n >= 2 => {
                for k in 0..n - 1 {
                    tris.push([pts[k], pts[k + 1], pts[k + 1]]);
                    owner.push((
                        p,
                        Piece::Segment {
                            k: k as u32,
                            segments: (n - 1) as u32,
                        },
                    ));
                }
            }
            _ => {}
        }
    }
    (positions, tris, owner)
}

/// The bilinear patch's point at (u, v).
pub fn bilinear(c: &[Vec3], u: f32, v: f32) -> Vec3 {
    c[0] * (1.0 - u) * (1.0 - v) + c[1] * (1.0 - u) * v + c[2] * u * v + c[3] * u * (1.0 - v)
}

/// The (u, v) of a quad's patch nearest `p`, by Gauss-Newton from a guess.
pub fn invert_bilinear(c: &[Vec3], p: Vec3, mut u: f32, mut v: f32) -> (f32, f32) {
    for _ in 0..8 {
        let r = bilinear(c, u, v) - p;
        let du = (c[3] - c[0]) * (1.0 - v) + (c[2] - c[1]) * v;
        let dv = (c[1] - c[0]) * (1.0 - u) + (c[2] - c[3]) * u;
        let (a, b, d) = (du.dot(du), du.dot(dv), dv.dot(dv));
        let det = a * d - b * b;
        if det.abs() < 1e-20 {
            break;
        }
        let (gu, gv) = (du.dot(r), dv.dot(r));
        u -= (d * gu - b * gv) / det;
        v -= (a * gv - b * gu) / det;
    }
    (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
}

/// The primitive's parametric (u, v) of a point found on its piece, from
/// the piece triangle's barycentric weights of corners 1 and 2.
pub fn prim_uv(g: &Geometry, prim: u32, piece: Piece, point: Vec3, b1: f32, b2: f32) -> (f32, f32) {
    match piece {
        Piece::Triangle => (b1, b2),
        Piece::QuadFirst | Piece::QuadSecond => {
            // On triangle (0,1,2) the guess from its weights: vertex 1 is
            // (0,1) and 2 is (1,1); on (0,2,3): 2 is (1,1) and 3 is (1,0).
            let (u, v) = match piece {
                Piece::QuadFirst => (b2, b1 + b2),
                _ => (b1 + b2, b1),
            };
            invert_bilinear(&corners(g, prim as usize), point, u, v)
        }
        Piece::Sector { k, sides } => {
            let rim = b1 + b2;
            let t = if rim > 0.0 { b2 / rim } else { 0.0 };
            ((k as f32 + t) / sides as f32, rim)
        }
        Piece::Segment { k, segments } => {
            // The segment triangle's corners 1 and 2 are both its end.
            let t = b1 + b2;
            ((k as f32 + t) / segments as f32, 0.0)
        }
    }
}

/// The weights of a primitive's vertices at (u, v); `None` outside the
/// shapes parametrised.
pub fn weights(g: &Geometry, prim: usize, u: f32, v: f32) -> Option<Vec<f32>> {
    let n = g.prim_vertex_range(prim).len();
    Some(match (g.prim_kind(prim), n) {
        (_, 1) => vec![1.0],
        (PrimKind::Polygon, 3) => vec![1.0 - u - v, u, v],
        (PrimKind::Polygon, 4) => vec![(1.0 - u) * (1.0 - v), (1.0 - u) * v, u * v, u * (1.0 - v)],
        (PrimKind::Polygon, n) if n > 4 => {
            // Centre (the average) times (1 - v), the rim point times v.
            let x = u.clamp(0.0, 1.0) * n as f32;
            let k = (x.floor() as usize).min(n - 1);
            let t = x - k as f32;
            let mut w = vec![(1.0 - v) / n as f32; n];
            w[k] += v * (1.0 - t);
            w[(k + 1) % n] += v * t;
            w
        }
        (PrimKind::Polyline, n) if n >= 2 => {
            let x = u.clamp(0.0, 1.0) * (n - 1) as f32;
            let k = (x.floor() as usize).min(n - 2);
            let t = x - k as f32;
            let mut w = vec![0.0; n];
            w[k] = 1.0 - t;
            w[k + 1] = t;
            w
        }
        _ => return None,
    })
}
