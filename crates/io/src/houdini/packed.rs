//! Houdini's packed geometry (`PackedGeometry` primitives, their details embedded once in `sharedprimitivedata`) read into and written from geode's packed instances.
//!
//! A packed primitive is a vertex (its point places it), a 3x3 `transform`
//! (row vectors, so stored as geode's columns) and a `pivot`: the world
//! transform is translate(P) * transform * translate(-pivot), so geode's
//! instance matrix (linear part L, translation t) is written with
//! transform = L and pivot = -L⁻¹ t — representable whenever L is
//! invertible; a singular L with a translation is refused by name. geode
//! also writes the translation itself (`geode_translate`), which it reads
//! in preference, so its own files come back bit for bit.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{DMat3, DVec3, Mat3, Mat4};

use geode_geo::Geometry;

use super::json::Json;
use super::{EncodeError, CANCEL_EVERY};
use crate::error::{ParseError, ParseResult};

/// Houdini's tag for embedded details.
const EMBEDDED: &str = "gu:embeddedgeo";
/// geode's parameter beside the pivot: the instance's translation exactly.
const EXACT_TRANSLATION: &str = "geode_translate";

/// A packed primitive as read: its Houdini vertex, the detail it embeds and its transform.
pub(super) struct PackedPrim {
    pub vertex: u32,
    pub key: String,
    pub transform: Mat4,
}

/// The fields of one packed primitive, looked up by name.
pub(super) fn read_prim(field: &dyn Fn(&str) -> Option<Json>) -> ParseResult<PackedPrim> {
    let params = field("parameters").ok_or_else(|| ParseError::whole("no `parameters`"))?;
    let key = params
        .get("embedded")
        .and_then(Json::as_str)
        .ok_or_else(|| {
            ParseError::whole("only embedded packed geometry is read (this one references a file or another primitive)")
        })?
        .to_owned();
    let vertex = field("vertex")
        .and_then(|v| v.as_i64())
        .and_then(|v| u32::try_from(v).ok())
        .ok_or_else(|| ParseError::whole("no `vertex`"))?;
    let numbers = |name: &str, n: usize| -> ParseResult<Option<Vec<f64>>> {
        match field(name) {
            None => Ok(None),
            Some(v) => match v.numbers() {
                Some(x) if x.len() == n => Ok(Some(x)),
                _ => Err(ParseError::whole(format!("`{name}` must be {n} numbers"))),
            },
        }
    };
    // In f64: the translation -L·pivot comes back as the f32 it was written from.
    let linear = numbers("transform", 9)?.map_or(DMat3::IDENTITY, |m| DMat3::from_cols_slice(&m));
    let pivot = numbers("pivot", 3)?.map_or(DVec3::ZERO, |p| DVec3::from_slice(&p));
    // geode's own files carry the translation as written (the pivot's
    // round trip through an inverse is only close); else `+ 0.0` turns the
    // -0.0 of a zero pivot into the 0.0 it was.
    let exact = params
        .get(EXACT_TRANSLATION)
        .and_then(Json::numbers)
        .filter(|t| t.len() == 3);
    let t = match exact {
        Some(t) => glam::Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32),
        None => (-(linear * pivot) + DVec3::ZERO).as_vec3(),
    };
    let mut transform = Mat4::from_mat3(linear.as_mat3());
    transform.w_axis = t.extend(1.0);
    Ok(PackedPrim {
        vertex,
        key,
        transform,
    })
}

/// The packed primitives of a `run` of `PackedGeometry`: uniform fields in
/// the header, each primitive's varying ones in the body.
pub(super) fn read_run(header: &Json, body: &Json) -> ParseResult<Vec<PackedPrim>> {
    let varying: Vec<String> = header
        .get("varyingfields")
        .and_then(Json::items)
        .map(|f| {
            f.iter()
                .filter_map(Json::as_str)
                .map(str::to_owned)
                .collect()
        })
        .unwrap_or_default();
    let uniform = header.get("uniformfields");
    body.items()
        .unwrap_or_default()
        .iter()
        .map(|prim| {
            let values = prim.items().unwrap_or_default();
            read_prim(&|name| match varying.iter().position(|f| f == name) {
                Some(i) => values.get(i).cloned(),
                None => uniform.and_then(|u| u.get(name)).cloned(),
            })
        })
        .collect()
}

/// The embedded details of `sharedprimitivedata` by key, each read by `read`.
pub(super) fn read_shared(
    doc: &Json,
    read: &dyn Fn(&Json) -> ParseResult<Geometry>,
) -> ParseResult<HashMap<String, Arc<Geometry>>> {
    let mut out = HashMap::new();
    let Some(items) = doc.get("sharedprimitivedata").and_then(Json::items) else {
        return Ok(out);
    };
    for pair in items.chunks(2) {
        let [kind, data] = pair else { break };
        if kind.as_str() != Some("PackedGeometry") {
            continue;
        }
        let Some([tag, key, detail]) = data.items() else {
            return Err(ParseError::whole(
                "sharedprimitivedata: expected [tag, key, detail]",
            ));
        };
        if tag.as_str() != Some(EMBEDDED) {
            continue;
        }
        let key = key
            .as_str()
            .ok_or_else(|| ParseError::whole("sharedprimitivedata: a key is not text"))?;
        let g = read(detail)
            .map_err(|e| ParseError::whole(format!("embedded detail `{key}`: {}", e.message)))?;
        out.insert(key.to_owned(), Arc::new(g));
    }
    Ok(out)
}

/// The key naming a source's embedded detail (its content hash).
pub(super) fn key(source: &Geometry) -> String {
    format!("embed:{:032x}", source.content_hash())
}

/// A packed primitive's varying fields: parameters, vertex, transform, pivot.
pub(super) fn write_prim(source: &Geometry, vertex: usize, m: &Mat4) -> Result<Json, String> {
    let linear = Mat3::from_mat4(*m).as_dmat3();
    let t = m.w_axis.truncate().as_dvec3();
    let pivot = if t == DVec3::ZERO {
        DVec3::ZERO
    } else if linear.determinant().abs() > 1e-30 {
        -(linear.inverse() * t)
    } else {
        return Err(
            "a packed primitive with a singular transform and a translation has no pivot form"
                .into(),
        );
    };
    let params = Json::Map(vec![
        ("embedded".into(), Json::str(&key(source))),
        ("pointinstancetransform".into(), Json::Bool(false)),
        ("viewportlod".into(), Json::str("full")),
        (
            EXACT_TRANSLATION.into(),
            Json::F32s(m.w_axis.truncate().to_array().to_vec()),
        ),
    ]);
    Ok(Json::Array(vec![
        params,
        Json::Int(vertex as i64),
        Json::F32s(linear.as_mat3().to_cols_array().to_vec()),
        Json::F64s(pivot.to_array().to_vec()),
    ]))
}

/// `sharedprimitivedata` for the distinct sources of `g`, each written by `write`.
pub(super) fn write_shared(
    g: &Geometry,
    write: &dyn Fn(&Geometry) -> Result<Json, EncodeError>,
    cancelled: &dyn Fn() -> bool,
) -> Result<Option<Json>, EncodeError> {
    let mut seen = std::collections::HashSet::new();
    let mut items = Vec::new();
    for (i, inst) in g.packed_instances().iter().enumerate() {
        if i % CANCEL_EVERY == 0 && cancelled() {
            return Err(EncodeError::Cancelled);
        }
        let k = key(&inst.source);
        if seen.insert(k.clone()) {
            items.push(Json::str("PackedGeometry"));
            items.push(Json::Array(vec![
                Json::str(EMBEDDED),
                Json::str(&k),
                write(&inst.source)?,
            ]));
        }
    }
    Ok((!items.is_empty()).then_some(Json::Array(items)))
}
