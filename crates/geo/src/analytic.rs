//! Analytic identity of mesh primitives (Houdini's "primitive" sphere and
//! tube types): polygons made by the box, sphere, torus and tube nodes can
//! carry the exact shape they approximate, per primitive, so that merges,
//! transforms and deletions keep it and an FRep node can rebuild the exact
//! solid (the seed feeds Houdini's own primitives into FRep nodes).

use glam::{Mat4, Vec3, Vec4};

use crate::{AttribClass, AttribData, Attribute, GeoError, Geometry, TypeInfo};

/// Which shape (0 = none: a polygon with no analytic form).
pub const SHAPE: &str = "analytic_shape";
/// The shape's dimensions, by shape (see [`AnalyticShape`]).
pub const SIZE: &str = "analytic_size";
/// Linear part of the shape's frame (a transform: rotates and scales with
/// `transform`, as Houdini's packed `transform` does).
pub const XFORM: &str = "analytic_xform";
/// Where the shape's origin is (a position: moves with `transform`).
pub const ORIGIN: &str = "analytic_origin";

/// An exact solid in its local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnalyticShape {
    /// Centred at the origin, edge lengths along X, Y, Z.
    Box { size: [f32; 3] },
    /// Centred at the origin.
    Sphere { radius: f32 },
    /// Around the Y axis, centred at the origin.
    Torus { major: f32, minor: f32 },
    /// A solid cylinder along Y from `y0` to `y1`.
    Tube { radius: f32, y0: f32, y1: f32 },
}

impl AnalyticShape {
    fn code_and_size(&self) -> (i32, Vec4) {
        match *self {
            AnalyticShape::Box { size } => (1, Vec4::new(size[0], size[1], size[2], 0.0)),
            AnalyticShape::Sphere { radius } => (2, Vec4::new(radius, 0.0, 0.0, 0.0)),
            AnalyticShape::Torus { major, minor } => (3, Vec4::new(major, minor, 0.0, 0.0)),
            AnalyticShape::Tube { radius, y0, y1 } => (4, Vec4::new(radius, y0, y1, 0.0)),
        }
    }

    fn from_code(code: i32, s: Vec4) -> Option<AnalyticShape> {
        Some(match code {
            1 => AnalyticShape::Box {
                size: [s.x, s.y, s.z],
            },
            2 => AnalyticShape::Sphere { radius: s.x },
            3 => AnalyticShape::Torus {
                major: s.x,
                minor: s.y,
            },
            4 => AnalyticShape::Tube {
                radius: s.x,
                y0: s.y,
                y1: s.z,
            },
            _ => return None,
        })
    }
}

/// Marks every primitive of `g` as approximating `shape` (in `g`'s frame).
pub fn tag(g: &mut Geometry, shape: AnalyticShape) -> Result<(), GeoError> {
    let n = g.num_prims();
    let (code, size) = shape.code_and_size();
    g.set_attrib(
        AttribClass::Primitive,
        SHAPE,
        Attribute::from_data(AttribData::Int(vec![code; n]), TypeInfo::None),
    )?;
    g.set_attrib(
        AttribClass::Primitive,
        SIZE,
        Attribute::from_data(AttribData::Vec4(vec![size; n]), TypeInfo::None),
    )?;
    g.set_attrib(
        AttribClass::Primitive,
        XFORM,
        Attribute::from_data(
            AttribData::Mat4(vec![Mat4::IDENTITY; n]),
            TypeInfo::Transform,
        ),
    )?;
    g.set_attrib(
        AttribClass::Primitive,
        ORIGIN,
        Attribute::from_data(AttribData::Vec3(vec![Vec3::ZERO; n]), TypeInfo::Position),
    )
}

/// Why a geometry has no analytic reading.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum AnalyticError {
    #[error("the geometry has no primitives")]
    Empty,
    #[error("primitive {0} has no analytic shape (make it with a box, sphere, torus or tube node with `analytic` on)")]
    NotAnalytic(usize),
}

/// The distinct shapes of `g` with their local-to-world frames, in order of first
/// appearance; every primitive must carry one.
pub fn shapes(g: &Geometry) -> Result<Vec<(AnalyticShape, Mat4)>, AnalyticError> {
    if g.num_prims() == 0 {
        return Err(AnalyticError::Empty);
    }
    let column = |name: &str| g.attrib(AttribClass::Primitive, name).map(|a| a.data());
    let (
        Some(AttribData::Int(codes)),
        Some(AttribData::Vec4(sizes)),
        Some(AttribData::Mat4(xforms)),
        Some(AttribData::Vec3(origins)),
    ) = (column(SHAPE), column(SIZE), column(XFORM), column(ORIGIN))
    else {
        return Err(AnalyticError::NotAnalytic(0));
    };
    let mut out: Vec<(AnalyticShape, Mat4)> = Vec::new();
    for i in 0..g.num_prims() {
        let shape =
            AnalyticShape::from_code(codes[i], sizes[i]).ok_or(AnalyticError::NotAnalytic(i))?;
        let record = (shape, Mat4::from_translation(origins[i]) * xforms[i]);
        // Consecutive primitives of one shape are the common case.
        if out.last() != Some(&record) && !out.contains(&record) {
            out.push(record);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ops, primitives};

    #[test]
    fn shapes_survive_transform_and_merge_and_untagged_polygons_are_named() {
        let mut a = primitives::uv_sphere(1.0, 8, 6);
        tag(&mut a, AnalyticShape::Sphere { radius: 1.0 }).unwrap();
        let moved = Mat4::from_translation(glam::Vec3::new(2.0, 0.0, 0.0));
        ops::transform(&mut a, moved);
        let mut b = primitives::torus(1.0, 0.25, 8, 6);
        tag(
            &mut b,
            AnalyticShape::Torus {
                major: 1.0,
                minor: 0.25,
            },
        )
        .unwrap();
        let merged = ops::merge(&[&a, &b]).unwrap();
        assert_eq!(
            shapes(&merged).unwrap(),
            vec![
                (AnalyticShape::Sphere { radius: 1.0 }, moved),
                (
                    AnalyticShape::Torus {
                        major: 1.0,
                        minor: 0.25
                    },
                    Mat4::IDENTITY
                ),
            ]
        );
        let plain = primitives::cube(1.0);
        let mixed = ops::merge(&[&merged, &plain]).unwrap();
        assert_eq!(
            shapes(&mixed),
            Err(AnalyticError::NotAnalytic(merged.num_prims()))
        );
        assert_eq!(shapes(&plain), Err(AnalyticError::NotAnalytic(0)));
    }
}
