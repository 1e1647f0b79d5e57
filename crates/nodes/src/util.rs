//! Small helpers shared by the node families: input access, vectors, class menus.

use std::sync::Arc;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{AttribClass, Geometry};
use geode_op::{CookContext, CookError, Params, Value};

/// The geometry on input `i` (inputs are checked at load; this guards the rest).
pub fn input<'a>(
    ctx: &CookContext,
    inputs: &'a [Option<Value>],
    i: usize,
) -> Result<&'a Arc<Geometry>, CookError> {
    inputs
        .get(i)
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_geometry())
        .ok_or_else(|| ctx.input_error(format!("input {} needs geometry", i + 1)))
}

/// A copy of input `i` to modify (shared data is cloned only here).
pub fn input_owned(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    i: usize,
) -> Result<Geometry, CookError> {
    Ok(Geometry::clone(input(ctx, inputs, i)?))
}

pub fn vec3(p: &Params, name: &str) -> Result<Vec3, CookError> {
    let [x, y, z] = p.vector::<3>(name)?;
    Ok(Vec3::new(x as f32, y as f32, z as f32))
}

pub fn vec2(p: &Params, name: &str) -> Result<Vec2, CookError> {
    let [x, y] = p.vector::<2>(name)?;
    Ok(Vec2::new(x as f32, y as f32))
}

pub const CLASSES: &[&str] = &["point", "vertex", "primitive", "detail"];
pub const ELEMENT_CLASSES: &[&str] = &["point", "primitive"];

pub fn class(p: &Params, name: &str) -> Result<AttribClass, CookError> {
    Ok(match p.string(name)? {
        "point" => AttribClass::Point,
        "vertex" => AttribClass::Vertex,
        "primitive" => AttribClass::Primitive,
        _ => AttribClass::Detail,
    })
}

/// Number of elements of a class.
pub fn count(g: &Geometry, c: AttribClass) -> usize {
    match c {
        AttribClass::Point => g.num_points(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Detail => 1,
    }
}

pub fn geometry(g: Geometry) -> Result<Value, CookError> {
    Ok(Value::geometry(g))
}
