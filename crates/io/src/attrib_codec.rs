//! Geode attribute types named in files that have no type system of their own (PLY header comments, glTF accessor extras), and columns rebuilt from flat floats.

use geode_geo::{AttribData, AttribType, AttribValue, TypeInfo};

/// The token naming each attribute type a file can carry (strings aside):
/// its name (`Display`) without spaces, so one word in a header.
pub(crate) fn type_token(ty: AttribType) -> Option<String> {
    match ty {
        AttribType::String | AttribType::StringArray => None,
        _ => Some(ty.to_string().replace(' ', "")),
    }
}

pub(crate) fn type_from_token(token: &str) -> Option<AttribType> {
    AttribType::ALL
        .into_iter()
        .find(|&t| type_token(t).as_deref() == Some(token))
}

pub(crate) fn info_from_token(token: &str) -> TypeInfo {
    TypeInfo::ALL
        .into_iter()
        .find(|t| t.to_string() == token)
        .unwrap_or(TypeInfo::None)
}

/// The property suffixes of a multi-component type (`NAME_x` ..), empty for scalars.
pub(crate) fn component_suffixes(ty: AttribType) -> Vec<String> {
    let n = match ty {
        AttribType::Vec2 => 2,
        AttribType::Vec3 => 3,
        AttribType::Vec4 | AttribType::Quat => 4,
        AttribType::Mat3 => return (0..9).map(|i| i.to_string()).collect(),
        AttribType::Mat4 => return (0..16).map(|i| i.to_string()).collect(),
        _ => return Vec::new(),
    };
    ["x", "y", "z", "w"][..n]
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// A column of `ty` from its components flat in element order (`None` for
/// types not made of floats, or a length that is not whole elements).
pub(crate) fn column_from_floats(ty: AttribType, flat: &[f32]) -> Option<AttribData> {
    if ty == AttribType::Int {
        return Some(AttribData::Int(flat.iter().map(|&x| x as i32).collect()));
    }
    let k = AttribData::filled(&AttribValue::zero(ty), 1).as_floats()?.1;
    if !flat.len().is_multiple_of(k) {
        return None;
    }
    let mut data = AttribData::filled(&AttribValue::zero(ty), flat.len() / k);
    data.as_floats_mut()?.0.copy_from_slice(flat);
    Some(data)
}
