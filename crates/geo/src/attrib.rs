//! Typed attribute columns (structure of arrays) and the tables that hold them per class.

use std::collections::BTreeMap;
use std::fmt;

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

use crate::error::GeoError;
use crate::shared::Shared;

/// Which element an attribute is stored on, as in Houdini.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AttribClass {
    Point,
    Vertex,
    Primitive,
    Detail,
}

impl AttribClass {
    pub const ALL: [AttribClass; 4] = [
        AttribClass::Point,
        AttribClass::Vertex,
        AttribClass::Primitive,
        AttribClass::Detail,
    ];
}

impl fmt::Display for AttribClass {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AttribClass::Point => "point",
            AttribClass::Vertex => "vertex",
            AttribClass::Primitive => "primitive",
            AttribClass::Detail => "detail",
        })
    }
}

/// The storage type of an attribute column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AttribType {
    Float,
    Int,
    Vec2,
    Vec3,
    Vec4,
    Quat,
    Mat4,
    Mat3,
    String,
    /// Arrays per element (Houdini's `i[]@` and `f[]@`).
    IntArray,
    FloatArray,
    Vec3Array,
    StringArray,
}

impl AttribType {
    /// Every type. The binary codec numbers types by their place here:
    /// append, never reorder.
    pub const ALL: [AttribType; 13] = [
        AttribType::Float,
        AttribType::Int,
        AttribType::Vec2,
        AttribType::Vec3,
        AttribType::Vec4,
        AttribType::Quat,
        AttribType::Mat4,
        AttribType::Mat3,
        AttribType::String,
        AttribType::IntArray,
        AttribType::FloatArray,
        AttribType::Vec3Array,
        AttribType::StringArray,
    ];
}

impl fmt::Display for AttribType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AttribType::Float => "float",
            AttribType::Int => "int",
            AttribType::Vec2 => "vector2",
            AttribType::Vec3 => "vector3",
            AttribType::Vec4 => "vector4",
            AttribType::Quat => "quaternion",
            AttribType::Mat4 => "matrix4",
            AttribType::Mat3 => "matrix3",
            AttribType::String => "string",
            AttribType::IntArray => "int array",
            AttribType::FloatArray => "float array",
            AttribType::Vec3Array => "vector3 array",
            AttribType::StringArray => "string array",
        })
    }
}

/// Semantic tag telling transforms how to treat a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum TypeInfo {
    /// Plain data: transforms leave it alone.
    #[default]
    None,
    /// A location: the full affine transform applies.
    Position,
    /// A direction with length: the linear part applies.
    Vector,
    /// A surface normal: the inverse transpose applies, then renormalisation.
    Normal,
    /// A colour: never transformed.
    Color,
    /// An orientation: the rotation part is pre-multiplied.
    Quaternion,
    /// Texture coordinates: never transformed.
    TexCoord,
    /// A local 4x4 transform (instancing): the linear part is pre-multiplied.
    Transform,
}

impl TypeInfo {
    /// Every tag. The binary codec numbers tags by their place here:
    /// append, never reorder.
    pub const ALL: [TypeInfo; 8] = [
        TypeInfo::None,
        TypeInfo::Position,
        TypeInfo::Vector,
        TypeInfo::Normal,
        TypeInfo::Color,
        TypeInfo::Quaternion,
        TypeInfo::TexCoord,
        TypeInfo::Transform,
    ];
}

impl fmt::Display for TypeInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            TypeInfo::None => "none",
            TypeInfo::Position => "position",
            TypeInfo::Vector => "vector",
            TypeInfo::Normal => "normal",
            TypeInfo::Color => "color",
            TypeInfo::Quaternion => "quaternion",
            TypeInfo::TexCoord => "texcoord",
            TypeInfo::Transform => "transform",
        })
    }
}

/// One attribute value, used for defaults and single-element access.
#[derive(Clone, Debug, PartialEq)]
pub enum AttribValue {
    Float(f32),
    Int(i32),
    Vec2(Vec2),
    Vec3(Vec3),
    Vec4(Vec4),
    Quat(Quat),
    Mat4(Mat4),
    Mat3(Mat3),
    String(String),
    IntArray(Vec<i32>),
    FloatArray(Vec<f32>),
    Vec3Array(Vec<Vec3>),
    StringArray(Vec<String>),
}

impl AttribValue {
    pub fn attrib_type(&self) -> AttribType {
        match self {
            AttribValue::Float(_) => AttribType::Float,
            AttribValue::Int(_) => AttribType::Int,
            AttribValue::Vec2(_) => AttribType::Vec2,
            AttribValue::Vec3(_) => AttribType::Vec3,
            AttribValue::Vec4(_) => AttribType::Vec4,
            AttribValue::Quat(_) => AttribType::Quat,
            AttribValue::Mat4(_) => AttribType::Mat4,
            AttribValue::Mat3(_) => AttribType::Mat3,
            AttribValue::String(_) => AttribType::String,
            AttribValue::IntArray(_) => AttribType::IntArray,
            AttribValue::FloatArray(_) => AttribType::FloatArray,
            AttribValue::Vec3Array(_) => AttribType::Vec3Array,
            AttribValue::StringArray(_) => AttribType::StringArray,
        }
    }

    /// The zero value of a type (identity for quaternions and matrices).
    pub fn zero(ty: AttribType) -> AttribValue {
        match ty {
            AttribType::Float => AttribValue::Float(0.0),
            AttribType::Int => AttribValue::Int(0),
            AttribType::Vec2 => AttribValue::Vec2(Vec2::ZERO),
            AttribType::Vec3 => AttribValue::Vec3(Vec3::ZERO),
            AttribType::Vec4 => AttribValue::Vec4(Vec4::ZERO),
            AttribType::Quat => AttribValue::Quat(Quat::IDENTITY),
            AttribType::Mat4 => AttribValue::Mat4(Mat4::IDENTITY),
            AttribType::Mat3 => AttribValue::Mat3(Mat3::IDENTITY),
            AttribType::String => AttribValue::String(String::new()),
            AttribType::IntArray => AttribValue::IntArray(Vec::new()),
            AttribType::FloatArray => AttribValue::FloatArray(Vec::new()),
            AttribType::Vec3Array => AttribValue::Vec3Array(Vec::new()),
            AttribType::StringArray => AttribValue::StringArray(Vec::new()),
        }
    }
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
