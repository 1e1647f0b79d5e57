//! Tensor-product NURBS surfaces: a grid of homogeneous control points with
//! a knot vector and degree per direction; points, first derivatives and
//! normals; exact knot insertion per direction; surfaces of revolution
//! (exact spheres, cylinders, tori from the rational circle); tessellation
//! into quads with normals and UVs.

use geode_geo::glam::{DVec3, DVec4, Vec2, Vec3};
use rayon::prelude::*;

use super::basis::{KnotError, Knots};
use super::curve::{lift, project, rational_derivatives, NurbsCurve};

#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    pub u: Knots,
    pub v: Knots,
    /// Homogeneous control points, `v` fastest: point (i, j) at `i * nv + j`.
    pub points: Vec<DVec4>,
}

/// A tessellated surface: a grid of points with normals and parameters,
/// and quads over it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tessellation {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub quads: Vec<[u32; 4]>,
}

impl Tessellation {
    /// The quads as geode geometry with point `N` and `uv`.
    pub fn into_geometry(self) -> Result<geode_geo::Geometry, geode_geo::GeoError> {
        use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
        let flat: Vec<u32> = self.quads.iter().flatten().copied().collect();
        let mut g = Geometry::from_polygons(self.positions, flat, &vec![4; self.quads.len()])?;
        g.set_attrib(
            AttribClass::Point,
            "N",
            Attribute::from_data(AttribData::Vec3(self.normals), TypeInfo::Normal),
        )?;
        g.set_attrib(
            AttribClass::Point,
            "uv",
            Attribute::from_data(AttribData::Vec2(self.uvs), TypeInfo::TexCoord),
        )?;
        Ok(g)
    }
}

impl NurbsSurface {
    pub fn new(u: Knots, v: Knots, points: Vec<DVec4>) -> Result<NurbsSurface, KnotError> {
        let (nu, nv) = (u.points(), v.points());
        if points.len() != nu * nv {
            return Err(KnotError::Count {
                found: points.len(),
                points: nu * nv,
                degree: u.degree,
                expected: nu * nv,
            });
        }
        Ok(NurbsSurface { u, v, points })
    }

    fn nv(&self) -> usize {
        self.v.points()
    }

    /// Homogeneous S, S_u, S_v at (u, v).
    fn homogeneous(&self, u: f64, v: f64) -> [DVec4; 3] {
        let (pu, pv) = (self.u.degree, self.v.degree);
        let (su, sv) = (self.u.span(u), self.v.span(v));
        let (du, dv) = (self.u.derivatives(su, u, 1), self.v.derivatives(sv, v, 1));
        let nv = self.nv();
        let mut out = [DVec4::ZERO; 3];
        for (a, (nu, nu1)) in du[0].iter().zip(&du[1]).enumerate() {
            for (b, (nv0, nv1)) in dv[0].iter().zip(&dv[1]).enumerate() {
                let p = self.points[(su - pu + a) * nv + sv - pv + b];
                out[0] += p * (nu * nv0);
                out[1] += p * (nu1 * nv0);
                out[2] += p * (nu * nv1);
            }
        }
        out
    }

    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        project(self.homogeneous(u, v)[0])
    }

    /// The point, the partial derivatives along u and v, and the unit normal
    /// (S_u x S_v, or its limit at a degenerate point such as a pole).
    pub fn frame(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3, DVec3) {
        let (p, su, sv) = self.first_derivatives(u, v);
        let n = su.cross(sv);
        let scale = (su.length() + sv.length()).powi(2);
        if n.length() > 1e-9 * scale {
            return (p, su, sv, n.normalize());
        }
        // A degenerate point (a pole): the normal is the limit of nearby
        // normals; look a hair inside the domain.
        let ((u0, u1), (v0, v1)) = (self.u.domain(), self.v.domain());
        let (eu, ev) = (1e-6 * (u1 - u0), 1e-6 * (v1 - v0));
        let nu = if u - u0 < u1 - u { u + eu } else { u - eu };
        let nv = if v - v0 < v1 - v { v + ev } else { v - ev };
        let (_, a, b) = self.first_derivatives(nu, nv);
        (p, su, sv, a.cross(b).normalize_or_zero())
    }

    fn first_derivatives(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let [h, hu, hv] = self.homogeneous(u, v);
        let du = rational_derivatives(&[h, hu]);
        let dv = rational_derivatives(&[h, hv]);
        (du[0], du[1], dv[1])
    }

    /// Inserts the knot `t` `times` times in the u (`along_u`) or v direction.
    pub fn insert_knot(&self, along_u: bool, t: f64, times: usize) -> NurbsSurface {
        let (nu, nv) = (self.u.points(), self.nv());
        let lines: Vec<NurbsCurve> = if along_u {
            (0..nv)
                .map(|j| NurbsCurve {
                    knots: self.u.clone(),
                    points: (0..nu).map(|i| self.points[i * nv + j]).collect(),
                })
                .collect()
        } else {
            (0..nu)
                .map(|i| NurbsCurve {
                    knots: self.v.clone(),
                    points: self.points[i * nv..(i + 1) * nv].to_vec(),
                })
                .collect()
        };
        let refined: Vec<NurbsCurve> = lines.iter().map(|c| c.insert_knot(t, times)).collect();
        let knots = refined[0].knots.clone();
        if along_u {
            let nu2 = knots.points();
            let mut points = vec![DVec4::ZERO; nu2 * nv];
            for (j, c) in refined.iter().enumerate() {
                for i in 0..nu2 {
                    points[i * nv + j] = c.points[i];
                }
            }
            NurbsSurface {
                u: knots,
                v: self.v.clone(),
                points,
            }
        } else {
            NurbsSurface {
                u: self.u.clone(),
                v: knots,
                points: refined.into_iter().flat_map(|c| c.points).collect(),
            }
        }
    }

    /// The surface swept by turning `profile` (in the XY plane, x >= 0)
    /// about +Y: exact, with the nine-point rational circle around. A
    /// profile running up +Y gives normals facing out.
    pub fn revolve(profile: &NurbsCurve) -> NurbsSurface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        // The circle's control points on the unit circle's square, in XZ.
        let dirs = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
            (1.0, 0.0),
        ];
        let weights = [1.0, w, 1.0, w, 1.0, w, 1.0, w, 1.0];
        let v = Knots {
            degree: 2,
            knots: vec![
                0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
            ],
        };
        let mut points = Vec::with_capacity(profile.points.len() * 9);
        for h in &profile.points {
            let p = project(*h);
            for (k, (c, s)) in dirs.iter().enumerate() {
                let q = DVec3::new(p.x * c, p.y, p.x * s);
                points.push(lift(q, h.w * weights[k]));
            }
        }
        NurbsSurface {
            u: profile.knots.clone(),
            v,
            points,
        }
    }

    /// An exact sphere about the origin.
    pub fn sphere(radius: f64) -> NurbsSurface {
        Self::revolve(&NurbsCurve::arcs(DVec3::ZERO, radius, 2))
    }

    /// An exact torus about +Y.
    pub fn torus(major: f64, minor: f64) -> NurbsSurface {
        Self::revolve(&NurbsCurve::circle(DVec3::new(major, 0.0, 0.0), minor))
    }

    /// An exact open cylinder about +Y, centred.
    pub fn cylinder(radius: f64, height: f64) -> NurbsSurface {
        let line = NurbsCurve::new(
            1,
            &[
                DVec3::new(radius, -height / 2.0, 0.0),
                DVec3::new(radius, height / 2.0, 0.0),
            ],
            None,
            None,
        )
        .expect("a line has valid knots");
        Self::revolve(&line)
    }

    /// `su` x `sv` samples over the domain: points, normals, (u, v) scaled
    /// to [0, 1], and quads facing along the normal.
    pub fn tessellate(&self, su: usize, sv: usize) -> Tessellation {
        let (su, sv) = (su.max(2), sv.max(2));
        let ((u0, u1), (v0, v1)) = (self.u.domain(), self.v.domain());
        let samples: Vec<(Vec3, Vec3, Vec2)> = (0..su * sv)
            .into_par_iter()
            .map(|k| {
                let (a, b) = (
                    (k / sv) as f64 / (su - 1) as f64,
                    (k % sv) as f64 / (sv - 1) as f64,
                );
                let (p, _, _, n) = self.frame(u0 + (u1 - u0) * a, v0 + (v1 - v0) * b);
                (p.as_vec3(), n.as_vec3(), Vec2::new(a as f32, b as f32))
            })
            .collect();
        let mut t = Tessellation::default();
        for (p, n, uv) in samples {
            t.positions.push(p);
            t.normals.push(n);
            t.uvs.push(uv);
        }
        let id = |i: usize, j: usize| (i * sv + j) as u32;
        for i in 0..su - 1 {
            for j in 0..sv - 1 {
                t.quads
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_revolved_semicircle_is_exactly_a_sphere_with_radial_normals() {
        let s = NurbsSurface::sphere(2.0);
        for i in 0..=40 {
            for j in 0..=40 {
                let (u, v) = (0.01 + 0.98 * i as f64 / 40.0, j as f64 / 40.0);
                let (p, _, _, n) = s.frame(u, v);
                assert!((p.length() - 2.0).abs() < 1e-12, "{u} {v}: {}", p.length());
                assert!(
                    n.dot(p / 2.0) > 1.0 - 1e-9,
                    "outward normal along the radius"
                );
            }
        }
        // Knot insertion in either direction keeps the surface.
        let r = s.insert_knot(true, 0.3, 2).insert_knot(false, 0.6, 1);
        for i in 0..=20 {
            for j in 0..=20 {
                let (u, v) = (i as f64 / 20.0, j as f64 / 20.0);
                assert!((r.point(u, v) - s.point(u, v)).length() < 1e-12);
            }
        }
    }

    #[test]
    fn a_torus_tessellates_into_a_closed_grid_of_the_right_area() {
        let s = NurbsSurface::torus(1.5, 0.5);
        let t = s.tessellate(200, 200);
        let mut area = 0.0f64;
        for q in &t.quads {
            let p = q.map(|i| t.positions[i as usize].as_dvec3());
            area += 0.5
                * ((p[1] - p[0]).cross(p[2] - p[0]).length()
                    + (p[2] - p[0]).cross(p[3] - p[0]).length());
        }
        let want = 4.0 * std::f64::consts::PI.powi(2) * 1.5 * 0.5;
        assert!((area - want).abs() / want < 1e-3, "{area} vs {want}");
    }
}
