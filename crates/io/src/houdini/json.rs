//! Houdini's JSON documents as a tree, read from and written to text (binary JSON is `bjson.rs`).
//!
//! Numeric arrays are kept packed in the tree (`F32s`, `I32s`, ...) so that
//! a column of eight million positions is one allocation, not eight million
//! nodes.

use crate::error::{ParseError, ParseResult};

/// A JSON value; arrays of one numeric type are held packed.
#[derive(Clone, Debug, PartialEq)]
pub enum Json {
    Null,
    Bool(bool),
    Int(i64),
    Real(f64),
    Str(String),
    Array(Vec<Json>),
    /// Keys in file order (Houdini's maps are small: `info`, `options`).
    Map(Vec<(String, Json)>),
    F32s(Vec<f32>),
    F64s(Vec<f64>),
    I32s(Vec<i32>),
    I64s(Vec<i64>),
    Bools(Vec<bool>),
}

impl Json {
    /// The value of `key` in a Houdini key-value list (`["a", 1, "b", 2]`) or a map.
    pub fn get(&self, key: &str) -> Option<&Json> {
        match self {
            Json::Array(items) => items
                .chunks_exact(2)
                .find(|kv| kv[0].as_str() == Some(key))
                .map(|kv| &kv[1]),
            Json::Map(entries) => entries.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The value of the first of `keys` present (Houdini spells some keys short in binary files).
    pub fn get_any(&self, keys: &[&str]) -> Option<&Json> {
        keys.iter().find_map(|k| self.get(k))
    }

    pub fn as_str(&self) -> Option<&str> {
        match self {
            Json::Str(s) => Some(s),
            _ => None,
        }
    }

    pub fn as_i64(&self) -> Option<i64> {
        match *self {
            Json::Int(i) => Some(i),
            Json::Real(r) if r.fract() == 0.0 && r.abs() < 9.0e15 => Some(r as i64),
            _ => None,
        }
    }

    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Json::Int(i) => Some(i as f64),
            Json::Real(r) => Some(r),
            Json::Null => Some(f64::NAN),
            _ => None,
        }
    }

    pub fn as_bool(&self) -> Option<bool> {
        match *self {
            Json::Bool(b) => Some(b),
            Json::Int(i) => Some(i != 0),
            _ => None,
        }
    }

    /// The items of an array (packed arrays are not item lists: see `numbers`).
    pub fn items(&self) -> Option<&[Json]> {
        match self {
            Json::Array(items) => Some(items),
            _ => None,
        }
    }

    /// The length of any array, packed or not.
    pub fn len(&self) -> Option<usize> {
        Some(match self {
            Json::Array(v) => v.len(),
            Json::F32s(v) => v.len(),
            Json::F64s(v) => v.len(),
            Json::I32s(v) => v.len(),
            Json::I64s(v) => v.len(),
            Json::Bools(v) => v.len(),
            _ => return None,
        })
    }

    /// Every number of an array as `f64`, whatever its encoding.
    pub fn numbers(&self) -> Option<Vec<f64>> {
        Some(match self {
            Json::F32s(v) => v.iter().map(|&x| x as f64).collect(),
            Json::F64s(v) => v.clone(),
            Json::I32s(v) => v.iter().map(|&x| x as f64).collect(),
            Json::I64s(v) => v.iter().map(|&x| x as f64).collect(),
            Json::Bools(v) => v.iter().map(|&x| x as u8 as f64).collect(),
            Json::Array(items) => items.iter().map(Json::as_f64).collect::<Option<_>>()?,
            _ => return None,
        })
    }

    /// Every number of an array as `i64`; `None` when one is not an integer.
    pub fn integers(&self) -> Option<Vec<i64>> {
        Some(match self {
            Json::I32s(v) => v.iter().map(|&x| x as i64).collect(),
            Json::I64s(v) => v.clone(),
            Json::Bools(v) => v.iter().map(|&x| x as i64).collect(),
            Json::F32s(_) | Json::F64s(_) => self
                .numbers()?
                .into_iter()
                .map(|x| Json::Real(x).as_i64())
                .collect::<Option<_>>()?,
            Json::Array(items) => items.iter().map(Json::as_i64).collect::<Option<_>>()?,
            _ => return None,
        })
    }

    /// Every value of an array as a flag (`true`/`false` or 0/1).
    pub fn flags(&self) -> Option<Vec<bool>> {
        match self {
            Json::Bools(v) => Some(v.clone()),
            Json::Array(items) => items.iter().map(Json::as_bool).collect(),
            _ => Some(self.integers()?.into_iter().map(|x| x != 0).collect()),
        }
    }

    /// A key-value list of Houdini's schema: `["k1", v1, "k2", v2]`.
    pub fn pairs(entries: Vec<(&str, Json)>) -> Json {
        let mut items = Vec::with_capacity(entries.len() * 2);
        for (k, v) in entries {
            items.push(Json::Str(k.to_owned()));
            items.push(v);
        }
        Json::Array(items)
    }

    pub fn str(s: &str) -> Json {
        Json::Str(s.to_owned())
    }
}

// ----- text -----

/// Parses a text JSON document (errors name the line and column).
pub fn parse_text(bytes: &[u8]) -> ParseResult<Json> {
    let value: serde_json::Value = serde_json::from_slice(bytes).map_err(|e| {
        ParseError::line(
            e.line() as u64,
            format!("column {}: malformed JSON: {e}", e.column()),
        )
    })?;
    Ok(from_serde(value))
}

fn from_serde(v: serde_json::Value) -> Json {
    use serde_json::Value as V;
    match v {
        V::Null => Json::Null,
        V::Bool(b) => Json::Bool(b),
        V::Number(n) => match n.as_i64() {
            Some(i) => Json::Int(i),
            None => Json::Real(n.as_f64().unwrap_or(f64::NAN)),
        },
        V::String(s) => Json::Str(s),
        V::Array(items) => pack_numbers(&items)
            .unwrap_or_else(|| Json::Array(items.into_iter().map(from_serde).collect())),
        V::Object(map) => Json::Map(map.into_iter().map(|(k, v)| (k, from_serde(v))).collect()),
    }
}

/// An array of numbers (all integers, or any reals) or of flags, packed;
/// arrays of two or fewer items stay plain so key-value lists stay lists.
fn pack_numbers(items: &[serde_json::Value]) -> Option<Json> {
    if items.len() < 3 {
        return None;
    }
    if items.iter().all(|v| v.is_boolean()) {
        return Some(Json::Bools(
            items.iter().map(|v| v.as_bool() == Some(true)).collect(),
        ));
    }
    if items.iter().all(|v| v.is_i64()) {
        return Some(Json::I64s(
            items.iter().filter_map(|v| v.as_i64()).collect(),
        ));
    }
    if items.iter().all(|v| v.is_number()) {
        return Some(Json::F64s(
            items
                .iter()
                .map(|v| v.as_f64().unwrap_or(f64::NAN))
                .collect(),
        ));
    }
    None
}

/// Writes a tree as text JSON: one top-level key-value pair per line,
/// numbers in their shortest exact form, non-finite reals as `null`.
pub fn write_text(json: &Json, out: &mut Vec<u8>) {
    match json {
        Json::Array(items) => {
            out.push(b'[');
            for (i, item) in items.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                write_text(item, out);
            }
            out.push(b']');
        }
        Json::Map(entries) => {
            out.push(b'{');
            for (i, (k, v)) in entries.iter().enumerate() {
                if i > 0 {
                    out.push(b',');
                }
                write_text_string(k, out);
                out.push(b':');
                write_text(v, out);
            }
            out.push(b'}');
        }
        Json::Null => out.extend_from_slice(b"null"),
        Json::Bool(b) => out.extend_from_slice(if *b { b"true" } else { b"false" }),
        Json::Int(i) => out.extend_from_slice(i.to_string().as_bytes()),
        Json::Real(r) => write_real(*r, out),
        Json::Str(s) => write_text_string(s, out),
        Json::F32s(v) => write_text_list(v, out, |x, o| write_real_f32(*x, o)),
        Json::F64s(v) => write_text_list(v, out, |x, o| write_real(*x, o)),
        Json::I32s(v) => {
            write_text_list(v, out, |x, o| o.extend_from_slice(x.to_string().as_bytes()))
        }
        Json::I64s(v) => {
            write_text_list(v, out, |x, o| o.extend_from_slice(x.to_string().as_bytes()))
        }
        Json::Bools(v) => write_text_list(v, out, |x, o| {
            o.extend_from_slice(if *x { b"true" } else { b"false" })
        }),
    }
}

fn write_text_list<T>(v: &[T], out: &mut Vec<u8>, each: impl Fn(&T, &mut Vec<u8>)) {
    out.push(b'[');
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        each(x, out);
    }
    out.push(b']');
}

fn write_real(r: f64, out: &mut Vec<u8>) {
    if r.is_finite() {
        out.extend_from_slice(format!("{r:?}").as_bytes());
    } else {
        out.extend_from_slice(b"null");
    }
}

fn write_real_f32(r: f32, out: &mut Vec<u8>) {
    if r.is_finite() {
        out.extend_from_slice(format!("{r:?}").as_bytes());
    } else {
        out.extend_from_slice(b"null");
    }
}

fn write_text_string(s: &str, out: &mut Vec<u8>) {
    let quoted = serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_owned());
    out.extend_from_slice(quoted.as_bytes());
}
