//! Values on the wires: geometry (shared, copy on write) and bundles of named geometries.

use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

use geode_geo::Geometry;
use xxhash_rust::xxh3::Xxh3;

/// The type of a port or wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PortType {
    Geometry,
    /// Several named geometries on one wire (seed 004's streams).
    Bundle,
    /// An FRep field (`f >= 0` inside), meshed by a polygonise node.
    Field,
}

impl fmt::Display for PortType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PortType::Geometry => "geometry",
            PortType::Bundle => "bundle",
            PortType::Field => "field",
        })
    }
}

/// Named geometries travelling together, in name order.
#[derive(Clone, Debug, Default)]
pub struct Bundle {
    pub entries: BTreeMap<String, Arc<Geometry>>,
}

/// A value produced by a node. Cheap to clone (shared).
#[derive(Clone, Debug)]
pub enum Value {
    Geometry(Arc<Geometry>),
    Bundle(Arc<Bundle>),
    Field(geode_frep::Field),
}

impl Value {
    pub fn geometry(g: Geometry) -> Value {
        Value::Geometry(Arc::new(g))
    }

    pub fn port_type(&self) -> PortType {
        match self {
            Value::Geometry(_) => PortType::Geometry,
            Value::Bundle(_) => PortType::Bundle,
            Value::Field(_) => PortType::Field,
        }
    }

    pub fn as_geometry(&self) -> Option<&Arc<Geometry>> {
        match self {
            Value::Geometry(g) => Some(g),
            _ => None,
        }
    }

    pub fn as_bundle(&self) -> Option<&Arc<Bundle>> {
        match self {
            Value::Bundle(b) => Some(b),
            _ => None,
        }
    }

    pub fn as_field(&self) -> Option<&geode_frep::Field> {
        match self {
            Value::Field(f) => Some(f),
            _ => None,
        }
    }

    /// Content identity: equal for equal content, whatever produced it.
    pub fn identity(&self) -> u128 {
        match self {
            Value::Geometry(g) => g.content_hash(),
            Value::Field(f) => f.identity(),
            Value::Bundle(b) => {
                let mut h = Xxh3::new();
                h.update(b"bundle");
                for (name, g) in &b.entries {
                    h.update(&(name.len() as u64).to_le_bytes());
                    h.update(name.as_bytes());
                    h.update(&g.content_hash().to_le_bytes());
                }
                h.digest128()
            }
        }
    }

    /// Bytes held, for the cache's budget.
    pub fn bytes(&self) -> usize {
        match self {
            Value::Geometry(g) => g.memory_bytes(),
            Value::Bundle(b) => b.entries.values().map(|g| g.memory_bytes()).sum(),
            Value::Field(f) => f.memory_bytes(),
        }
    }
}
