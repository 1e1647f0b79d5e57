//! VEX's value types, their widths in float slots and their spelling,
//! and how they map to attribute columns.

use geode_geo::{AttribData, AttribType};

/// The element type of an array, or the type of a plain value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ty {
    Void,
    Int,
    Float,
    Vec2,
    Vec3,
    Vec4,
    Mat3,
    Mat4,
    Str,
    Array(Elem),
}

/// What an array holds: any non-array type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Elem {
    Int,
    Float,
    Vec2,
    Vec3,
    Vec4,
    Mat3,
    Mat4,
    Str,
}

impl Elem {
    pub fn ty(self) -> Ty {
        match self {
            Elem::Int => Ty::Int,
            Elem::Float => Ty::Float,
            Elem::Vec2 => Ty::Vec2,
            Elem::Vec3 => Ty::Vec3,
            Elem::Vec4 => Ty::Vec4,
            Elem::Mat3 => Ty::Mat3,
            Elem::Mat4 => Ty::Mat4,
            Elem::Str => Ty::Str,
        }
    }
}

impl Ty {
    /// The array of this type, if it can be one.
    pub fn array(self) -> Option<Ty> {
        Some(Ty::Array(match self {
            Ty::Int => Elem::Int,
            Ty::Float => Elem::Float,
            Ty::Vec2 => Elem::Vec2,
            Ty::Vec3 => Elem::Vec3,
            Ty::Vec4 => Elem::Vec4,
            Ty::Mat3 => Elem::Mat3,
            Ty::Mat4 => Elem::Mat4,
            Ty::Str => Elem::Str,
            Ty::Void | Ty::Array(_) => return None,
        }))
    }

    /// Float slots of a float-based type (0 for int, string, array).
    pub fn floats(self) -> usize {
        match self {
            Ty::Float => 1,
            Ty::Vec2 => 2,
            Ty::Vec3 => 3,
            Ty::Vec4 => 4,
            Ty::Mat3 => 9,
            Ty::Mat4 => 16,
            _ => 0,
        }
    }

    /// Whether values live in float registers (float, vectors, matrices).
    pub fn is_floaty(self) -> bool {
        self.floats() > 0
    }

    /// Whether arithmetic applies (int and the float-based types).
    pub fn is_numeric(self) -> bool {
        self == Ty::Int || self.is_floaty()
    }

    pub fn is_vector(self) -> bool {
        matches!(self, Ty::Vec2 | Ty::Vec3 | Ty::Vec4)
    }

    pub fn is_matrix(self) -> bool {
        matches!(self, Ty::Mat3 | Ty::Mat4)
    }

    /// The type named by a VEX keyword.
    pub fn from_keyword(word: &str) -> Option<Ty> {
        Some(match word {
            "void" => Ty::Void,
            "int" => Ty::Int,
            "float" => Ty::Float,
            "vector2" => Ty::Vec2,
            "vector" => Ty::Vec3,
            "vector4" => Ty::Vec4,
            "matrix3" => Ty::Mat3,
            "matrix" => Ty::Mat4,
            "string" => Ty::Str,
            _ => return None,
        })
    }

    /// The type a binding prefix (`f@`, `v@`, ...) declares.
    pub fn from_prefix(prefix: char) -> Option<Ty> {
        Some(match prefix {
            'f' => Ty::Float,
            'i' => Ty::Int,
            'v' => Ty::Vec3,
            'u' => Ty::Vec2,
            'p' => Ty::Vec4,
            '3' => Ty::Mat3,
            '4' => Ty::Mat4,
            's' => Ty::Str,
            _ => return None,
        })
    }

    /// The float-based type of `n` slots (vectors by width).
    pub fn of_floats(n: usize) -> Option<Ty> {
        Some(match n {
            1 => Ty::Float,
            2 => Ty::Vec2,
            3 => Ty::Vec3,
            4 => Ty::Vec4,
            9 => Ty::Mat3,
            16 => Ty::Mat4,
            _ => return None,
        })
    }
}

impl Ty {
    /// The type with its article: "an int", "a vector".
    pub fn a(self) -> String {
        let s = self.to_string();
        let vowel = s.starts_with(['a', 'e', 'i', 'o', 'u']);
        format!("{} {s}", if vowel { "an" } else { "a" })
    }
}

impl std::fmt::Display for Ty {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Ty::Void => f.write_str("void"),
            Ty::Int => f.write_str("int"),
            Ty::Float => f.write_str("float"),
            Ty::Vec2 => f.write_str("vector2"),
            Ty::Vec3 => f.write_str("vector"),
            Ty::Vec4 => f.write_str("vector4"),
            Ty::Mat3 => f.write_str("matrix3"),
            Ty::Mat4 => f.write_str("matrix"),
            Ty::Str => f.write_str("string"),
            Ty::Array(e) => write!(f, "{}[]", e.ty()),
        }
    }
}

/// The VEX type of an attribute column.
pub fn ty_of(data: &AttribData) -> Option<Ty> {
    Some(match data {
        AttribData::Float(_) => Ty::Float,
        AttribData::Int(_) => Ty::Int,
        AttribData::Vec2(_) => Ty::Vec2,
        AttribData::Vec3(_) => Ty::Vec3,
        AttribData::Vec4(_) | AttribData::Quat(_) => Ty::Vec4,
        AttribData::Mat4(_) => Ty::Mat4,
        AttribData::String(_) => Ty::Str,
        AttribData::IntArray(_) => Ty::Array(crate::ty::Elem::Int),
        AttribData::FloatArray(_) => Ty::Array(crate::ty::Elem::Float),
        AttribData::Mat3(_) => Ty::Mat3,
        AttribData::Vec3Array(_) => Ty::Array(crate::ty::Elem::Vec3),
        AttribData::StringArray(_) => Ty::Array(crate::ty::Elem::Str),
    })
}

/// The attribute type a binding of `ty` creates.
pub fn attrib_type(ty: Ty) -> Option<AttribType> {
    Some(match ty {
        Ty::Float => AttribType::Float,
        Ty::Int => AttribType::Int,
        Ty::Vec2 => AttribType::Vec2,
        Ty::Vec3 => AttribType::Vec3,
        Ty::Vec4 => AttribType::Vec4,
        Ty::Mat4 => AttribType::Mat4,
        Ty::Str => AttribType::String,
        Ty::Array(crate::ty::Elem::Int) => AttribType::IntArray,
        Ty::Array(crate::ty::Elem::Float) => AttribType::FloatArray,
        Ty::Array(crate::ty::Elem::Vec3) => AttribType::Vec3Array,
        Ty::Array(crate::ty::Elem::Str) => AttribType::StringArray,
        Ty::Mat3 => AttribType::Mat3,
        _ => return None,
    })
}
