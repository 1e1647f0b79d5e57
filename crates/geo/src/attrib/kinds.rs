//! What an attribute is: its class (point, vertex, primitive, detail), its
//! storage type, its type info, and one element's value.

use std::fmt;

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

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

impl TypeInfo {
    /// The tag Houdini gives an attribute created by this name (`N` is a
    /// normal, `v` a vector, `Cd` a colour, `orient` a quaternion).
    pub fn for_name(name: &str) -> TypeInfo {
        match name {
            "P" => TypeInfo::Position,
            "N" => TypeInfo::Normal,
            "v" | "up" | "accel" | "force" => TypeInfo::Vector,
            "Cd" => TypeInfo::Color,
            "orient" | "rot" => TypeInfo::Quaternion,
            _ => TypeInfo::None,
        }
    }
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
