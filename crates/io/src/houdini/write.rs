//! A `Geometry` written in Houdini's geometry schema: polygon runs, polyline runs, packed geometry, every attribute with its type info, groups.

use geode_geo::attrib::{AttribClass, AttribData, AttribTable, AttribValue, Attribute, TypeInfo};
use geode_geo::{Geometry, PrimKind};

use super::groups::group;
use super::json::Json;
use super::{
    houdini_order, packed, type_info_name, EncodeError, ARRAY_TYPE, CANCEL_EVERY, STRING_ARRAY_TYPE,
};

/// Houdini reads files of its own and older versions; this is the schema
/// version whose layout (`Polygon_run`, `rawpagedata`) the writer follows.
const FILE_VERSION: &str = "18.5.0";
/// Elements per page of `rawpagedata` (Houdini's own page size).
const PAGE_SIZE: i64 = 1024;

/// The document for `g`: polygons, polylines and packed instances (their
/// sources embedded once each); the caller refuses patches.
pub fn document(g: &Geometry, cancelled: &dyn Fn() -> bool) -> Result<Json, EncodeError> {
    // Houdini's vertex order: each polygon's vertices turned to clockwise.
    let order = vertex_order(g);
    let pointref: Vec<i32> = order
        .iter()
        .map(|&v| g.vertex_points()[v as usize] as i32)
        .collect();
    let mut entries = vec![
        ("fileversion", Json::str(FILE_VERSION)),
        ("hasindex", Json::Bool(false)),
        ("pointcount", Json::Int(g.num_points() as i64)),
        ("vertexcount", Json::Int(g.num_vertices() as i64)),
        ("primitivecount", Json::Int(g.num_prims() as i64)),
        (
            "info",
            Json::Map(vec![(
                "software".into(),
                Json::str(concat!("geode ", env!("CARGO_PKG_VERSION"))),
            )]),
        ),
        (
            "topology",
            Json::pairs(vec![(
                "pointref",
                Json::pairs(vec![("indices", Json::I32s(pointref))]),
            )]),
        ),
        ("attributes", attributes(g, &order)),
        ("primitives", primitives(g, cancelled)?),
    ];
    if let Some(shared) = packed::write_shared(g, &|s| document(s, cancelled), cancelled)? {
        entries.push(("sharedprimitivedata", shared));
    }
    for (key, groups) in [
        ("pointgroups", g.point_groups()),
        ("primitivegroups", g.prim_groups()),
    ] {
        if !groups.is_empty() {
            entries.push((
                key,
                Json::Array(groups.iter().map(|(n, grp)| group(n, grp)).collect()),
            ));
        }
    }
    Ok(Json::pairs(entries))
}

fn vertex_order(g: &Geometry) -> Vec<u32> {
    let mut order: Vec<u32> = (0..g.num_vertices() as u32).collect();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) == PrimKind::Polygon {
            houdini_order(&mut order[g.prim_vertex_range(prim)]);
        }
    }
    order
}

fn attributes(g: &Geometry, order: &[u32]) -> Json {
    let mut classes = Vec::new();
    for (key, class) in [
        ("vertexattributes", AttribClass::Vertex),
        ("pointattributes", AttribClass::Point),
        ("primitiveattributes", AttribClass::Primitive),
        ("globalattributes", AttribClass::Detail),
    ] {
        let table: &AttribTable = g.attribs(class);
        if table.num_attribs() == 0 {
            continue;
        }
        // P first, as Houdini writes it.
        let mut named: Vec<(&str, &Attribute)> = table.iter().collect();
        named.sort_by_key(|(n, _)| *n != geode_geo::P);
        let list = named
            .into_iter()
            .map(|(name, a)| {
                if class == AttribClass::Vertex {
                    attribute(name, &a.gather(order))
                } else {
                    attribute(name, a)
                }
            })
            .collect();
        classes.push((key, Json::Array(list)));
    }
    Json::pairs(classes)
}

fn header(name: &str, ty: &str, info: TypeInfo) -> Json {
    let options = match type_info_name(info) {
        Some(t) => Json::Map(vec![(
            "type".into(),
            Json::Map(vec![
                ("type".into(), Json::str("string")),
                ("value".into(), Json::str(t)),
            ]),
        )]),
        None => Json::Map(Vec::new()),
    };
    Json::pairs(vec![
        ("scope", Json::str("public")),
        ("type", Json::str(ty)),
        ("name", Json::str(name)),
        ("options", options),
    ])
}

/// A block of `size`-tuples, flat, as one page run without constant pages.
fn paged(size: usize, storage: &str, flat: Json) -> Json {
    Json::pairs(vec![
        ("size", Json::Int(size as i64)),
        ("storage", Json::str(storage)),
        ("packing", Json::Array(vec![Json::Int(size as i64)])),
        ("pagesize", Json::Int(PAGE_SIZE)),
        ("rawpagedata", flat),
    ])
}

fn defaults(values: Vec<f64>) -> Json {
    Json::pairs(vec![
        ("size", Json::Int(values.len() as i64)),
        ("storage", Json::str("fpreal64")),
        (
            "values",
            Json::Array(values.into_iter().map(Json::Real).collect()),
        ),
    ])
}

fn default_numbers(v: &AttribValue) -> Vec<f64> {
    match v {
        AttribValue::Int(i) => vec![*i as f64],
        other => AttribData::filled(other, 1)
            .as_floats()
            .map(|(f, _)| f.iter().map(|&x| x as f64).collect())
            .unwrap_or_default(),
    }
}

fn attribute(name: &str, a: &Attribute) -> Json {
    let data = a.data();
    let default = a.default_value();
    let (ty, body) = match data {
        AttribData::Int(v) => (
            "numeric",
            Json::pairs(vec![
                ("size", Json::Int(1)),
                ("storage", Json::str("int32")),
                ("defaults", defaults(default_numbers(default))),
                ("values", paged(1, "int32", Json::I32s(v.clone()))),
            ]),
        ),
        AttribData::String(col) => (
            "string",
            Json::pairs(vec![
                ("size", Json::Int(1)),
                ("storage", Json::str("int32")),
                (
                    "strings",
                    Json::Array(col.table.iter().map(|s| Json::str(s)).collect()),
                ),
                (
                    "indices",
                    paged(
                        1,
                        "int32",
                        Json::I32s(col.indices.iter().map(|&i| i as i32).collect()),
                    ),
                ),
            ]),
        ),
        AttribData::IntArray(lists) => (
            ARRAY_TYPE,
            arrays(1, "int32", lists.iter().map(|l| Json::I32s(l.clone()))),
        ),
        AttribData::FloatArray(lists) => (
            ARRAY_TYPE,
            arrays(1, "fpreal32", lists.iter().map(|l| Json::F32s(l.clone()))),
        ),
        AttribData::Vec3Array(lists) => (
            ARRAY_TYPE,
            arrays(
                3,
                "fpreal32",
                lists
                    .iter()
                    .map(|l| Json::F32s(bytemuck::cast_slice(l).to_vec())),
            ),
        ),
        AttribData::StringArray(lists) => (STRING_ARRAY_TYPE, string_arrays(lists)),
        _ => {
            let (flat, size) = data.as_floats().expect("every other column is float-based");
            (
                "numeric",
                Json::pairs(vec![
                    ("size", Json::Int(size as i64)),
                    ("storage", Json::str("fpreal32")),
                    ("defaults", defaults(default_numbers(default))),
                    ("values", paged(size, "fpreal32", Json::F32s(flat.to_vec()))),
                ]),
            )
        }
    };
    Json::Array(vec![header(name, ty, a.type_info), body])
}

fn arrays(size: usize, storage: &str, lists: impl Iterator<Item = Json>) -> Json {
    Json::pairs(vec![
        ("size", Json::Int(size as i64)),
        ("storage", Json::str(storage)),
        (
            "values",
            Json::pairs(vec![
                ("size", Json::Int(size as i64)),
                ("storage", Json::str(storage)),
                ("arrays", Json::Array(lists.collect())),
            ]),
        ),
    ])
}

fn string_arrays(lists: &[Vec<String>]) -> Json {
    let mut table: Vec<&str> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let indices = lists
        .iter()
        .map(|l| {
            Json::I32s(
                l.iter()
                    .map(|s| {
                        *index.entry(s.as_str()).or_insert_with(|| {
                            table.push(s);
                            table.len() as i32 - 1
                        })
                    })
                    .collect(),
            )
        })
        .collect();
    Json::pairs(vec![
        ("size", Json::Int(1)),
        ("storage", Json::str("int32")),
        (
            "strings",
            Json::Array(table.into_iter().map(Json::str).collect()),
        ),
        (
            "indices",
            Json::pairs(vec![
                ("size", Json::Int(1)),
                ("storage", Json::str("int32")),
                ("arrays", Json::Array(indices)),
            ]),
        ),
    ])
}

/// Consecutive polygons as one `Polygon_run` (sizes run-length encoded);
/// consecutive polylines as one run of open `Poly` primitives; consecutive
/// packed primitives as one run of `PackedGeometry`.
fn primitives(g: &Geometry, cancelled: &dyn Fn() -> bool) -> Result<Json, EncodeError> {
    let mut runs = Vec::new();
    let mut prim = 0;
    let same = |a: PrimKind, b: PrimKind| std::mem::discriminant(&a) == std::mem::discriminant(&b);
    while prim < g.num_prims() {
        let kind = g.prim_kind(prim);
        let end = (prim..g.num_prims())
            .find(|&p| !same(g.prim_kind(p), kind))
            .unwrap_or(g.num_prims());
        let sizes: Vec<i64> = (prim..end)
            .map(|p| g.prim_vertex_range(p).len() as i64)
            .collect();
        let start = g.prim_vertex_range(prim).start as i64;
        runs.push(match kind {
            PrimKind::Polygon => Json::Array(vec![
                Json::pairs(vec![("type", Json::str("Polygon_run"))]),
                Json::pairs(vec![
                    ("startvertex", Json::Int(start)),
                    ("nprimitives", Json::Int(sizes.len() as i64)),
                    ("nvertices_rle", Json::Array(run_lengths(&sizes))),
                ]),
            ]),
            PrimKind::Packed(_) => {
                let per_prim = (prim..end)
                    .map(|p| {
                        if p % CANCEL_EVERY == 0 && cancelled() {
                            return Err(EncodeError::Cancelled);
                        }
                        let inst = g
                            .packed_instance(p)
                            .expect("a packed primitive has an instance");
                        packed::write_prim(
                            &inst.source,
                            g.prim_vertex_range(p).start,
                            &inst.transform,
                        )
                        .map_err(EncodeError::from)
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Json::Array(vec![
                    Json::pairs(vec![
                        ("type", Json::str("run")),
                        ("runtype", Json::str("PackedGeometry")),
                        (
                            "varyingfields",
                            Json::Array(
                                ["parameters", "vertex", "transform", "pivot"]
                                    .map(Json::str)
                                    .to_vec(),
                            ),
                        ),
                        ("uniformfields", Json::Map(Vec::new())),
                    ]),
                    Json::Array(per_prim),
                ])
            }
            _ => {
                let mut at = start;
                let per_prim = sizes
                    .iter()
                    .map(|&n| {
                        let verts = Json::I32s((at..at + n).map(|v| v as i32).collect());
                        at += n;
                        Json::Array(vec![verts])
                    })
                    .collect();
                Json::Array(vec![
                    Json::pairs(vec![
                        ("type", Json::str("run")),
                        ("runtype", Json::str("Poly")),
                        ("varyingfields", Json::Array(vec![Json::str("vertex")])),
                        (
                            "uniformfields",
                            Json::Map(vec![("closed".into(), Json::Bool(false))]),
                        ),
                    ]),
                    Json::Array(per_prim),
                ])
            }
        });
        prim = end;
    }
    Ok(Json::Array(runs))
}

fn run_lengths(sizes: &[i64]) -> Vec<Json> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < sizes.len() {
        let j = sizes[i..]
            .iter()
            .position(|&s| s != sizes[i])
            .map_or(sizes.len(), |k| i + k);
        out.push(Json::Int(sizes[i]));
        out.push(Json::Int((j - i) as i64));
        i = j;
    }
    out
}
