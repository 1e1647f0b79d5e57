//! All attributes of one class, by name, each with the same number of
//! elements.

use std::collections::BTreeMap;

use crate::error::GeoError;

use super::{AttribClass, AttribData, AttribValue, Attribute, TypeInfo};

/// All attributes of one class, by name, each with the same number of elements.
#[derive(Clone, Debug, PartialEq)]
pub struct AttribTable {
    class: AttribClass,
    len: usize,
    attribs: BTreeMap<String, Attribute>,
}

impl AttribTable {
    pub fn new(class: AttribClass, len: usize) -> AttribTable {
        AttribTable {
            class,
            len,
            attribs: BTreeMap::new(),
        }
    }

    pub fn class(&self) -> AttribClass {
        self.class
    }

    /// Number of elements every column holds.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn get(&self, name: &str) -> Option<&Attribute> {
        self.attribs.get(name)
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut Attribute> {
        self.attribs.get_mut(name)
    }

    pub fn contains(&self, name: &str) -> bool {
        self.attribs.contains_key(name)
    }

    /// Attributes in name order (deterministic).
    pub fn iter(&self) -> impl Iterator<Item = (&str, &Attribute)> {
        self.attribs.iter().map(|(k, v)| (k.as_str(), v))
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.attribs.keys().map(|k| k.as_str())
    }

    pub fn num_attribs(&self) -> usize {
        self.attribs.len()
    }

    /// Adds or replaces an attribute; its length must match the table's.
    pub fn insert(&mut self, name: &str, attrib: Attribute) -> Result<(), GeoError> {
        if attrib.len() != self.len {
            return Err(GeoError::AttribLength {
                class: self.class,
                name: name.to_owned(),
                expected: self.len,
                found: attrib.len(),
            });
        }
        self.attribs.insert(name.to_owned(), attrib);
        Ok(())
    }

    /// The attribute `name`, created with `default` when absent; errors if it
    /// exists with another type.
    pub fn get_or_create(
        &mut self,
        name: &str,
        default: AttribValue,
        type_info: TypeInfo,
    ) -> Result<&mut Attribute, GeoError> {
        let class = self.class;
        let len = self.len;
        let ty = default.attrib_type();
        let attrib = self
            .attribs
            .entry(name.to_owned())
            .or_insert_with(|| Attribute::new(default, type_info, len));
        if attrib.attrib_type() != ty {
            return Err(GeoError::AttribType {
                class,
                name: name.to_owned(),
                expected: ty,
                found: attrib.attrib_type(),
            });
        }
        Ok(attrib)
    }

    pub fn remove(&mut self, name: &str) -> Option<Attribute> {
        self.attribs.remove(name)
    }

    /// Resizes every column, new elements taking each attribute's default.
    pub(crate) fn resize(&mut self, len: usize) {
        self.len = len;
        for a in self.attribs.values_mut() {
            if a.len() != len {
                let d = a.default.clone();
                a.data.make_mut().resize(len, &d);
            }
        }
    }

    /// A table of the elements at `indices`.
    pub fn gather(&self, indices: &[u32]) -> AttribTable {
        AttribTable {
            class: self.class,
            len: indices.len(),
            attribs: self
                .attribs
                .iter()
                .map(|(k, a)| (k.clone(), a.gather(indices)))
                .collect(),
        }
    }

    /// A table of weighted sums of three elements each (barycentric
    /// interpolation; see [`AttribData::mix3`]).
    pub fn mix3(&self, items: &[([u32; 3], [f32; 3])]) -> AttribTable {
        AttribTable {
            class: self.class,
            len: items.len(),
            attribs: self
                .attribs
                .iter()
                .map(|(k, a)| (k.clone(), a.mix3(items)))
                .collect(),
        }
    }

    /// Appends `other`'s elements. Attributes missing on either side are filled
    /// with their defaults; a name with two different types is an error.
    pub(crate) fn append(&mut self, other: &AttribTable) -> Result<(), GeoError> {
        for (name, theirs) in &other.attribs {
            if let Some(ours) = self.attribs.get(name) {
                if ours.attrib_type() != theirs.attrib_type() {
                    return Err(GeoError::AttribType {
                        class: self.class,
                        name: name.clone(),
                        expected: ours.attrib_type(),
                        found: theirs.attrib_type(),
                    });
                }
            }
        }
        let old_len = self.len;
        let new_len = old_len + other.len;
        for (name, theirs) in &other.attribs {
            let ours = self.attribs.entry(name.clone()).or_insert_with(|| {
                Attribute::new(theirs.default.clone(), theirs.type_info, old_len)
            });
            let appended = theirs.is_empty() || ours.data.make_mut().append(&theirs.data);
            debug_assert!(appended, "types checked above");
        }
        for a in self.attribs.values_mut() {
            if a.len() != new_len {
                let d = a.default.clone();
                a.data.make_mut().resize(new_len, &d);
            }
        }
        self.len = new_len;
        Ok(())
    }

    pub(crate) fn iter_mut(&mut self) -> impl Iterator<Item = (&str, &mut Attribute)> {
        self.attribs.iter_mut().map(|(k, v)| (k.as_str(), v))
    }

    /// A copy whose columns `f` returns new values for (same type and
    /// length) take them; the others are copied.
    pub(crate) fn map_columns(&self, f: impl Fn(&Attribute) -> Option<AttribData>) -> AttribTable {
        AttribTable {
            class: self.class,
            len: self.len,
            attribs: self
                .attribs
                .iter()
                .map(|(k, a)| {
                    (
                        k.clone(),
                        f(a).map_or_else(|| a.clone(), |d| a.with_data(d)),
                    )
                })
                .collect(),
        }
    }
}
