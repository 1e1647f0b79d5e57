//! Projections: texture coordinates read off positions through a frame
//! (Houdini's UV Project and UV Texture: planar, cylindrical, spherical,
//! and box, which projects each polygon along its dominant axis).
//!
//! Every position `P` is first taken into the projection's own space by
//! the inverse of [`ProjectOptions::frame`] (the frame's unit cube, centred
//! on its origin, is what maps onto the unit square). There:
//!
//! * **planar** along an axis A drops A and keeps the other two as seen
//!   from +A (never mirrored): along Z `(x, y)`, along X `(-z, y)`, along
//!   Y `(x, -z)`, each plus 0.5, so the frame's unit square covers [0,1]^2;
//! * **cylindrical** about an axis A (Y unless told) gives u the angle
//!   around A over a full turn (0 on +X for A = Y, growing towards -Z, so
//!   outward-facing polygons keep their orientation in uv) and v the
//!   height along A plus 0.5;
//! * **spherical** gives the same u and v the latitude, 0 at the -A pole
//!   and 1 at the +A pole;
//! * **box** projects each polygon planar along the axis (and sign) that
//!   dominates its normal in frame space, seen from outside the box: +Z
//!   `(x, y)`, -Z `(-x, y)`, +X `(-z, y)`, -X `(z, y)`, +Y `(x, -z)`, -Y
//!   `(x, z)`, each plus 0.5.
//!
//! Cylindrical and spherical u jumps from 1 back to 0 on the seam half
//! plane. A polygon (or polyline) crossing it would smear the whole
//! texture across itself, so its vertices' u are unwrapped along the
//! primitive (each vertex's u moved by whole turns to be within half a
//! turn of the previous one), which keeps the primitive continuous; u may
//! then leave [0,1] by less than one polygon's width, as Houdini's do.
//! Vertices on the axis (a sphere's poles, where u means nothing) take the
//! mean u of the primitive's other vertices. The result is finally scaled,
//! rotated and offset in uv space by [`UvTransform`].

mod map;
mod seam;

use geode_geo::glam::{EulerRot, Mat4, Quat, Vec2, Vec3};
use geode_geo::{Geometry, PrimKind};
use rayon::prelude::*;

use crate::error::UvError;
use map::{box_face, map_point};

/// One of the frame's axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Axis {
    X,
    #[default]
    Y,
    Z,
}

/// How positions become texture coordinates (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Projection {
    /// Along `axis` of the frame.
    Planar { axis: Axis },
    /// Around `axis` of the frame.
    Cylindrical { axis: Axis },
    /// Around `axis` of the frame, poles on it.
    Spherical { axis: Axis },
    /// Each polygon along its dominant normal axis.
    Box,
}

impl Default for Projection {
    fn default() -> Self {
        Projection::Planar { axis: Axis::Z }
    }
}

/// An affine change of the projected coordinates, applied last:
/// `uv' = R(rotate_degrees) * (scale * uv) + offset`, the rotation
/// counter-clockwise about uv's origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    pub scale: Vec2,
    pub rotate_degrees: f32,
    pub offset: Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform {
            scale: Vec2::ONE,
            rotate_degrees: 0.0,
            offset: Vec2::ZERO,
        }
    }
}

impl UvTransform {
    /// Applies the transform to one coordinate pair.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let (s, c) = self.rotate_degrees.to_radians().sin_cos();
        let p = uv * self.scale;
        Vec2::new(c * p.x - s * p.y, s * p.x + c * p.y) + self.offset
    }
}

/// Everything [`project`] needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectOptions {
    pub projection: Projection,
    /// Projection space to world space (the projection handle's
    /// placement). Build it with [`frame_from_trs`] or any invertible
    /// affine matrix; the identity projects the unit cube at the origin.
    pub frame: Mat4,
    pub transform: UvTransform,
}

impl Default for ProjectOptions {
    fn default() -> Self {
        ProjectOptions {
            projection: Projection::default(),
            frame: Mat4::IDENTITY,
            transform: UvTransform::default(),
        }
    }
}

/// A projection frame from a translation (its origin), rotations in
/// degrees about X, then Y, then Z (Houdini's default XYZ order), and a
/// size along each of its axes: `T * Rz * Ry * Rx * S`.
pub fn frame_from_trs(translate: Vec3, rotate_degrees: Vec3, scale: Vec3) -> Mat4 {
    let r = rotate_degrees * (std::f32::consts::PI / 180.0);
    let rotation = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
    Mat4::from_scale_rotation_translation(scale, rotation, translate)
}

/// Texture coordinates of every vertex of `g` (z = 0), in vertex order,
/// ready to be written as the vertex attribute `uv` (see
/// [`crate::write_uv`]). Packed and patch primitives' vertices are
/// projected like points; only polygons and polylines are unwrapped across
/// the seam. Fails only on a frame that cannot be inverted.
pub fn project(g: &Geometry, options: &ProjectOptions) -> Result<Vec<Vec3>, UvError> {
    let to_frame = inverse_frame(&options.frame)?;
    let positions = g.positions();
    let vertex_points = g.vertex_points();
    let projection = options.projection;
    let mut uv: Vec<Vec3> = vec![Vec3::ZERO; vertex_points.len()];
    match projection {
        Projection::Box => {
            let faces = box_faces(g, &to_frame);
            for_each_prim_block(g, &mut uv, |prims, block, first_vertex| {
                for prim in prims {
                    let range = g.prim_vertex_range(prim);
                    for v in range {
                        let local = to_frame.transform_point3(positions[vertex_points[v] as usize]);
                        let (u, w) = box_face(faces[prim], local);
                        block[v - first_vertex] = Vec3::new(u, w, 0.0);
                    }
                }
            });
        }
        _ => {
            uv.par_iter_mut()
                .zip(vertex_points.par_iter())
                .with_min_len(4096)
                .for_each(|(out, &p)| {
                    let local = to_frame.transform_point3(positions[p as usize]);
                    let m = map_point(projection, local);
                    // z marks vertices on the axis for the seam pass.
                    *out = Vec3::new(m.u, m.v, if m.on_axis { 1.0 } else { 0.0 });
                });
            if matches!(
                projection,
                Projection::Cylindrical { .. } | Projection::Spherical { .. }
            ) {
                for_each_prim_block(g, &mut uv, |prims, block, first_vertex| {
                    for prim in prims {
                        if matches!(g.prim_kind(prim), PrimKind::Polygon | PrimKind::Polyline) {
                            let r = g.prim_vertex_range(prim);
                            seam::unwrap_prim(
                                &mut block[r.start - first_vertex..r.end - first_vertex],
                            );
                        }
                    }
                });
            }
        }
    }
    let transform = options.transform;
    let identity = transform == UvTransform::default();
    uv.par_iter_mut().with_min_len(4096).for_each(|t| {
        let m = if identity {
            Vec2::new(t.x, t.y)
        } else {
            transform.apply(Vec2::new(t.x, t.y))
        };
        *t = Vec3::new(m.x, m.y, 0.0);
    });
    Ok(uv)
}

/// The world-to-frame matrix, or why there is none.
fn inverse_frame(frame: &Mat4) -> Result<Mat4, UvError> {
    let det = frame.determinant();
    if !det.is_finite() || det.abs() < 1e-12 || !frame.is_finite() {
        return Err(UvError::Invalid(format!(
            "the projection frame cannot be inverted (determinant {det})"
        )));
    }
    Ok(frame.inverse())
}

/// Each primitive's box face: its dominant normal axis and sign in frame
/// space (0..6 as +X, -X, +Y, -Y, +Z, -Z; +Z for a primitive without one).
fn box_faces(g: &Geometry, to_frame: &Mat4) -> Vec<u8> {
    let positions = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |local: &mut Vec<Vec3>, prim| {
            local.clear();
            local.extend(
                g.prim_points(prim)
                    .iter()
                    .map(|&p| to_frame.transform_point3(positions[p as usize])),
            );
            map::dominant_face(map::newell_normal(local))
        })
        .collect()
}

/// Runs `f(prims, uv_block, first_vertex)` over blocks of whole primitives
/// in parallel, each with the slice of `uv` its vertices own.
fn for_each_prim_block<F>(g: &Geometry, uv: &mut [Vec3], f: F)
where
    F: Fn(std::ops::Range<usize>, &mut [Vec3], usize) + Sync,
{
    const PRIMS_PER_BLOCK: usize = 2048;
    let offsets = g.prim_offsets();
    let prims = g.num_prims();
    let mut blocks = Vec::with_capacity(prims / PRIMS_PER_BLOCK + 1);
    let mut rest = uv;
    let mut start = 0;
    while start < prims {
        let end = (start + PRIMS_PER_BLOCK).min(prims);
        let len = (offsets[end] - offsets[start]) as usize;
        let (block, tail) = rest.split_at_mut(len);
        blocks.push((start..end, block, offsets[start] as usize));
        rest = tail;
        start = end;
    }
    blocks
        .into_par_iter()
        .for_each(|(range, block, first)| f(range, block, first));
}
