//! geode's geometry model (Houdini's): points, vertices, primitives, typed
//! attribute columns, groups, packed instances, topology and the operations
//! every node needs. Knows nothing of files, nodes or graphs.

pub mod analytic;
pub mod attrib;
mod bytes;
pub mod codec;
mod error;
mod geometry;
mod group;
mod hash;
pub mod hint;
pub mod ops;
mod patch;
pub mod pattern;
mod payload;
pub mod primitives;
pub mod ramp;
pub mod random;
mod shared;
pub mod topology;
pub mod volume;

pub use attrib::{
    AttribClass, AttribData, AttribTable, AttribType, AttribValue, Attribute, StringColumn,
    TypeInfo,
};
pub use bytes::human_bytes;
pub use error::GeoError;
pub use geometry::{Geometry, PackedInstance, PrimKind, P};
pub use glam;
pub use group::Group;
pub use hash::hash_bytes;
pub use patch::{KnotVector, PatchBasis, WEIGHT};
pub use payload::Payload;
pub use ramp::{Ramp, RampBasis, RampError, RampKey, RampKind};
pub use topology::{HalfEdge, ManifoldReport, Topology};
