//! Geode's own point and vertex attributes in glTF: application-specific vertex attributes (`_NAME`), their geode type kept in the accessor's `extras`.
//!
//! glTF carries `N`, `uv` and `Cd` under its own semantics; every other
//! float-based point or vertex attribute (float, vectors, quaternions,
//! 3x3 and 4x4 matrices) becomes `_NAME` with FLOAT components, and an int
//! attribute whose values a float holds exactly (|v| <= 2^24) too — glTF
//! allows no 32-bit signed integers, and application attributes no
//! unsigned 32-bit ones. The accessor's `extras.geode` records the geode
//! type and type info so geode reads the attribute back as it was.
//! Primitive and detail attributes, strings, arrays and groups have no
//! glTF form and are reported.

use geode_geo::{AttribClass, AttribData, AttribType, Attribute, Geometry, TypeInfo};
use serde_json::{json, Value};

use crate::progress::describe_attrib;

/// Names glTF carries under its own semantics.
const STANDARD: [&str; 3] = ["N", "uv", "Cd"];

/// A point or vertex attribute written as `_NAME`.
pub(crate) struct Custom<'a> {
    pub class: AttribClass,
    pub name: &'a str,
    pub attrib: &'a Attribute,
}

/// Largest integer every f32 holds exactly.
const EXACT_INT: i32 = 1 << 24;

/// The attributes of `g` written as `_NAME`, and descriptions of those glTF cannot hold.
pub(crate) fn custom_columns(g: &Geometry) -> (Vec<Custom<'_>>, Vec<String>) {
    let (mut out, mut dropped) = (Vec::new(), Vec::new());
    for class in AttribClass::ALL {
        for (name, a) in g.attribs(class).iter() {
            let standard = name == geode_geo::P
                || (STANDARD.contains(&name)
                    && matches!(class, AttribClass::Point | AttribClass::Vertex));
            if standard {
                continue;
            }
            let fits = match a.data() {
                AttribData::Int(v) => v.iter().all(|x| x.abs() <= EXACT_INT),
                d => d.as_floats().is_some(),
            };
            let identifier = !name.is_empty() && name.chars().all(|c| c.is_ascii_graphic());
            if fits && identifier && matches!(class, AttribClass::Point | AttribClass::Vertex) {
                out.push(Custom {
                    class,
                    name,
                    attrib: a,
                });
            } else {
                dropped.push(describe_attrib(class, name, a.attrib_type()));
            }
        }
    }
    (out, dropped)
}

/// The glTF accessor type for `k` floats per element.
fn accessor_type(k: usize) -> Option<&'static str> {
    Some(match k {
        1 => "SCALAR",
        2 => "VEC2",
        3 => "VEC3",
        4 => "VEC4",
        9 => "MAT3",
        16 => "MAT4",
        _ => return None,
    })
}

impl Custom<'_> {
    /// The values of each glTF vertex (a point, and a corner when the
    /// layout is per corner), flat, with the accessor type and its extras.
    pub fn gather(
        &self,
        vertex_source: &[(u32, Option<u32>)],
    ) -> Option<(Vec<f32>, &'static str, Value)> {
        let element = |&(pt, vx): &(u32, Option<u32>)| match self.class {
            AttribClass::Vertex => vx.unwrap_or(0) as usize,
            _ => pt as usize,
        };
        let (flat, k): (Vec<f32>, usize) = match self.attrib.data() {
            AttribData::Int(v) => (
                vertex_source.iter().map(|s| v[element(s)] as f32).collect(),
                1,
            ),
            d => {
                let (f, k) = d.as_floats()?;
                let flat = vertex_source
                    .iter()
                    .flat_map(|s| f[element(s) * k..(element(s) + 1) * k].iter().copied())
                    .collect();
                (flat, k)
            }
        };
        let extras = json!({"geode": {
            "type": crate::attrib_codec::type_token(self.attrib.attrib_type()),
            "typeinfo": self.attrib.type_info.to_string(),
        }});
        Some((flat, accessor_type(k)?, extras))
    }

    pub fn semantic(&self) -> String {
        format!("_{}", self.name)
    }
}

/// A custom attribute read back: its geode type from the accessor's
/// `extras` when geode wrote it, else from the accessor's shape.
pub(crate) fn read_custom(
    accessor: &gltf::Accessor,
    flat: Vec<f32>,
) -> Option<(AttribData, TypeInfo)> {
    let extras: Option<Value> = accessor
        .extras()
        .as_ref()
        .and_then(|r| serde_json::from_str(r.get()).ok());
    let declared = extras.as_ref().and_then(|e| e.get("geode"));
    let ty = declared
        .and_then(|d| d.get("type"))
        .and_then(Value::as_str)
        .and_then(crate::attrib_codec::type_from_token);
    let info = declared
        .and_then(|d| d.get("typeinfo"))
        .and_then(Value::as_str)
        .map(crate::attrib_codec::info_from_token)
        .unwrap_or(TypeInfo::None);
    use gltf::accessor::Dimensions as D;
    let ty = ty.unwrap_or(match accessor.dimensions() {
        D::Scalar => AttribType::Float,
        D::Vec2 => AttribType::Vec2,
        D::Vec3 => AttribType::Vec3,
        D::Vec4 => AttribType::Vec4,
        D::Mat3 => AttribType::Mat3,
        D::Mat4 => AttribType::Mat4,
        D::Mat2 => return None,
    });
    let data = crate::attrib_codec::column_from_floats(ty, &flat)?;
    Some((data, info))
}
