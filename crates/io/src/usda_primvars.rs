//! Geode attributes as USD primvars: the USD type (with its role) of each column, its interpolation by class, and its values as `.usda` text.
//!
//! Houdini's mapping: point attributes are `vertex` primvars, vertex
//! attributes `faceVarying` (on curves, whose control points are their
//! vertices, `vertex`), primitive attributes `uniform`, detail attributes
//! `constant`. Type info becomes the role (`color3f`, `normal3f`,
//! `point3f`, `vector3f`, `texCoord2f`, `quatf`). `N`, `Cd`, `Alpha` and
//! `uv` take USD's own names (`normals`, `displayColor`, `displayOpacity`,
//! `st`). Per-element arrays have no primvar form and are reported.

use std::fmt::Write as _;

use geode_geo::glam::{Mat3, Mat4};
use geode_geo::{AttribClass, AttribData, Attribute, TypeInfo};

/// Where a primvar's values sit on the USD prim.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interpolation {
    Vertex,
    FaceVarying,
    Uniform,
    Constant,
}

impl Interpolation {
    pub fn token(self) -> &'static str {
        match self {
            Interpolation::Vertex => "vertex",
            Interpolation::FaceVarying => "faceVarying",
            Interpolation::Uniform => "uniform",
            Interpolation::Constant => "constant",
        }
    }

    /// The interpolation of an attribute class on a mesh (`curves`: on
    /// linear curves, where a vertex is a control point).
    pub fn of(class: AttribClass, curves: bool) -> Interpolation {
        match class {
            AttribClass::Point => Interpolation::Vertex,
            AttribClass::Vertex if curves => Interpolation::Vertex,
            AttribClass::Vertex => Interpolation::FaceVarying,
            AttribClass::Primitive => Interpolation::Uniform,
            AttribClass::Detail => Interpolation::Constant,
        }
    }
}

/// One attribute as a USD property: its name on the prim and its element type.
pub(crate) struct Primvar<'a> {
    /// `normals` or `primvars:NAME`.
    pub property: String,
    /// The element type, e.g. `color3f` (arrays add `[]`).
    pub usd_type: &'static str,
    pub data: &'a AttribData,
    /// Only the first two components are written (a vector3 `uv` as `st`).
    pub as_st: bool,
}

/// The primvar for an attribute, or `None` when USD has no form for it.
pub(crate) fn primvar<'a>(name: &str, a: &'a Attribute) -> Option<Primvar<'a>> {
    let data = a.data();
    let info = a.type_info;
    let (property, as_st) = match (name, data) {
        ("N", AttribData::Vec3(_)) => ("normals".to_owned(), false),
        ("Cd", AttribData::Vec3(_)) => ("primvars:displayColor".to_owned(), false),
        ("Alpha", AttribData::Float(_)) => ("primvars:displayOpacity".to_owned(), false),
        ("uv", AttribData::Vec2(_)) => ("primvars:st".to_owned(), false),
        ("uv", AttribData::Vec3(_)) => ("primvars:st".to_owned(), true),
        _ => (format!("primvars:{}", usd_identifier(name)), false),
    };
    let usd_type = if as_st || property == "primvars:st" {
        "texCoord2f"
    } else if property == "normals" {
        "normal3f"
    } else if property == "primvars:displayColor" {
        "color3f"
    } else {
        usd_type(data, info)?
    };
    Some(Primvar {
        property,
        usd_type,
        data,
        as_st,
    })
}

fn usd_type(data: &AttribData, info: TypeInfo) -> Option<&'static str> {
    Some(match data {
        AttribData::Float(_) => "float",
        AttribData::Int(_) => "int",
        AttribData::Vec2(_) if info == TypeInfo::TexCoord => "texCoord2f",
        AttribData::Vec2(_) => "float2",
        AttribData::Vec3(_) => match info {
            TypeInfo::Color => "color3f",
            TypeInfo::Normal => "normal3f",
            TypeInfo::Position => "point3f",
            TypeInfo::Vector => "vector3f",
            TypeInfo::TexCoord => "texCoord3f",
            _ => "float3",
        },
        AttribData::Vec4(_) if info == TypeInfo::Color => "color4f",
        AttribData::Vec4(_) => "float4",
        AttribData::Quat(_) => "quatf",
        AttribData::Mat3(_) => "matrix3d",
        AttribData::Mat4(_) => "matrix4d",
        AttribData::String(_) => "string",
        AttribData::IntArray(_)
        | AttribData::FloatArray(_)
        | AttribData::Vec3Array(_)
        | AttribData::StringArray(_) => return None,
    })
}

/// USD property names are identifiers: anything else becomes `_`.
fn usd_identifier(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.starts_with(|c: char| c.is_ascii_digit()) || s.is_empty() {
        s.insert(0, '_');
    }
    s
}

/// Appends element `i`'s value in `.usda` syntax.
pub(crate) fn write_value(out: &mut String, pv: &Primvar, i: usize) {
    match pv.data {
        AttribData::Float(v) => {
            let _ = write!(out, "{}", v[i]);
        }
        AttribData::Int(v) => {
            let _ = write!(out, "{}", v[i]);
        }
        AttribData::Vec2(v) => {
            let _ = write!(out, "({}, {})", v[i].x, v[i].y);
        }
        AttribData::Vec3(v) if pv.as_st => {
            let _ = write!(out, "({}, {})", v[i].x, v[i].y);
        }
        AttribData::Vec3(v) => {
            let _ = write!(out, "({}, {}, {})", v[i].x, v[i].y, v[i].z);
        }
        AttribData::Vec4(v) => {
            let _ = write!(out, "({}, {}, {}, {})", v[i].x, v[i].y, v[i].z, v[i].w);
        }
        // USD writes quaternions real part first.
        AttribData::Quat(v) => {
            let _ = write!(out, "({}, {}, {}, {})", v[i].w, v[i].x, v[i].y, v[i].z);
        }
        AttribData::Mat3(v) => out.push_str(&matrix3(&v[i])),
        AttribData::Mat4(v) => out.push_str(&matrix4(&v[i])),
        AttribData::String(s) => {
            out.push_str(&serde_json::to_string(s.get(i)).unwrap_or_else(|_| "\"\"".into()))
        }
        AttribData::IntArray(_)
        | AttribData::FloatArray(_)
        | AttribData::Vec3Array(_)
        | AttribData::StringArray(_) => {}
    }
}

/// USD matrices multiply row vectors: its rows are our columns.
pub(crate) fn matrix4(m: &Mat4) -> String {
    let rows: Vec<String> = m
        .to_cols_array_2d()
        .iter()
        .map(|r| {
            format!(
                "({}, {}, {}, {})",
                r[0] as f64, r[1] as f64, r[2] as f64, r[3] as f64
            )
        })
        .collect();
    format!("({})", rows.join(", "))
}

fn matrix3(m: &Mat3) -> String {
    let rows: Vec<String> = m
        .to_cols_array_2d()
        .iter()
        .map(|r| format!("({}, {}, {})", r[0] as f64, r[1] as f64, r[2] as f64))
        .collect();
    format!("({})", rows.join(", "))
}
