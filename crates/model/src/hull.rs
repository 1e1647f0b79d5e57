//! The convex hull of a geometry's points: 3D quickhull (Barber, Dobkin
//! and Huhdanpaa) with exact orientation tests, so coplanar and duplicate
//! points need no tolerance.
//!
//! Quickhull starts from a tetrahedron of extreme points, gives every
//! point outside it to the first face it lies strictly above, and then,
//! face by face, takes the farthest point above a face (the eye), finds
//! the faces it sees (a walk over neighbours), replaces them by a fan from
//! the eye to their horizon, and hands their points to the first new face
//! each lies strictly above (the rest are inside and drop out).
//!
//! Every above/below decision is `exact::orient3d` (filtered, exact when
//! the filter cannot decide), so no tolerance decides anything. A point
//! on a face's plane is not outside it (repeated points and points inside
//! the hull's faces are never eyes), while a face whose plane holds the
//! eye is replaced with the faces the eye sees (so a point that became a
//! vertex early and ends inside a flat face of the hull drops out). Each
//! step keeps the hull convex (a new face meets the face beyond the
//! horizon at a strictly convex edge) and the hull's vertices are exactly
//! its extreme points, as Qhull's are. The hull is triangles wound outward (faces
//! on one plane stay separate triangles). Distances that only pick the
//! eye are f64. The sequence of steps depends on the input alone, so the
//! result is deterministic; the first assignment and large reassignments
//! run in parallel, in order.
//!
//! All points coplanar (exactly): the 2D hull, one polygon, by Andrew's
//! monotone chain in the coordinate plane the hull's plane projects onto
//! best (an affine map of the plane, so orientations carry over exactly),
//! wound so its normal has a positive dominant component. All collinear:
//! a polyline between the two extreme points. One distinct point: that
//! point alone.
//!
//! Points carry their attributes and groups (with `keep_used_only`, only
//! the hull's vertices stay); faces are new and carry none.

mod exact;
mod quickhull;

use std::cmp::Ordering;

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry, PrimKind};
use rayon::prelude::*;

pub use exact::{orient2d, orient3d};
use quickhull::Quickhull;

use crate::ModelError;

/// The convex hull of `g`'s points (see the module doc); with
/// `keep_used_only`, only the hull's vertices are kept.
pub fn convex_hull(
    g: &Geometry,
    keep_used_only: bool,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let p = g.positions();
    if let Some(i) = p.iter().position(|x| !x.is_finite()) {
        return Err(ModelError::Invalid(format!(
            "point {i} is not finite ({:?}): a hull needs finite positions",
            p[i]
        )));
    }
    let simplex = Simplex::find(p);
    let single = match simplex {
        Simplex::Point(i) => Some(i),
        _ => None,
    };
    let (counts, vertices, kind) = match simplex {
        Simplex::Empty | Simplex::Point(_) => (Vec::new(), Vec::new(), PrimKind::Polygon),
        Simplex::Segment(a, b) => (vec![2], vec![a.min(b), a.max(b)], PrimKind::Polyline),
        Simplex::Triangle(a, b, c) => {
            let ring = hull_2d(p, [a, b, c]);
            (vec![ring.len() as u32], ring, PrimKind::Polygon)
        }
        Simplex::Tetrahedron(t) => {
            let faces = Quickhull::new(p, t, cancel)?.run(cancel)?;
            (vec![3; faces.len()], faces.concat(), PrimKind::Polygon)
        }
    };
    output(g, counts, vertices, kind, keep_used_only, single)
}

/// What the points span, for callers that want the solid hull's triangles
/// alone (the oriented box's candidate directions).
pub(crate) enum Span {
    /// The hull's triangles over the points' indices, wound outward.
    Solid(Vec<[u32; 3]>),
    /// All points on one plane (its unit normal).
    Flat(Vec3),
    /// All on one line or one point, or none.
    Lower,
}

/// The span of `p` and, when solid, its hull's triangles.
pub(crate) fn span(p: &[Vec3], cancel: &(dyn Fn() -> bool + Sync)) -> Result<Span, ModelError> {
    Ok(match Simplex::find(p) {
        Simplex::Tetrahedron(t) => Span::Solid(Quickhull::new(p, t, cancel)?.run(cancel)?),
        Simplex::Triangle(a, b, c) => {
            let at = |i: u32| p[i as usize].as_dvec3();
            let n = (at(b) - at(a)).cross(at(c) - at(a)).normalize_or_zero();
            Span::Flat(n.as_vec3())
        }
        Simplex::Empty | Simplex::Point(_) | Simplex::Segment(..) => Span::Lower,
    })
}

/// The first points spanning the hull's dimension.
enum Simplex {
    Empty,
    Point(u32),
    Segment(u32, u32),
    Triangle(u32, u32, u32),
    Tetrahedron([u32; 4]),
}

impl Simplex {
    fn find(p: &[Vec3]) -> Simplex {
        if p.is_empty() {
            return Simplex::Empty;
        }
        let extremes = extremes(p);
        let mut pair = (extremes[0], extremes[0], 0.0);
        for (k, &i) in extremes.iter().enumerate() {
            for &j in &extremes[k + 1..] {
                let d = p[i as usize]
                    .as_dvec3()
                    .distance_squared(p[j as usize].as_dvec3());
                if d > pair.2 {
                    pair = (i.min(j), i.max(j), d);
                }
            }
        }
        let (a, b, _) = pair;
        if pair.2 == 0.0 {
            return Simplex::Point(a);
        }
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let line = pb.as_dvec3() - pa.as_dvec3();
        let Some(c) = farthest(p, |x| {
            if collinear(pa, pb, x) {
                None
            } else {
                Some((x.as_dvec3() - pa.as_dvec3()).cross(line).length_squared())
            }
        }) else {
            return Simplex::Segment(a, b);
        };
        let pc = p[c as usize];
        let normal = line.cross(pc.as_dvec3() - pa.as_dvec3());
        let Some(d) = farthest(p, |x| {
            if orient3d(pa, pb, pc, x) == Ordering::Equal {
                None
            } else {
                Some((x.as_dvec3() - pa.as_dvec3()).dot(normal).abs())
            }
        }) else {
            return Simplex::Triangle(a, b, c);
        };
        Simplex::Tetrahedron([a, b, c, d])
    }
}

/// The lowest-numbered points of least and greatest x, y and z.
fn extremes(p: &[Vec3]) -> [u32; 6] {
    let mut e = [0u32; 6];
    for (i, x) in p.iter().enumerate() {
        for axis in 0..3 {
            if x[axis] < p[e[2 * axis] as usize][axis] {
                e[2 * axis] = i as u32;
            }
            if x[axis] > p[e[2 * axis + 1] as usize][axis] {
                e[2 * axis + 1] = i as u32;
            }
        }
    }
    e
}

/// The point of greatest `measure` (None: not a candidate); the lowest
/// numbered of equals.
fn farthest(p: &[Vec3], measure: impl Fn(Vec3) -> Option<f64> + Sync) -> Option<u32> {
    p.par_iter()
        .enumerate()
        .with_min_len(1 << 14)
        .filter_map(|(i, &x)| measure(x).map(|m| (m, i as u32)))
        .reduce_with(|a, b| match a.0.total_cmp(&b.0) {
            Ordering::Less => b,
            Ordering::Greater => a,
            Ordering::Equal => (a.0, a.1.min(b.1)),
        })
        .map(|(_, i)| i)
}

/// Whether three points lie on one line (exactly: every coordinate
/// projection is degenerate).
fn collinear(a: Vec3, b: Vec3, c: Vec3) -> bool {
    [(0, 1), (1, 2), (2, 0)]
        .iter()
        .all(|&(i, j)| orient2d([a[i], a[j]], [b[i], b[j]], [c[i], c[j]]) == Ordering::Equal)
}

/// The hull of coplanar points: a ring anticlockwise about the axis the
/// plane (through `t`) faces most.
fn hull_2d(p: &[Vec3], t: [u32; 3]) -> Vec<u32> {
    let [a, b, c] = t.map(|i| p[i as usize].as_dvec3());
    let axis = (b - a).cross(c - a).abs().max_position();
    let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
    let q = |k: u32| [p[k as usize][i], p[k as usize][j]];
    let mut order: Vec<u32> = (0..p.len() as u32).collect();
    order.par_sort_unstable_by(|&x, &y| {
        let (qx, qy) = (q(x), q(y));
        qx[0]
            .total_cmp(&qy[0])
            .then(qx[1].total_cmp(&qy[1]))
            .then(x.cmp(&y))
    });
    let chain = |pts: &mut dyn Iterator<Item = u32>| {
        let mut h: Vec<u32> = Vec::new();
        for k in pts {
            while h.len() >= 2
                && orient2d(q(h[h.len() - 2]), q(h[h.len() - 1]), q(k)) != Ordering::Greater
            {
                h.pop();
            }
            h.push(k);
        }
        h.pop();
        h
    };
    let mut ring = chain(&mut order.iter().copied());
    ring.extend(chain(&mut order.iter().rev().copied()));
    ring
}

/// The output: the hull's primitives over the input's points (all of
/// them, or those used, renumbered), point attributes and groups carried.
fn output(
    g: &Geometry,
    counts: Vec<u32>,
    vertices: Vec<u32>,
    kind: PrimKind,
    keep_used_only: bool,
    single: Option<u32>,
) -> Result<Geometry, ModelError> {
    let failed = |e: geode_geo::GeoError| ModelError::Failed {
        op: "convex hull",
        why: e.to_string(),
    };
    let kept: Vec<u32> = if keep_used_only {
        let mut used = vec![false; g.num_points()];
        vertices.iter().for_each(|&v| used[v as usize] = true);
        if let Some(i) = single {
            used[i as usize] = true;
        }
        (0..g.num_points() as u32)
            .filter(|&i| used[i as usize])
            .collect()
    } else {
        (0..g.num_points() as u32).collect()
    };
    let mut index = vec![u32::MAX; g.num_points()];
    for (k, &i) in kept.iter().enumerate() {
        index[i as usize] = k as u32;
    }
    let positions = kept.iter().map(|&i| g.positions()[i as usize]).collect();
    let vertices = vertices.iter().map(|&v| index[v as usize]).collect();
    let kinds = vec![kind; counts.len()];
    let mut out = Geometry::from_prims(positions, vertices, &counts, kinds).map_err(failed)?;
    for (name, attr) in g.attribs(AttribClass::Point).iter() {
        if name != geode_geo::P {
            out.set_attrib(AttribClass::Point, name, attr.gather(&kept))
                .map_err(failed)?;
        }
    }
    for (name, group) in g.point_groups() {
        out.set_point_group(name, group.gather(&kept))
            .map_err(failed)?;
    }
    for (name, attr) in g.attribs(AttribClass::Detail).iter() {
        out.set_attrib(AttribClass::Detail, name, attr.clone())
            .map_err(failed)?;
    }
    Ok(out)
}
