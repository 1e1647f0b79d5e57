//! Fields defined by data rather than formulas, as one kind of field node
//! evaluated at the point three argument fields give: unions of capsules
//! and triangle meshes as signed distances, sparse volumes as sampled
//! values. Every evaluator, the codec and
//! the tapes treat them through this one type, so a new kind of data is one
//! more arm here, not one more instruction everywhere.

use crate::capsules::CapsuleSet;
use crate::codec::{FieldDecodeError, Reader};
use crate::interval::Interval;
use crate::mesh_distance::MeshDistance;
use crate::volume::VolumeField;

/// Data a field node evaluates.
#[derive(Debug, PartialEq)]
pub enum Dataset {
    Capsules(CapsuleSet),
    Mesh(MeshDistance),
    Volume(VolumeField),
}

impl Dataset {
    /// Structural identity: equal for equal data.
    pub fn identity(&self) -> u128 {
        match self {
            Dataset::Capsules(s) => s.identity(),
            Dataset::Mesh(m) => m.identity(),
            Dataset::Volume(v) => v.identity(),
        }
    }

    /// Items held (capsules or triangles): the node's size in a field's
    /// tree-size count.
    pub fn len(&self) -> usize {
        match self {
            Dataset::Capsules(s) => s.len(),
            Dataset::Mesh(m) => m.len(),
            Dataset::Volume(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn memory_bytes(&self) -> usize {
        match self {
            Dataset::Capsules(s) => s.memory_bytes(),
            Dataset::Mesh(m) => m.memory_bytes(),
            Dataset::Volume(v) => v.memory_bytes(),
        }
    }

    /// Whether the values are signed distances to the surface already (a
    /// mesh's, a level set's).
    pub fn is_distance(&self) -> bool {
        match self {
            Dataset::Capsules(_) => false,
            Dataset::Mesh(_) => true,
            Dataset::Volume(v) => v.volume().class == geode_geo::volume::VolumeClass::LevelSet,
        }
    }

    /// A step for central differences of the value.
    pub fn difference_step(&self) -> f64 {
        match self {
            Dataset::Capsules(s) => s.difference_step(),
            Dataset::Mesh(m) => m.difference_step(),
            Dataset::Volume(v) => v.difference_step(),
        }
    }

    pub fn value(&self, p: [f64; 3]) -> f64 {
        match self {
            Dataset::Capsules(s) => s.value(p),
            Dataset::Mesh(m) => m.value(p),
            Dataset::Volume(v) => v.value(p),
        }
    }

    pub fn value_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        match self {
            Dataset::Capsules(s) => s.value_gradient(p),
            Dataset::Mesh(m) => m.value_gradient(p),
            Dataset::Volume(v) => v.value_gradient(p),
        }
    }

    /// Bounds over the box the intervals span, and the data narrowed to
    /// what may decide the value there (`None`: all of it may).
    pub fn interval(&self, x: Interval, y: Interval, z: Interval) -> (Interval, Option<Dataset>) {
        match self {
            Dataset::Capsules(s) => {
                let (v, narrowed) = s.interval(x, y, z);
                (v, narrowed.map(Dataset::Capsules))
            }
            Dataset::Mesh(m) => (m.interval(x, y, z), None),
            Dataset::Volume(v) => (v.interval(x, y, z), None),
        }
    }

    /// Values at many points (`out[i]` at `(xs[i], ys[i], zs[i])`).
    pub fn values(&self, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
        match self {
            Dataset::Capsules(s) => s.values(xs, ys, zs, out),
            Dataset::Mesh(m) => m.values(xs, ys, zs, out),
            Dataset::Volume(v) => v.values(xs, ys, zs, out),
        }
    }

    /// The same data with values below `floor` (< 0) free to read as the
    /// floor, for a reader that needs exact values only above it (the
    /// mesher's); `None` where that buys nothing.
    pub fn with_floor(&self, floor: f64) -> Option<Dataset> {
        match self {
            Dataset::Capsules(s) => Some(Dataset::Capsules(s.with_floor(floor))),
            Dataset::Mesh(_) | Dataset::Volume(_) => None,
        }
    }

    /// Appends a tag and the data (see `codec.rs`).
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        match self {
            Dataset::Capsules(s) => {
                out.push(0);
                s.encode(out);
            }
            Dataset::Mesh(m) => {
                out.push(1);
                m.encode(out);
            }
            Dataset::Volume(v) => {
                out.push(2);
                v.encode(out);
            }
        }
    }

    pub(crate) fn decode(r: &mut Reader) -> Result<Dataset, FieldDecodeError> {
        match r.take(1)?[0] {
            0 => CapsuleSet::decode(r).map(Dataset::Capsules),
            1 => MeshDistance::decode(r).map(Dataset::Mesh),
            2 => VolumeField::decode(r).map(Dataset::Volume),
            t => Err(FieldDecodeError::Invalid(format!("dataset tag {t}"))),
        }
    }
}
