//! Houdini attribute blocks decoded into geode columns: numeric tuples (listed, per component or paged), strings, per-element arrays.

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

use geode_geo::attrib::{AttribData, AttribValue, Attribute, StringColumn, TypeInfo};

use super::bad;
use super::json::Json;
use super::{type_info_from_name, ARRAY_TYPE, STRING_ARRAY_TYPE};
use crate::error::{ParseError, ParseResult};

/// Decodes a values block into `n` tuples of `size`, flat: `tuples`,
/// `arrays` (one list per component) or paged `rawpagedata`.
/// Values of `n` tuples of `size`; refused, before anything is allocated,
/// when decoding them would need more than `budget` bytes.
pub(super) fn decode_values(
    block: &Json,
    n: usize,
    size: usize,
    budget: u64,
) -> ParseResult<Vec<f64>> {
    let bytes = (n as u64).saturating_mul(size as u64).saturating_mul(8);
    if bytes > budget {
        return Err(ParseError::over_budget(format!(
            "{n} elements of {size} values would need {}, more than the memory budget of {} (GEODE_MEMORY_MB)",
            geode_geo::human_bytes(bytes as f64),
            geode_geo::human_bytes(budget as f64)
        )));
    }
    let flat = if let Some(tuples) = block.get("tuples") {
        let mut flat = Vec::new();
        match tuples {
            Json::Array(items) => {
                // Reserved for the tuples the file holds, not the count it
                // claims: a lying count must not cost memory.
                flat.reserve(items.len().min(n).saturating_mul(size));
                for t in items {
                    let t = t
                        .numbers()
                        .ok_or_else(|| ParseError::whole("a tuple is not numbers"))?;
                    if t.len() != size {
                        return Err(ParseError::whole(format!(
                            "a tuple of {} values, expected {size}",
                            t.len()
                        )));
                    }
                    flat.extend(t);
                }
            }
            packed => flat = packed.numbers().unwrap_or_default(),
        }
        flat
    } else if let Some(arrays) = block.get("arrays") {
        let components: Vec<Vec<f64>> = match arrays {
            Json::Array(items) => items.iter().map(Json::numbers).collect::<Option<_>>(),
            _ => None,
        }
        .ok_or_else(|| ParseError::whole("`arrays` is not a list of number lists"))?;
        if components.len() != size || components.iter().any(|c| c.len() != n) {
            return Err(ParseError::whole(format!(
                "`arrays` must hold {size} lists of {n} values"
            )));
        }
        (0..n * size)
            .map(|i| components[i % size][i / size])
            .collect()
    } else if let Some(raw) = block.get("rawpagedata") {
        paged(block, raw, n, size)?
    } else {
        return Err(ParseError::whole(
            "values have no `tuples`, `arrays` or `rawpagedata`",
        ));
    };
    if flat.len() != n * size {
        return Err(ParseError::whole(format!(
            "{} values for {n} elements of size {size}",
            flat.len()
        )));
    }
    Ok(flat)
}

/// Paged data: per page of `pagesize` elements, each packed sub-vector in
/// turn, one tuple of it when its constant-page flag is set.
fn paged(block: &Json, raw: &Json, n: usize, size: usize) -> ParseResult<Vec<f64>> {
    let raw = raw
        .numbers()
        .ok_or_else(|| ParseError::whole("`rawpagedata` is not numbers"))?;
    let page = block.get("pagesize").and_then(Json::as_i64).unwrap_or(0);
    if page <= 0 {
        return Err(ParseError::whole(
            "`rawpagedata` needs a positive `pagesize`",
        ));
    }
    let page = page as usize;
    let packing: Vec<usize> = match block.get("packing") {
        Some(p) => p
            .integers()
            .ok_or_else(|| ParseError::whole("`packing` is not integers"))?
            .into_iter()
            .map(|x| x.max(0) as usize)
            .collect(),
        None => vec![size],
    };
    if packing.iter().sum::<usize>() != size || packing.contains(&0) {
        return Err(ParseError::whole(format!(
            "`packing` {packing:?} does not add up to size {size}"
        )));
    }
    let flags: Vec<Vec<bool>> = match block.get("constantpageflags") {
        Some(Json::Array(per_pack)) => per_pack
            .iter()
            .map(|f| f.flags().unwrap_or_default())
            .collect(),
        _ => Vec::new(),
    };
    // One sub-vector and no constant page: the pages are the tuples in order.
    if packing.len() == 1 && flags.iter().all(|f| !f.contains(&true)) {
        return Ok(raw);
    }
    let mut flat = vec![0.0; n * size];
    let mut at = 0usize;
    let mut take = |count: usize| -> ParseResult<&[f64]> {
        let s = raw
            .get(at..at + count)
            .ok_or_else(|| ParseError::whole("`rawpagedata` ends early"))?;
        at += count;
        Ok(s)
    };
    for (p, first) in (0..n).step_by(page).enumerate() {
        let len = page.min(n - first);
        let mut component = 0;
        for (k, &width) in packing.iter().enumerate() {
            let constant = flags
                .get(k)
                .and_then(|f| f.get(p))
                .copied()
                .unwrap_or(false);
            if constant {
                let tuple = take(width)?;
                for e in first..first + len {
                    flat[e * size + component..][..width].copy_from_slice(tuple);
                }
            } else {
                let data = take(width * len)?;
                for (i, tuple) in data.chunks_exact(width).enumerate() {
                    flat[(first + i) * size + component..][..width].copy_from_slice(tuple);
                }
            }
            component += width;
        }
    }
    if at != raw.len() {
        return Err(ParseError::whole(format!(
            "`rawpagedata` has {} values, {at} expected",
            raw.len()
        )));
    }
    Ok(flat)
}

/// One attribute entry; `None` for kinds geode does not hold (dictionaries,
/// private attributes, tuple sizes without a geode type).
pub(super) fn attribute(
    entry: &Json,
    class_key: &str,
    n: usize,
    budget: u64,
) -> ParseResult<Option<(String, Attribute)>> {
    let Some([header, body]) = entry.items() else {
        return Err(bad(class_key, "expected [header, body] per attribute"));
    };
    let name = header
        .get("name")
        .and_then(Json::as_str)
        .ok_or_else(|| bad(class_key, "an attribute has no name"))?
        .to_owned();
    if header.get("scope").and_then(Json::as_str) == Some("private") {
        return Ok(None);
    }
    let what = format!("{class_key} `{name}`");
    let info = header
        .get("options")
        .and_then(|o| o.get("type"))
        .and_then(|t| t.get("value"))
        .and_then(Json::as_str)
        .map(type_info_from_name)
        .unwrap_or(TypeInfo::None);
    let attrib = match header.get("type").and_then(Json::as_str).unwrap_or("") {
        "numeric" => numeric(body, n, info, budget).map_err(|e| e.within(&what))?,
        // String tuples (Houdini's `varmap`) have no geode type.
        "string" if body.get("size").and_then(Json::as_i64).unwrap_or(1) != 1 => None,
        "string" => Some(strings(body, n, budget).map_err(|e| e.within(&what))?),
        ARRAY_TYPE => Some(arrays(body, n).map_err(|e| bad(&what, e.message))?),
        STRING_ARRAY_TYPE => Some(string_arrays(body, n).map_err(|e| bad(&what, e.message))?),
        _ => None,
    };
    Ok(attrib.map(|a| (name, a)))
}

fn numeric(body: &Json, n: usize, info: TypeInfo, budget: u64) -> ParseResult<Option<Attribute>> {
    let values = body
        .get("values")
        .ok_or_else(|| ParseError::whole("missing `values`"))?;
    let size = values
        .get("size")
        .or_else(|| body.get("size"))
        .and_then(Json::as_i64)
        .unwrap_or(1) as usize;
    let storage = values
        .get("storage")
        .or_else(|| body.get("storage"))
        .and_then(Json::as_str)
        .unwrap_or("fpreal32");
    if !matches!(size, 1..=4 | 9 | 16) {
        return Ok(None);
    }
    let flat = decode_values(values, n, size, budget)?;
    let default: Vec<f64> = body
        .get("defaults")
        .and_then(|d| d.get("values"))
        .and_then(Json::numbers)
        .unwrap_or_default();
    let default_at = |i: usize| default.get(i).or(default.first()).copied().unwrap_or(0.0) as f32;
    let f = |c: &[f64]| c.iter().map(|&x| x as f32).collect::<Vec<f32>>();
    let (data, dflt) = match size {
        1 if storage.starts_with("int") || storage.starts_with("uint") => {
            let ints = flat.iter().map(|&x| x as i32).collect();
            (
                AttribData::Int(ints),
                AttribValue::Int(default_at(0) as i32),
            )
        }
        1 => (
            AttribData::Float(f(&flat)),
            AttribValue::Float(default_at(0)),
        ),
        2 => (
            AttribData::Vec2(
                flat.chunks_exact(2)
                    .map(|c| Vec2::from_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Vec2(Vec2::new(default_at(0), default_at(1))),
        ),
        3 => (
            AttribData::Vec3(
                flat.chunks_exact(3)
                    .map(|c| Vec3::from_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Vec3(Vec3::new(default_at(0), default_at(1), default_at(2))),
        ),
        4 if info == TypeInfo::Quaternion => (
            AttribData::Quat(
                flat.chunks_exact(4)
                    .map(|c| Quat::from_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Quat(Quat::from_xyzw(
                default_at(0),
                default_at(1),
                default_at(2),
                default_at(3),
            )),
        ),
        4 => (
            AttribData::Vec4(
                flat.chunks_exact(4)
                    .map(|c| Vec4::from_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Vec4(Vec4::new(
                default_at(0),
                default_at(1),
                default_at(2),
                default_at(3),
            )),
        ),
        9 => (
            AttribData::Mat3(
                flat.chunks_exact(9)
                    .map(|c| Mat3::from_cols_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Mat3(matrix_default(&default, 3, Mat3::from_cols_slice)),
        ),
        _ => (
            AttribData::Mat4(
                flat.chunks_exact(16)
                    .map(|c| Mat4::from_cols_slice(&f(c)))
                    .collect(),
            ),
            AttribValue::Mat4(matrix_default(&default, 4, Mat4::from_cols_slice)),
        ),
    };
    let info = match (info, size) {
        (TypeInfo::Transform, 9 | 16) => TypeInfo::Transform,
        (TypeInfo::Transform, _) => TypeInfo::None,
        (info, _) => info,
    };
    Ok(Some(
        Attribute::from_data(data, info)
            .with_default(dflt)
            .map_err(|_| ParseError::whole("default of another type"))?,
    ))
}

/// A matrix default: all its entries given, or one value (Houdini writes a
/// single 0); the identity otherwise.
fn matrix_default<M: Default>(values: &[f64], dim: usize, from: impl Fn(&[f32]) -> M) -> M {
    let v: Vec<f32> = values.iter().map(|&x| x as f32).collect();
    if v.len() == dim * dim {
        from(&v)
    } else {
        M::default()
    }
}

fn string_table(body: &Json) -> ParseResult<Vec<String>> {
    match body.get("strings") {
        Some(Json::Array(items)) => items
            .iter()
            .map(|s| s.as_str().map(str::to_owned))
            .collect::<Option<_>>()
            .ok_or_else(|| ParseError::whole("`strings` holds a non-string")),
        None => Ok(Vec::new()),
        Some(other) if other.len() == Some(0) => Ok(Vec::new()),
        _ => Err(ParseError::whole("`strings` is not a list of strings")),
    }
}

fn strings(body: &Json, n: usize, budget: u64) -> ParseResult<Attribute> {
    let table = string_table(body)?;
    let block = body
        .get("indices")
        .ok_or_else(|| ParseError::whole("missing `indices`"))?;
    let idx = decode_values(block, n, 1, budget)?;
    let mut column = StringColumn {
        table: table.clone(),
        indices: Vec::with_capacity(n),
    };
    // Houdini's -1 is the empty string.
    let empty = if idx.iter().any(|&i| i < 0.0) {
        Some(column.intern(""))
    } else {
        None
    };
    for i in idx {
        let i = if i < 0.0 {
            empty.unwrap_or(0)
        } else if (i as usize) < table.len() {
            i as u32
        } else {
            return Err(ParseError::whole(format!(
                "string index {i} out of range ({} strings)",
                table.len()
            )));
        };
        column.indices.push(i);
    }
    Ok(Attribute::from_data(
        AttribData::String(column),
        TypeInfo::None,
    ))
}

/// Per-element number lists: `size` numbers per entry (3 for vector arrays).
fn arrays(body: &Json, n: usize) -> ParseResult<Attribute> {
    let size = body.get("size").and_then(Json::as_i64).unwrap_or(1);
    let storage = body
        .get("storage")
        .and_then(Json::as_str)
        .unwrap_or("fpreal32");
    let lists = element_lists(body.get("values"), n)?;
    let data = match (size, storage.starts_with("int")) {
        (1, true) => AttribData::IntArray(
            lists
                .iter()
                .map(|l| l.iter().map(|&x| x as i32).collect())
                .collect(),
        ),
        (1, false) => AttribData::FloatArray(
            lists
                .iter()
                .map(|l| l.iter().map(|&x| x as f32).collect())
                .collect(),
        ),
        (3, _) => AttribData::Vec3Array(
            lists
                .iter()
                .map(|l| {
                    l.chunks_exact(3)
                        .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
                        .collect()
                })
                .collect(),
        ),
        _ => {
            return Err(ParseError::whole(format!(
                "array entries of size {size} are not supported (1 or 3)"
            )))
        }
    };
    Ok(Attribute::from_data(data, TypeInfo::None))
}

fn element_lists(block: Option<&Json>, n: usize) -> ParseResult<Vec<Vec<f64>>> {
    let lists = block
        .and_then(|b| b.get("arrays"))
        .and_then(Json::items)
        .ok_or_else(|| ParseError::whole("missing `values` `arrays` (one list per element)"))?;
    if lists.len() != n {
        return Err(ParseError::whole(format!(
            "{} lists for {n} elements",
            lists.len()
        )));
    }
    lists
        .iter()
        .map(|l| {
            l.numbers()
                .ok_or_else(|| ParseError::whole("an element's list is not numbers"))
        })
        .collect()
}

fn string_arrays(body: &Json, n: usize) -> ParseResult<Attribute> {
    let table = string_table(body)?;
    let lists = element_lists(body.get("indices"), n)?;
    let data = lists
        .iter()
        .map(|l| {
            l.iter()
                .map(|&i| {
                    table.get(i as usize).cloned().ok_or_else(|| {
                        ParseError::whole(format!(
                            "string index {i} out of range ({} strings)",
                            table.len()
                        ))
                    })
                })
                .collect()
        })
        .collect::<ParseResult<_>>()?;
    Ok(Attribute::from_data(
        AttribData::StringArray(data),
        TypeInfo::None,
    ))
}
