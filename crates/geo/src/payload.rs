//! Typed values a geometry carries beside its attributes (an hspline
//! hierarchy on its tessellation): shared, identified by content, sized for
//! the cache, and opaque to everything but the code that made them.

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use crate::geometry::Geometry;

/// A value of any type, with the content identity and size the engine
/// needs (equal content, equal identity) and no text round trip.
#[derive(Clone)]
pub struct Payload {
    data: Arc<dyn Any + Send + Sync>,
    identity: u128,
    bytes: usize,
}

impl Payload {
    pub fn new<T: Any + Send + Sync>(data: T, identity: u128, bytes: usize) -> Payload {
        Payload {
            data: Arc::new(data),
            identity,
            bytes,
        }
    }

    /// The value, if it is a `T`.
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.data.downcast_ref::<T>()
    }

    pub fn identity(&self) -> u128 {
        self.identity
    }

    pub fn bytes(&self) -> usize {
        self.bytes
    }
}

impl fmt::Debug for Payload {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Payload({:032x}, {} bytes)", self.identity, self.bytes)
    }
}

impl Geometry {
    /// Attaches (or replaces) a named payload.
    pub fn set_payload(&mut self, name: &str, p: Payload) {
        self.payloads.insert(name.to_owned(), p);
        self.content_hash = Default::default();
    }

    pub fn payload(&self, name: &str) -> Option<&Payload> {
        self.payloads.get(name)
    }

    /// Payloads in name order.
    pub fn payloads(&self) -> impl Iterator<Item = (&str, &Payload)> {
        self.payloads.iter().map(|(k, v)| (k.as_str(), v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn payloads_are_typed_shared_and_part_of_the_content_hash() {
        let mut a = crate::primitives::cube(1.0);
        let plain = a.content_hash();
        let before = a.memory_bytes();
        a.set_payload("note", Payload::new(vec![1u32, 2, 3], 7, 12));
        assert_ne!(a.content_hash(), plain);
        assert_eq!(a.memory_bytes(), before + 12);
        let b = a.clone();
        assert_eq!(
            b.payload("note").unwrap().get::<Vec<u32>>(),
            Some(&vec![1, 2, 3])
        );
        assert!(b.payload("note").unwrap().get::<String>().is_none());
        let mut c = crate::primitives::cube(1.0);
        c.set_payload("note", Payload::new(vec![9u32], 7, 4));
        assert_eq!(
            a.content_hash(),
            c.content_hash(),
            "identity, not the bytes, counts"
        );
    }
}
