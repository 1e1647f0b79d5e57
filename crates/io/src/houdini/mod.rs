//! Houdini's own geometry files: `.geo` (JSON text) and `.bgeo` (the same schema in Houdini's binary JSON).
//!
//! The schema is SideFX's (`GA_Detail` JSON: counts, `topology/pointref`,
//! attributes per class with type info, primitive runs, groups); the
//! reader accepts the spellings Houdini 12 to 20 write (`Polygon_run` and
//! its short binary keys, the older `run` of `Poly`, single `Poly`
//! primitives; `tuples`, `arrays` and paged `rawpagedata` with constant
//! pages). Houdini winds polygons clockwise seen from the front and geode
//! counter-clockwise: each polygon's vertices after the first are reversed
//! on the way in and out, so faces keep their side. Packed instances are
//! `PackedGeometry` primitives with their sources embedded once each
//! (`packed.rs`); other primitive types (volumes, NURBS, packed disk
//! files and fragments, polygon soups) are refused on reading with their
//! name. Per-element arrays are written as `arraydata` (numbers) and
//! `sharedstringarray` (strings) — the tags Houdini uses — in this
//! module's own layout, which no Houdini sample has confirmed.

mod attribs;
mod bjson;
mod groups;
mod json;
mod packed;
mod read;
mod write;

use geode_geo::{Geometry, TypeInfo};

use crate::error::ParseResult;

pub(crate) const ARRAY_TYPE: &str = "arraydata";
pub(crate) const STRING_ARRAY_TYPE: &str = "sharedstringarray";

/// Reads a `.geo` or `.bgeo` file's bytes (binary JSON is recognised by its magic byte).
pub fn read_houdini(bytes: &[u8], budget: u64) -> ParseResult<Geometry> {
    let doc = if bjson::is_binary(bytes) {
        bjson::parse_binary(bytes)?
    } else {
        json::parse_text(bytes)?
    };
    read::geometry(&doc, bytes.len(), budget)
}

/// Encodes a geometry of polygons, polylines and packed instances as `.geo`
/// text or `.bgeo` binary; an instance whose transform has no Houdini form
/// is refused with the reason.
pub fn encode_houdini(
    g: &Geometry,
    binary: bool,
    cancelled: &dyn Fn() -> bool,
) -> Result<Vec<u8>, EncodeError> {
    let doc = write::document(g, cancelled)?;
    if cancelled() {
        return Err(EncodeError::Cancelled);
    }
    let mut out = Vec::new();
    if binary {
        bjson::write_binary(&doc, &mut out);
    } else {
        json::write_text(&doc, &mut out);
        out.push(b'\n');
    }
    Ok(out)
}

/// Why a geometry was not encoded.
#[derive(Debug)]
pub enum EncodeError {
    /// The geometry holds what the format cannot (the reason).
    Unsupported(String),
    /// The caller asked to stop.
    Cancelled,
}

impl From<String> for EncodeError {
    fn from(reason: String) -> EncodeError {
        EncodeError::Unsupported(reason)
    }
}

/// Packed primitives encoded between two questions whether to stop.
const CANCEL_EVERY: usize = 4096;

/// A parse error naming where in the document it was found.
pub(crate) fn bad(
    what: impl std::fmt::Display,
    message: impl std::fmt::Display,
) -> crate::error::ParseError {
    crate::error::ParseError::whole(format!("{what}: {message}"))
}

/// Turns a polygon's vertices between geode's and Houdini's winding: the
/// first stays, the rest reverse (its own inverse).
pub(crate) fn houdini_order<T>(polygon: &mut [T]) {
    if polygon.len() > 2 {
        polygon[1..].reverse();
    }
}

/// Houdini's type-info names (`GA_TypeInfo`) for geode's tags.
pub(crate) fn type_info_name(info: TypeInfo) -> Option<&'static str> {
    Some(match info {
        TypeInfo::None => return None,
        TypeInfo::Position => "point",
        TypeInfo::Vector => "vector",
        TypeInfo::Normal => "normal",
        TypeInfo::Color => "color",
        TypeInfo::Quaternion => "quaternion",
        TypeInfo::TexCoord => "texturecoord",
        TypeInfo::Transform => "matrix",
    })
}

pub(crate) fn type_info_from_name(name: &str) -> TypeInfo {
    match name {
        "point" | "hpoint" => TypeInfo::Position,
        "vector" => TypeInfo::Vector,
        "normal" => TypeInfo::Normal,
        "color" => TypeInfo::Color,
        "quaternion" => TypeInfo::Quaternion,
        "texturecoord" => TypeInfo::TexCoord,
        "matrix" => TypeInfo::Transform,
        _ => TypeInfo::None,
    }
}
