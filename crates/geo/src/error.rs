//! Errors raised by geometry operations (typed; no panics on bad user data).

use crate::attrib::{AttribClass, AttribType};

/// Everything that can go wrong inside the geometry model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeoError {
    #[error("{class} attribute `{name}` has {found} elements, expected {expected}")]
    AttribLength {
        class: AttribClass,
        name: String,
        expected: usize,
        found: usize,
    },
    #[error("{class} attribute `{name}` is {found}, expected {expected}")]
    AttribType {
        class: AttribClass,
        name: String,
        expected: AttribType,
        found: AttribType,
    },
    #[error("point attribute `{name}` is {found}; it is read as {expected}")]
    AttribReadAs {
        name: String,
        expected: &'static str,
        found: AttribType,
    },
    #[error("no {class} attribute named `{name}`")]
    MissingAttrib { class: AttribClass, name: String },
    #[error("the point attribute `P` cannot be removed or retyped")]
    PositionRequired,
    #[error("point index {index} out of range (geometry has {count} points)")]
    PointOutOfRange { index: u32, count: usize },
    #[error("no {kind} group named `{name}`")]
    MissingGroup { kind: &'static str, name: String },
    #[error("group `{name}` has {found} members flags, expected {expected}")]
    GroupLength {
        name: String,
        expected: usize,
        found: usize,
    },
    #[error("cancelled")]
    Cancelled,
    #[error("a polygon needs at least 3 vertices, got {0}")]
    PolygonTooSmall(usize),
    #[error("a polyline needs at least 2 vertices, got {0}")]
    PolylineTooSmall(usize),
    #[error("the primitives count {counted} vertices but {given} points were given")]
    VertexCountMismatch { counted: usize, given: usize },
    #[error("geometry too large: {what} exceeds the 32-bit index range")]
    TooLarge { what: &'static str },
    #[error("{0}")]
    Invalid(String),
}
