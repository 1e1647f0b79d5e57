//! Writing the result back: the vertex attribute `uv` (and the island
//! number per primitive), as Houdini names them.

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};

use crate::error::UvError;

/// The vertex attribute Houdini keeps texture coordinates in.
pub const UV: &str = "uv";

/// Sets the vertex attribute `name` (usually [`UV`]) to `uv`, three
/// floats per vertex tagged as texture coordinates. Fails when `uv` does
/// not have one value per vertex.
pub fn write_uv(g: &mut Geometry, name: &str, uv: Vec<Vec3>) -> Result<(), UvError> {
    if uv.len() != g.num_vertices() {
        return Err(UvError::Invalid(format!(
            "{} uv values for {} vertices",
            uv.len(),
            g.num_vertices()
        )));
    }
    let attrib = Attribute::from_data(AttribData::Vec3(uv), TypeInfo::TexCoord);
    g.set_attrib(AttribClass::Vertex, name, attrib)
        .map_err(|e| UvError::Invalid(e.to_string()))
}

/// Sets the integer primitive attribute `name` to `islands` (one per
/// primitive, as [`crate::Flattened::prim_island`]).
pub fn write_islands(g: &mut Geometry, name: &str, islands: Vec<i32>) -> Result<(), UvError> {
    if islands.len() != g.num_prims() {
        return Err(UvError::Invalid(format!(
            "{} island numbers for {} primitives",
            islands.len(),
            g.num_prims()
        )));
    }
    let attrib = Attribute::from_data(AttribData::Int(islands), TypeInfo::None);
    g.set_attrib(AttribClass::Primitive, name, attrib)
        .map_err(|e| UvError::Invalid(e.to_string()))
}
