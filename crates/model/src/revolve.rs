//! Surfaces of revolution (Houdini's Revolve SOP): each polyline or
//! polygon outline turned about an axis from a start to an end angle in
//! `divisions` steps.
//!
//! Every point the curves use is copied once per step (shared by every
//! curve through it), rotated about the axis in f64 (right-handed: counter-
//! clockwise seen from the axis's tip). A point on the axis is one point,
//! a pole: the faces next to it are triangles, not quads with a repeated
//! corner, so a half circle with its ends on the axis turns into a closed
//! sphere with no degenerate face. A full turn (a multiple of 360 degrees)
//! joins the last step to the first; otherwise a closed curve gets caps at
//! both ends (its outline as an n-gon) when asked.
//!
//! Winding: a profile that runs along the axis's direction on the far
//! side of the axis (a closed profile anticlockwise in the half-plane of
//! radius and height) gives outward normals, whichever way the angles
//! run (a negative sweep is rewound to match).
//!
//! Point attributes are copied to every step with directions turned with
//! it (`Vector` and `Normal` vectors rotate, `Position` ones rotate about
//! the axis, `Quaternion`s are pre-multiplied); vertex attributes come
//! from the curve's vertex at each corner, turned likewise; faces copy
//! their curve's primitive attributes and groups. `uv` (optional, per
//! vertex) runs around the axis in u (0 to 1 over the sweep) and along the
//! curve by arc length in v.

use geode_geo::glam::{DQuat, DVec3, Quat, Vec2, Vec3};
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, PrimKind, TypeInfo, P};

use crate::carry::{self, copy, Plan};
use crate::ModelError;

#[derive(Clone, Debug)]
pub struct RevolveOptions {
    /// A point of the axis.
    pub origin: Vec3,
    /// The axis's direction.
    pub axis: Vec3,
    /// Degrees.
    pub start_angle: f32,
    pub end_angle: f32,
    /// Steps around the axis (at least one).
    pub divisions: u32,
    /// Close a closed curve's partial revolution with its outline at
    /// both ends.
    pub caps: bool,
    /// Write vertex `uv`.
    pub uv: bool,
}

impl Default for RevolveOptions {
    fn default() -> Self {
        RevolveOptions {
            origin: Vec3::ZERO,
            axis: Vec3::Y,
            start_angle: 0.0,
            end_angle: 360.0,
            divisions: 16,
            caps: true,
            uv: false,
        }
    }
}

/// Revolves the curves of `g` (see the module doc).
pub fn revolve(
    g: &Geometry,
    options: &RevolveOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let sweep = Sweep::new(options)?;
    carry::polygons_and_polylines(g, "revolve")?;
    let mut plan = Plan::default();
    let rings = sweep.place_points(g, &mut plan);
    let mut corners = Corners::default();
    for prim in 0..g.num_prims() {
        if prim % 1024 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        sweep.faces(g, prim, &rings, options.caps, &mut plan, &mut corners);
    }
    plan.first_new_prim = plan.prim_kinds.len();
    let mut out = carry::build(g, plan, "revolve", cancel)?;
    sweep.turn_attributes(&mut out, AttribClass::Point, &rings.point_step);
    sweep.turn_attributes(&mut out, AttribClass::Vertex, &corners.step);
    if options.uv {
        let uv = Attribute::from_data(AttribData::Vec2(corners.uv), TypeInfo::TexCoord);
        out.set_attrib(AttribClass::Vertex, "uv", uv)
            .map_err(|e| ModelError::Failed {
                op: "revolve",
                why: e.to_string(),
            })?;
    }
    Ok(out)
}

/// The steps of the revolution.
struct Sweep {
    origin: DVec3,
    axis: DVec3,
    /// Radians of each step, `steps` of them.
    angles: Vec<f64>,
    divisions: usize,
    full: bool,
    /// The sweep runs clockwise (faces are rewound).
    backwards: bool,
}

/// Where each input point's copies are.
struct Rings {
    /// The output number of the first copy of each point (u32::MAX: no
    /// curve uses it).
    first: Vec<u32>,
    pole: Vec<bool>,
    /// The step of each output point.
    point_step: Vec<u32>,
}

/// Per output vertex: its step, and its uv when asked.
#[derive(Default)]
struct Corners {
    step: Vec<u32>,
    uv: Vec<Vec2>,
}

impl Sweep {
    fn new(o: &RevolveOptions) -> Result<Sweep, ModelError> {
        let axis = o.axis.as_dvec3();
        if !axis.is_finite() || axis.length() == 0.0 {
            return Err(ModelError::Invalid(
                "the revolve axis has no direction".into(),
            ));
        }
        if o.divisions == 0 {
            return Err(ModelError::Invalid(
                "a revolve needs at least one division".into(),
            ));
        }
        let span = o.end_angle as f64 - o.start_angle as f64;
        if span == 0.0 || !span.is_finite() {
            return Err(ModelError::Invalid(
                "the start and end angles are equal: nothing to revolve".into(),
            ));
        }
        let turns = span.abs() / 360.0;
        let full = turns >= 1.0 - 1e-9 && (turns - turns.round()).abs() < 1e-9;
        let divisions = o.divisions as usize;
        let steps = if full { divisions } else { divisions + 1 };
        let angles = (0..steps)
            .map(|k| (o.start_angle as f64 + span * k as f64 / divisions as f64).to_radians())
            .collect();
        Ok(Sweep {
            origin: o.origin.as_dvec3(),
            axis: axis.normalize(),
            angles,
            divisions,
            full,
            backwards: span < 0.0,
        })
    }

    fn rotation(&self, step: u32) -> DQuat {
        DQuat::from_axis_angle(self.axis, self.angles[step as usize])
    }

    /// Copies every point a curve uses once per step (a pole once, moved
    /// onto the axis).
    fn place_points(&self, g: &Geometry, plan: &mut Plan) -> Rings {
        let mut used = vec![false; g.num_points()];
        for &p in g.vertex_points() {
            used[p as usize] = true;
        }
        let p = g.positions();
        let extent = p
            .iter()
            .map(|x| (x.as_dvec3() - self.origin).length())
            .fold(0.0, f64::max);
        let tolerance = 1e-6 * extent.max(1e-30);
        let mut rings = Rings {
            first: vec![u32::MAX; g.num_points()],
            pole: vec![false; g.num_points()],
            point_step: Vec::new(),
        };
        let rotations: Vec<DQuat> = (0..self.angles.len() as u32)
            .map(|k| self.rotation(k))
            .collect();
        for (i, x) in p.iter().enumerate() {
            if !used[i] {
                continue;
            }
            let r = x.as_dvec3() - self.origin;
            let along = r.dot(self.axis) * self.axis;
            rings.first[i] = plan.positions.len() as u32;
            if (r - along).length() <= tolerance {
                rings.pole[i] = true;
                plan.positions.push((self.origin + along).as_vec3());
                plan.point_sources.push(copy(i as u32));
                rings.point_step.push(0);
                continue;
            }
            for (k, q) in rotations.iter().enumerate() {
                plan.positions.push((self.origin + *q * r).as_vec3());
                plan.point_sources.push(copy(i as u32));
                rings.point_step.push(k as u32);
            }
        }
        rings
    }

    /// The faces swept by curve `prim` (and its caps).
    fn faces(
        &self,
        g: &Geometry,
        prim: usize,
        rings: &Rings,
        caps: bool,
        plan: &mut Plan,
        corners: &mut Corners,
    ) {
        let pts = g.prim_points(prim);
        let first_vertex = g.prim_vertex_range(prim).start as u32;
        let closed = g.prim_kind(prim) == PrimKind::Polygon;
        let n = pts.len();
        let arc = arc_lengths(g, pts, closed);
        let d = self.divisions;
        // A corner: position `i` along the curve (n: the first again), step.
        let face = |plan: &mut Plan, corners: &mut Corners, list: &mut Vec<(usize, usize)>| {
            if self.backwards {
                list[1..].reverse();
            }
            for &(i, k) in list.iter() {
                let point = pts[i % n] as usize;
                let step = if rings.pole[point] {
                    0
                } else {
                    (k % self.angles.len()) as u32
                };
                plan.vertex_points.push(rings.first[point] + step);
                plan.vertex_sources
                    .push(copy(first_vertex + (i % n) as u32));
                corners.step.push(step);
                corners.uv.push(Vec2::new(
                    (k as f64 / d as f64) as f32,
                    (arc[i] / arc[n].max(f64::MIN_POSITIVE)) as f32,
                ));
            }
            plan.prim_counts.push(list.len() as u32);
            plan.prim_kinds.push(PrimKind::Polygon);
            plan.prim_sources.push(prim as u32);
        };
        let segments = if closed { n } else { n - 1 };
        let mut list = Vec::with_capacity(4);
        for i in 0..segments {
            let (a, b) = (pts[i] as usize, pts[(i + 1) % n] as usize);
            for k in 0..d {
                list.clear();
                match (rings.pole[a], rings.pole[b]) {
                    (true, true) => continue,
                    (true, false) => list.extend([(i, k), (i + 1, k + 1), (i + 1, k)]),
                    (false, true) => list.extend([(i, k), (i, k + 1), (i + 1, k)]),
                    (false, false) => list.extend([(i, k), (i, k + 1), (i + 1, k + 1), (i + 1, k)]),
                }
                face(plan, corners, &mut list);
            }
        }
        let distinct = pts.iter().filter(|&&p| !rings.pole[p as usize]).count();
        if caps && closed && !self.full && distinct >= 2 && n >= 3 {
            list.clear();
            list.extend((0..n).map(|i| (i, 0)));
            face(plan, corners, &mut list);
            list.clear();
            list.extend((0..n).rev().map(|i| (i, d)));
            face(plan, corners, &mut list);
        }
    }

    /// Turns the direction-like attributes of `class` by each element's
    /// step.
    fn turn_attributes(&self, g: &mut Geometry, class: AttribClass, steps: &[u32]) {
        let rotations: Vec<DQuat> = (0..self.angles.len() as u32)
            .map(|k| self.rotation(k))
            .collect();
        let names: Vec<String> = g
            .attribs(class)
            .iter()
            .filter(|(name, a)| {
                !(class == AttribClass::Point && *name == P)
                    && matches!(
                        (a.type_info, a.data()),
                        (
                            TypeInfo::Vector | TypeInfo::Normal | TypeInfo::Position,
                            AttribData::Vec3(_)
                        ) | (TypeInfo::Quaternion, AttribData::Quat(_))
                    )
            })
            .map(|(n, _)| n.to_string())
            .collect();
        for name in names {
            let attr = g.attribs_mut(class).get_mut(&name).expect("listed above");
            let position = attr.type_info == TypeInfo::Position;
            if let Some(v) = attr.as_vec3_mut() {
                for (x, &k) in v.iter_mut().zip(steps) {
                    let q = rotations[k as usize];
                    *x = if position {
                        (self.origin + q * (x.as_dvec3() - self.origin)).as_vec3()
                    } else {
                        (q * x.as_dvec3()).as_vec3()
                    };
                }
            } else if let Some(v) = attr.as_quat_mut() {
                for (x, &k) in v.iter_mut().zip(steps) {
                    let q = rotations[k as usize];
                    let turned = Quat::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32);
                    *x = (turned * *x).normalize();
                }
            }
        }
    }
}

/// Cumulative arc length at each corner of a curve (`n + 1` entries: the
/// last is the closed curve's whole length, or the open one's again).
fn arc_lengths(g: &Geometry, pts: &[u32], closed: bool) -> Vec<f64> {
    let p = g.positions();
    let n = pts.len();
    let mut arc = Vec::with_capacity(n + 1);
    arc.push(0.0);
    for i in 1..=n {
        let step = if i < n || closed {
            (p[pts[i % n] as usize].as_dvec3() - p[pts[i - 1] as usize].as_dvec3()).length()
        } else {
            0.0
        };
        arc.push(arc[i - 1] + step);
    }
    arc
}
