//! Typed attribute columns (structure of arrays) and the tables that hold them per class.

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

use crate::shared::Shared;

mod kinds;
mod table;

pub use kinds::{AttribClass, AttribType, AttribValue, TypeInfo};
pub use table::AttribTable;

/// Whether `name` can name an attribute or a group, as Houdini allows:
/// letters, digits and `_`, not starting with a digit.
pub fn is_valid_name(name: &str) -> bool {
    !name.is_empty()
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.starts_with(|c: char| c.is_ascii_digit())
}

/// Strings stored once in a table; elements hold indices into it.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct StringColumn {
    pub table: Vec<String>,
    pub indices: Vec<u32>,
}

impl StringColumn {
    /// The index of `s` in the table, adding it when new.
    pub fn intern(&mut self, s: &str) -> u32 {
        match self.table.iter().position(|t| t == s) {
            Some(i) => i as u32,
            None => {
                self.table.push(s.to_owned());
                (self.table.len() - 1) as u32
            }
        }
    }

    pub fn get(&self, i: usize) -> &str {
        &self.table[self.indices[i] as usize]
    }
}

/// The column of values itself.
#[derive(Clone, Debug, PartialEq)]
pub enum AttribData {
    Float(Vec<f32>),
    Int(Vec<i32>),
    Vec2(Vec<Vec2>),
    Vec3(Vec<Vec3>),
    Vec4(Vec<Vec4>),
    Quat(Vec<Quat>),
    Mat4(Vec<Mat4>),
    Mat3(Vec<Mat3>),
    String(StringColumn),
    IntArray(Vec<Vec<i32>>),
    FloatArray(Vec<Vec<f32>>),
    Vec3Array(Vec<Vec<Vec3>>),
    StringArray(Vec<Vec<String>>),
}

/// Runs `$body` with `$v` bound to the inner `Vec` of every numeric variant,
/// `$s` for the string column and `$a` for an array column.
macro_rules! each_column {
    ($data:expr, $v:ident => $body:expr, $s:ident => $sbody:expr, $a:ident => $abody:expr) => {
        match $data {
            AttribData::IntArray($a) => $abody,
            AttribData::FloatArray($a) => $abody,
            AttribData::Vec3Array($a) => $abody,
            AttribData::StringArray($a) => $abody,
            AttribData::Float($v) => $body,
            AttribData::Int($v) => $body,
            AttribData::Vec2($v) => $body,
            AttribData::Vec3($v) => $body,
            AttribData::Vec4($v) => $body,
            AttribData::Quat($v) => $body,
            AttribData::Mat4($v) => $body,
            AttribData::Mat3($v) => $body,
            AttribData::String($s) => $sbody,
        }
    };
}

impl AttribData {
    /// A column of `len` copies of `value`.
    pub fn filled(value: &AttribValue, len: usize) -> AttribData {
        match value {
            AttribValue::Float(x) => AttribData::Float(vec![*x; len]),
            AttribValue::Int(x) => AttribData::Int(vec![*x; len]),
            AttribValue::Vec2(x) => AttribData::Vec2(vec![*x; len]),
            AttribValue::Vec3(x) => AttribData::Vec3(vec![*x; len]),
            AttribValue::Vec4(x) => AttribData::Vec4(vec![*x; len]),
            AttribValue::Quat(x) => AttribData::Quat(vec![*x; len]),
            AttribValue::Mat4(x) => AttribData::Mat4(vec![*x; len]),
            AttribValue::Mat3(x) => AttribData::Mat3(vec![*x; len]),
            AttribValue::String(s) => AttribData::String(StringColumn {
                table: vec![s.clone()],
                indices: vec![0; len],
            }),
            AttribValue::IntArray(a) => AttribData::IntArray(vec![a.clone(); len]),
            AttribValue::FloatArray(a) => AttribData::FloatArray(vec![a.clone(); len]),
            AttribValue::Vec3Array(a) => AttribData::Vec3Array(vec![a.clone(); len]),
            AttribValue::StringArray(a) => AttribData::StringArray(vec![a.clone(); len]),
        }
    }

    /// A column of `len` elements of type `ty`, every bit zero (the empty
    /// string, empty arrays), allocated zeroed: its pages are first touched
    /// by whoever writes them.
    pub fn zeroed(ty: AttribType, len: usize) -> AttribData {
        use bytemuck::zeroed_vec as z;
        match ty {
            AttribType::Float => AttribData::Float(z(len)),
            AttribType::Int => AttribData::Int(z(len)),
            AttribType::Vec2 => AttribData::Vec2(z(len)),
            AttribType::Vec3 => AttribData::Vec3(z(len)),
            AttribType::Vec4 => AttribData::Vec4(z(len)),
            AttribType::Quat => AttribData::Quat(z(len)),
            AttribType::Mat4 => AttribData::Mat4(z(len)),
            AttribType::Mat3 => AttribData::Mat3(z(len)),
            AttribType::String => AttribData::String(StringColumn {
                table: vec![String::new()],
                indices: z(len),
            }),
            AttribType::IntArray => AttribData::IntArray(vec![Vec::new(); len]),
            AttribType::FloatArray => AttribData::FloatArray(vec![Vec::new(); len]),
            AttribType::Vec3Array => AttribData::Vec3Array(vec![Vec::new(); len]),
            AttribType::StringArray => AttribData::StringArray(vec![Vec::new(); len]),
        }
    }

    pub fn attrib_type(&self) -> AttribType {
        match self {
            AttribData::Float(_) => AttribType::Float,
            AttribData::Int(_) => AttribType::Int,
            AttribData::Vec2(_) => AttribType::Vec2,
            AttribData::Vec3(_) => AttribType::Vec3,
            AttribData::Vec4(_) => AttribType::Vec4,
            AttribData::Quat(_) => AttribType::Quat,
            AttribData::Mat4(_) => AttribType::Mat4,
            AttribData::Mat3(_) => AttribType::Mat3,
            AttribData::String(_) => AttribType::String,
            AttribData::IntArray(_) => AttribType::IntArray,
            AttribData::FloatArray(_) => AttribType::FloatArray,
            AttribData::Vec3Array(_) => AttribType::Vec3Array,
            AttribData::StringArray(_) => AttribType::StringArray,
        }
    }

    pub fn len(&self) -> usize {
        each_column!(self, v => v.len(), s => s.indices.len(), a => a.len())
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The element at `i` as a value.
    pub fn get(&self, i: usize) -> AttribValue {
        match self {
            AttribData::Float(v) => AttribValue::Float(v[i]),
            AttribData::Int(v) => AttribValue::Int(v[i]),
            AttribData::Vec2(v) => AttribValue::Vec2(v[i]),
            AttribData::Vec3(v) => AttribValue::Vec3(v[i]),
            AttribData::Vec4(v) => AttribValue::Vec4(v[i]),
            AttribData::Quat(v) => AttribValue::Quat(v[i]),
            AttribData::Mat4(v) => AttribValue::Mat4(v[i]),
            AttribData::Mat3(v) => AttribValue::Mat3(v[i]),
            AttribData::String(s) => AttribValue::String(s.get(i).to_owned()),
            AttribData::IntArray(v) => AttribValue::IntArray(v[i].clone()),
            AttribData::FloatArray(v) => AttribValue::FloatArray(v[i].clone()),
            AttribData::Vec3Array(v) => AttribValue::Vec3Array(v[i].clone()),
            AttribData::StringArray(v) => AttribValue::StringArray(v[i].clone()),
        }
    }

    /// Sets element `i`; the value must have the column's type.
    pub fn set(&mut self, i: usize, value: &AttribValue) -> Result<(), AttribType> {
        match (self, value) {
            (AttribData::Float(v), AttribValue::Float(x)) => v[i] = *x,
            (AttribData::Int(v), AttribValue::Int(x)) => v[i] = *x,
            (AttribData::Vec2(v), AttribValue::Vec2(x)) => v[i] = *x,
            (AttribData::Vec3(v), AttribValue::Vec3(x)) => v[i] = *x,
            (AttribData::Vec4(v), AttribValue::Vec4(x)) => v[i] = *x,
            (AttribData::Quat(v), AttribValue::Quat(x)) => v[i] = *x,
            (AttribData::Mat4(v), AttribValue::Mat4(x)) => v[i] = *x,
            (AttribData::Mat3(v), AttribValue::Mat3(x)) => v[i] = *x,
            (AttribData::String(s), AttribValue::String(x)) => {
                let k = s.intern(x);
                s.indices[i] = k;
            }
            (AttribData::IntArray(v), AttribValue::IntArray(x)) => v[i].clone_from(x),
            (AttribData::FloatArray(v), AttribValue::FloatArray(x)) => v[i].clone_from(x),
            (AttribData::Vec3Array(v), AttribValue::Vec3Array(x)) => v[i].clone_from(x),
            (AttribData::StringArray(v), AttribValue::StringArray(x)) => v[i].clone_from(x),
            (_, other) => return Err(other.attrib_type()),
        }
        Ok(())
    }

    /// Grows or shrinks to `len`, filling new elements with `fill`.
    pub(crate) fn resize(&mut self, len: usize, fill: &AttribValue) {
        match (self, fill) {
            (AttribData::Float(v), AttribValue::Float(x)) => v.resize(len, *x),
            (AttribData::Int(v), AttribValue::Int(x)) => v.resize(len, *x),
            (AttribData::Vec2(v), AttribValue::Vec2(x)) => v.resize(len, *x),
            (AttribData::Vec3(v), AttribValue::Vec3(x)) => v.resize(len, *x),
            (AttribData::Vec4(v), AttribValue::Vec4(x)) => v.resize(len, *x),
            (AttribData::Quat(v), AttribValue::Quat(x)) => v.resize(len, *x),
            (AttribData::Mat4(v), AttribValue::Mat4(x)) => v.resize(len, *x),
            (AttribData::Mat3(v), AttribValue::Mat3(x)) => v.resize(len, *x),
            (AttribData::String(s), AttribValue::String(x)) => {
                let k = s.intern(x);
                s.indices.resize(len, k);
            }
            (AttribData::IntArray(v), AttribValue::IntArray(x)) => v.resize(len, x.clone()),
            (AttribData::FloatArray(v), AttribValue::FloatArray(x)) => v.resize(len, x.clone()),
            (AttribData::Vec3Array(v), AttribValue::Vec3Array(x)) => v.resize(len, x.clone()),
            (AttribData::StringArray(v), AttribValue::StringArray(x)) => v.resize(len, x.clone()),
            (data, _) => unreachable!(
                "attribute default type checked on creation ({})",
                data.attrib_type()
            ),
        }
    }

    /// A new column made of the elements at `indices`, in that order.
    pub fn gather(&self, indices: &[u32]) -> AttribData {
        fn pick<T: Copy>(v: &[T], idx: &[u32]) -> Vec<T> {
            idx.iter().map(|&i| v[i as usize]).collect()
        }
        match self {
            AttribData::Float(v) => AttribData::Float(pick(v, indices)),
            AttribData::Int(v) => AttribData::Int(pick(v, indices)),
            AttribData::Vec2(v) => AttribData::Vec2(pick(v, indices)),
            AttribData::Vec3(v) => AttribData::Vec3(pick(v, indices)),
            AttribData::Vec4(v) => AttribData::Vec4(pick(v, indices)),
            AttribData::Quat(v) => AttribData::Quat(pick(v, indices)),
            AttribData::Mat4(v) => AttribData::Mat4(pick(v, indices)),
            AttribData::Mat3(v) => AttribData::Mat3(pick(v, indices)),
            AttribData::String(s) => AttribData::String(StringColumn {
                table: s.table.clone(),
                indices: pick(&s.indices, indices),
            }),
            AttribData::IntArray(v) => {
                AttribData::IntArray(indices.iter().map(|&i| v[i as usize].clone()).collect())
            }
            AttribData::FloatArray(v) => {
                AttribData::FloatArray(indices.iter().map(|&i| v[i as usize].clone()).collect())
            }
            AttribData::Vec3Array(v) => {
                AttribData::Vec3Array(indices.iter().map(|&i| v[i as usize].clone()).collect())
            }
            AttribData::StringArray(v) => {
                AttribData::StringArray(indices.iter().map(|&i| v[i as usize].clone()).collect())
            }
        }
    }

    /// A new column of blends `(a, b, t)`: `(1 - t) a + t b` for numbers and
    /// vectors, a normalized slerp for quaternions, and the nearer element
    /// for integers, matrices and strings (they do not interpolate).
    pub fn blend(&self, pairs: &[(u32, u32, f32)]) -> AttribData {
        fn mix<T: Copy>(v: &[T], pairs: &[(u32, u32, f32)], f: impl Fn(T, T, f32) -> T) -> Vec<T> {
            pairs
                .iter()
                .map(|&(a, b, t)| f(v[a as usize], v[b as usize], t))
                .collect()
        }
        let nearest: Vec<u32> = pairs
            .iter()
            .map(|&(a, b, t)| if t < 0.5 { a } else { b })
            .collect();
        match self {
            AttribData::Float(v) => AttribData::Float(mix(v, pairs, |a, b, t| a + (b - a) * t)),
            AttribData::Vec2(v) => AttribData::Vec2(mix(v, pairs, |a, b, t| a.lerp(b, t))),
            AttribData::Vec3(v) => AttribData::Vec3(mix(v, pairs, |a, b, t| a.lerp(b, t))),
            AttribData::Vec4(v) => AttribData::Vec4(mix(v, pairs, |a, b, t| a.lerp(b, t))),
            AttribData::Quat(v) => {
                AttribData::Quat(mix(v, pairs, |a, b, t| a.slerp(b, t).normalize()))
            }
            AttribData::Int(_)
            | AttribData::Mat4(_)
            | AttribData::Mat3(_)
            | AttribData::String(_)
            | AttribData::IntArray(_)
            | AttribData::FloatArray(_)
            | AttribData::Vec3Array(_)
            | AttribData::StringArray(_) => self.gather(&nearest),
        }
    }

    /// A new column of weighted sums of three elements each (barycentric
    /// interpolation over a triangle): `w0 a + w1 b + w2 c` for numbers and
    /// vectors, the normalized sum for quaternions (aligned to the first),
    /// and the heaviest element for integers, matrices and strings (they do
    /// not interpolate).
    pub fn mix3(&self, items: &[([u32; 3], [f32; 3])]) -> AttribData {
        fn mix<T: Copy>(
            v: &[T],
            items: &[([u32; 3], [f32; 3])],
            f: impl Fn([T; 3], [f32; 3]) -> T,
        ) -> Vec<T> {
            items
                .iter()
                .map(|(k, w)| f(k.map(|i| v[i as usize]), *w))
                .collect()
        }
        let heaviest: Vec<u32> = items
            .iter()
            .map(|(k, w)| {
                let best = (1..3).fold(0, |b, j| if w[j] > w[b] { j } else { b });
                k[best]
            })
            .collect();
        match self {
            AttribData::Float(v) => AttribData::Float(mix(v, items, |x, w| {
                x[0] * w[0] + x[1] * w[1] + x[2] * w[2]
            })),
            AttribData::Vec2(v) => AttribData::Vec2(mix(v, items, |x, w| {
                x[0] * w[0] + x[1] * w[1] + x[2] * w[2]
            })),
            AttribData::Vec3(v) => AttribData::Vec3(mix(v, items, |x, w| {
                x[0] * w[0] + x[1] * w[1] + x[2] * w[2]
            })),
            AttribData::Vec4(v) => AttribData::Vec4(mix(v, items, |x, w| {
                x[0] * w[0] + x[1] * w[1] + x[2] * w[2]
            })),
            AttribData::Quat(v) => AttribData::Quat(mix(v, items, |q, w| {
                let align = |x: Quat| if x.dot(q[0]) < 0.0 { -x } else { x };
                let sum = q[0] * w[0] + align(q[1]) * w[1] + align(q[2]) * w[2];
                if sum.length_squared() > 0.0 {
                    sum.normalize()
                } else {
                    q[0]
                }
            })),
            AttribData::Int(_)
            | AttribData::Mat4(_)
            | AttribData::Mat3(_)
            | AttribData::String(_)
            | AttribData::IntArray(_)
            | AttribData::FloatArray(_)
            | AttribData::Vec3Array(_)
            | AttribData::StringArray(_) => self.gather(&heaviest),
        }
    }

    /// Appends `other`'s elements; false when the types differ.
    pub(crate) fn append(&mut self, other: &AttribData) -> bool {
        match (self, other) {
            (AttribData::Float(a), AttribData::Float(b)) => a.extend_from_slice(b),
            (AttribData::Int(a), AttribData::Int(b)) => a.extend_from_slice(b),
            (AttribData::Vec2(a), AttribData::Vec2(b)) => a.extend_from_slice(b),
            (AttribData::Vec3(a), AttribData::Vec3(b)) => a.extend_from_slice(b),
            (AttribData::Vec4(a), AttribData::Vec4(b)) => a.extend_from_slice(b),
            (AttribData::Quat(a), AttribData::Quat(b)) => a.extend_from_slice(b),
            (AttribData::Mat4(a), AttribData::Mat4(b)) => a.extend_from_slice(b),
            (AttribData::Mat3(a), AttribData::Mat3(b)) => a.extend_from_slice(b),
            (AttribData::String(a), AttribData::String(b)) => {
                let remap: Vec<u32> = b.table.iter().map(|s| a.intern(s)).collect();
                a.indices
                    .extend(b.indices.iter().map(|&i| remap[i as usize]));
            }
            (AttribData::IntArray(a), AttribData::IntArray(b)) => a.extend_from_slice(b),
            (AttribData::FloatArray(a), AttribData::FloatArray(b)) => a.extend_from_slice(b),
            (AttribData::Vec3Array(a), AttribData::Vec3Array(b)) => a.extend_from_slice(b),
            (AttribData::StringArray(a), AttribData::StringArray(b)) => a.extend_from_slice(b),
            _ => return false,
        }
        true
    }

    /// A float-based column as flat floats and the floats per element
    /// (None for int and string columns).
    pub fn as_floats(&self) -> Option<(&[f32], usize)> {
        Some(match self {
            AttribData::Float(v) => (v.as_slice(), 1),
            AttribData::Vec2(v) => (bytemuck::cast_slice(v), 2),
            AttribData::Vec3(v) => (bytemuck::cast_slice(v), 3),
            AttribData::Vec4(v) => (bytemuck::cast_slice(v), 4),
            AttribData::Quat(v) => (bytemuck::cast_slice(v), 4),
            AttribData::Mat4(v) => (bytemuck::cast_slice(v), 16),
            AttribData::Mat3(v) => (bytemuck::cast_slice(v), 9),
            AttribData::Int(_)
            | AttribData::String(_)
            | AttribData::IntArray(_)
            | AttribData::FloatArray(_)
            | AttribData::Vec3Array(_)
            | AttribData::StringArray(_) => return None,
        })
    }

    /// Mutable form of [`AttribData::as_floats`]; the length cannot change.
    pub fn as_floats_mut(&mut self) -> Option<(&mut [f32], usize)> {
        Some(match self {
            AttribData::Float(v) => (v.as_mut_slice(), 1),
            AttribData::Vec2(v) => (bytemuck::cast_slice_mut(v), 2),
            AttribData::Vec3(v) => (bytemuck::cast_slice_mut(v), 3),
            AttribData::Vec4(v) => (bytemuck::cast_slice_mut(v), 4),
            AttribData::Quat(v) => (bytemuck::cast_slice_mut(v), 4),
            AttribData::Mat4(v) => (bytemuck::cast_slice_mut(v), 16),
            AttribData::Mat3(v) => (bytemuck::cast_slice_mut(v), 9),
            AttribData::Int(_)
            | AttribData::String(_)
            | AttribData::IntArray(_)
            | AttribData::FloatArray(_)
            | AttribData::Vec3Array(_)
            | AttribData::StringArray(_) => return None,
        })
    }

    /// The raw bytes of a numeric column (None for strings).
    pub fn as_bytes(&self) -> Option<&[u8]> {
        each_column!(self, v => Some(bytemuck::cast_slice(v)), _s => None, _a => None)
    }
}

/// An attribute: its column, its semantic tag and the default for new elements.
/// The column is shared with the attribute's clones until one writes it
/// (copy on write): cloning a geometry copies no column.
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    pub type_info: TypeInfo,
    default: AttribValue,
    data: Shared<AttribData>,
}

macro_rules! typed_access {
    ($get:ident, $get_mut:ident, $variant:ident, $t:ty) => {
        pub fn $get(&self) -> Option<&[$t]> {
            match &*self.data {
                AttribData::$variant(v) => Some(v),
                _ => None,
            }
        }
        /// Copies the column first when another geometry shares it.
        pub fn $get_mut(&mut self) -> Option<&mut [$t]> {
            if !matches!(*self.data, AttribData::$variant(_)) {
                return None;
            }
            match self.data.make_mut() {
                AttribData::$variant(v) => Some(v),
                _ => None,
            }
        }
    };
}

impl Attribute {
    /// A column of `len` elements set to `default`.
    pub fn new(default: AttribValue, type_info: TypeInfo, len: usize) -> Attribute {
        Attribute {
            type_info,
            data: Shared::new(AttribData::filled(&default, len)),
            default,
        }
    }

    /// Wraps an existing column; the default is the type's zero.
    pub fn from_data(data: AttribData, type_info: TypeInfo) -> Attribute {
        Attribute {
            type_info,
            default: AttribValue::zero(data.attrib_type()),
            data: Shared::new(data),
        }
    }

    pub fn with_default(mut self, default: AttribValue) -> Result<Attribute, AttribType> {
        if default.attrib_type() != self.data.attrib_type() {
            return Err(default.attrib_type());
        }
        self.default = default;
        Ok(self)
    }

    pub fn attrib_type(&self) -> AttribType {
        self.data.attrib_type()
    }

    pub fn default_value(&self) -> &AttribValue {
        &self.default
    }

    pub fn data(&self) -> &AttribData {
        &self.data
    }

    /// The same attribute (type-info, default) over other values of its type.
    pub(crate) fn with_data(&self, data: AttribData) -> Attribute {
        debug_assert_eq!(data.attrib_type(), self.data.attrib_type());
        Attribute {
            type_info: self.type_info,
            default: self.default.clone(),
            data: Shared::new(data),
        }
    }

    /// Mutable access to the values (copied first when shared); the length
    /// cannot change through it.
    pub fn values_mut(&mut self) -> ValuesMut<'_> {
        ValuesMut(self.data.make_mut())
    }

    /// Whether two attributes hold one and the same column.
    pub fn shares_values(&self, other: &Attribute) -> bool {
        Shared::ptr_eq(&self.data, &other.data)
    }

    /// Makes the column this attribute's own without copying it when it is
    /// shared: its values become zeros. For a caller about to write every
    /// element (a copy would only be overwritten).
    pub fn discard_values(&mut self) {
        if !self.data.is_unique() {
            self.data = Shared::new(AttribData::zeroed(self.attrib_type(), self.len()));
        }
    }

    /// The content hash of the values alone, cached with the column (so
    /// geometries sharing it hash it once).
    pub(crate) fn values_hash(&self, f: impl FnOnce(&AttribData) -> u128) -> u128 {
        self.data.hash_with(f)
    }

    pub fn len(&self) -> usize {
        self.data.len()
    }

    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// The column's floats, flat, and the floats per element (float-based
    /// columns only).
    pub fn floats_mut(&mut self) -> Option<(&mut [f32], usize)> {
        self.data.as_floats()?;
        self.data.make_mut().as_floats_mut()
    }

    typed_access!(as_f32, as_f32_mut, Float, f32);
    typed_access!(as_i32, as_i32_mut, Int, i32);
    typed_access!(as_vec2, as_vec2_mut, Vec2, Vec2);
    typed_access!(as_vec3, as_vec3_mut, Vec3, Vec3);
    typed_access!(as_vec4, as_vec4_mut, Vec4, Vec4);
    typed_access!(as_quat, as_quat_mut, Quat, Quat);
    typed_access!(as_mat4, as_mat4_mut, Mat4, Mat4);
    typed_access!(as_mat3, as_mat3_mut, Mat3, Mat3);

    pub fn as_strings(&self) -> Option<&StringColumn> {
        match &*self.data {
            AttribData::String(s) => Some(s),
            _ => None,
        }
    }

    /// The same attribute (type info, default) over the elements at `indices`.
    pub fn gather(&self, indices: &[u32]) -> Attribute {
        Attribute {
            type_info: self.type_info,
            default: self.default.clone(),
            data: Shared::new(self.data.gather(indices)),
        }
    }

    /// An attribute of weighted sums of three elements each (see
    /// [`AttribData::mix3`]).
    pub fn mix3(&self, items: &[([u32; 3], [f32; 3])]) -> Attribute {
        Attribute {
            type_info: self.type_info,
            default: self.default.clone(),
            data: Shared::new(self.data.mix3(items)),
        }
    }
}

/// Length-preserving mutable view of a column.
pub struct ValuesMut<'a>(&'a mut AttribData);

impl ValuesMut<'_> {
    pub fn set(&mut self, i: usize, value: &AttribValue) -> Result<(), AttribType> {
        self.0.set(i, value)
    }

    /// Overwrites elements `at..at + from.len()` with `from` (a column of
    /// the same type) in one copy; errors with `from`'s type otherwise.
    pub fn write(&mut self, at: usize, from: &AttribData) -> Result<(), AttribType> {
        fn put<T: Clone>(to: &mut [T], at: usize, from: &[T]) {
            to[at..at + from.len()].clone_from_slice(from);
        }
        if at + from.len() > self.0.len() {
            return Err(from.attrib_type());
        }
        match (&mut *self.0, from) {
            (AttribData::Float(v), AttribData::Float(f)) => put(v, at, f),
            (AttribData::Int(v), AttribData::Int(f)) => put(v, at, f),
            (AttribData::Vec2(v), AttribData::Vec2(f)) => put(v, at, f),
            (AttribData::Vec3(v), AttribData::Vec3(f)) => put(v, at, f),
            (AttribData::Vec4(v), AttribData::Vec4(f)) => put(v, at, f),
            (AttribData::Quat(v), AttribData::Quat(f)) => put(v, at, f),
            (AttribData::Mat4(v), AttribData::Mat4(f)) => put(v, at, f),
            (AttribData::Mat3(v), AttribData::Mat3(f)) => put(v, at, f),
            (AttribData::IntArray(v), AttribData::IntArray(f)) => put(v, at, f),
            (AttribData::FloatArray(v), AttribData::FloatArray(f)) => put(v, at, f),
            (AttribData::Vec3Array(v), AttribData::Vec3Array(f)) => put(v, at, f),
            (AttribData::StringArray(v), AttribData::StringArray(f)) => put(v, at, f),
            (AttribData::String(v), AttribData::String(f)) => {
                let ids: Vec<u32> = f.table.iter().map(|x| v.intern(x)).collect();
                for (k, &i) in f.indices.iter().enumerate() {
                    v.indices[at + k] = ids[i as usize];
                }
            }
            (_, other) => return Err(other.attrib_type()),
        }
        Ok(())
    }
}
