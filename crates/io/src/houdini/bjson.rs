//! Houdini's binary JSON (`.bgeo`): parsed into and written from the `Json` tree.
//!
//! The encoding is the one `UT_JSONDefines.h` documents: one byte per
//! token (`UT_JID`), little-endian numbers, strings defined once as
//! numbered tokens and referred to after, and uniform arrays (a type byte,
//! a length, the packed values) for long numeric runs, kept packed in the
//! tree (`F32s`, `I32s`, ...).

use std::collections::HashMap;

use super::json::Json;
use crate::error::{ParseError, ParseResult};

const MAGIC: u8 = 0x7f;
const BINARY_MAGIC: u32 = 0x624a_534e;
const NULL: u8 = 0x00;
const MAP_BEGIN: u8 = 0x7b;
const MAP_END: u8 = 0x7d;
const ARRAY_BEGIN: u8 = 0x5b;
const ARRAY_END: u8 = 0x5d;
const BOOL: u8 = 0x10;
const INT8: u8 = 0x11;
const INT16: u8 = 0x12;
const INT32: u8 = 0x13;
const INT64: u8 = 0x14;
const REAL16: u8 = 0x18;
const REAL32: u8 = 0x19;
const REAL64: u8 = 0x1a;
const UINT8: u8 = 0x21;
const UINT16: u8 = 0x22;
const STRING: u8 = 0x27;
const FALSE: u8 = 0x30;
const TRUE: u8 = 0x31;
const TOKEN_DEF: u8 = 0x2b;
const TOKEN_REF: u8 = 0x26;
const TOKEN_UNDEF: u8 = 0x2d;
const UNIFORM_ARRAY: u8 = 0x40;
const KEY_SEPARATOR: u8 = 0x3a;
const VALUE_SEPARATOR: u8 = 0x2c;

/// Whether `bytes` start with the binary JSON magic.
pub fn is_binary(bytes: &[u8]) -> bool {
    bytes.first() == Some(&MAGIC)
}

/// Parses a binary JSON document (errors name the byte offset).
pub fn parse_binary(bytes: &[u8]) -> ParseResult<Json> {
    let mut r = BinaryReader {
        bytes,
        at: 0,
        tokens: HashMap::new(),
        depth: 0,
    };
    if r.u8()? != MAGIC {
        return Err(ParseError::byte(
            0,
            "not binary JSON: expected the byte 0x7f",
        ));
    }
    let magic = u32::from_le_bytes(r.take(4)?.try_into().unwrap_or_default());
    if magic == BINARY_MAGIC.swap_bytes() {
        return Err(ParseError::byte(
            1,
            "big-endian binary JSON is not supported (re-save the file on a little-endian machine)",
        ));
    }
    if magic != BINARY_MAGIC {
        return Err(ParseError::byte(
            1,
            "not binary JSON: expected the magic number NSJb",
        ));
    }
    let value = r.value()?;
    Ok(value)
}

struct BinaryReader<'a> {
    bytes: &'a [u8],
    at: usize,
    tokens: HashMap<u64, String>,
    depth: usize,
}

/// Deeper nesting than any geometry file has (Houdini's nest about 10
/// deep; an embedded packed detail adds 3): refuse rather than overflow the
/// stack, here and in the reader's recursion into embedded details.
const MAX_DEPTH: usize = 256;

impl<'a> BinaryReader<'a> {
    fn error(&self, message: impl Into<String>) -> ParseError {
        ParseError::byte(self.at as u64, message)
    }

    fn take(&mut self, n: usize) -> ParseResult<&'a [u8]> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(self.error(format!(
                "unexpected end of file: {n} more bytes expected, {} left",
                self.bytes.len() - self.at
            )));
        };
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }

    fn u8(&mut self) -> ParseResult<u8> {
        Ok(self.take(1)?[0])
    }

    fn array<const N: usize>(&mut self) -> ParseResult<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    /// A length: one byte below 0xf1, else a marker for 2, 4 or 8 bytes.
    fn length(&mut self) -> ParseResult<u64> {
        let b = self.u8()?;
        Ok(match b {
            0..=0xf0 => b as u64,
            0xf2 => u16::from_le_bytes(self.array()?) as u64,
            0xf4 => u32::from_le_bytes(self.array()?) as u64,
            0xf8 => u64::from_le_bytes(self.array()?),
            _ => return Err(self.error(format!("invalid length marker 0x{b:02x}"))),
        })
    }

    fn string_bytes(&mut self) -> ParseResult<String> {
        let n = self.length()?;
        let n = usize::try_from(n).map_err(|_| self.error("string length too large"))?;
        let s = self.take(n)?;
        String::from_utf8(s.to_vec()).map_err(|_| self.error("string is not UTF-8"))
    }

    /// The next token that is a value (token definitions and separators skipped).
    fn value(&mut self) -> ParseResult<Json> {
        loop {
            let start = self.at;
            let id = self.u8()?;
            if let Some(v) = self.scalar(id)? {
                return Ok(v);
            }
            match id {
                TOKEN_DEF => {
                    let key = self.length()?;
                    let s = self.string_bytes()?;
                    self.tokens.insert(key, s);
                }
                TOKEN_UNDEF => {
                    let key = self.length()?;
                    self.tokens.remove(&key);
                }
                KEY_SEPARATOR | VALUE_SEPARATOR => {}
                ARRAY_BEGIN => return self.nested(start, |r| r.array_items()),
                MAP_BEGIN => return self.nested(start, |r| r.map_items()),
                UNIFORM_ARRAY => return self.uniform_array(),
                _ => {
                    self.at = start;
                    return Err(self.error(format!("unexpected token 0x{id:02x}")));
                }
            }
        }
    }

    /// Reads an array or map opened at byte `start`, refusing to nest past
    /// `MAX_DEPTH` (the error names the opening byte).
    fn nested(
        &mut self,
        start: usize,
        f: impl FnOnce(&mut Self) -> ParseResult<Json>,
    ) -> ParseResult<Json> {
        if self.depth >= MAX_DEPTH {
            return Err(ParseError::byte(
                start as u64,
                format!("nesting deeper than {MAX_DEPTH} levels"),
            ));
        }
        self.depth += 1;
        let v = f(self);
        self.depth -= 1;
        v
    }

    fn scalar(&mut self, id: u8) -> ParseResult<Option<Json>> {
        Ok(Some(match id {
            NULL => Json::Null,
            FALSE => Json::Bool(false),
            TRUE => Json::Bool(true),
            BOOL => Json::Bool(self.u8()? != 0),
            INT8 => Json::Int(self.u8()? as i8 as i64),
            UINT8 => Json::Int(self.u8()? as i64),
            INT16 => Json::Int(i16::from_le_bytes(self.array()?) as i64),
            UINT16 => Json::Int(u16::from_le_bytes(self.array()?) as i64),
            INT32 => Json::Int(i32::from_le_bytes(self.array()?) as i64),
            INT64 => Json::Int(i64::from_le_bytes(self.array()?)),
            REAL16 => Json::Real(f16_to_f32(u16::from_le_bytes(self.array()?)) as f64),
            REAL32 => Json::Real(f32::from_le_bytes(self.array()?) as f64),
            REAL64 => Json::Real(f64::from_le_bytes(self.array()?)),
            STRING => Json::Str(self.string_bytes()?),
            TOKEN_REF => {
                let key = self.length()?;
                match self.tokens.get(&key) {
                    Some(s) => Json::Str(s.clone()),
                    None => {
                        return Err(self.error(format!("reference to undefined string token {key}")))
                    }
                }
            }
            _ => return Ok(None),
        }))
    }

    /// Whether the next token (after definitions and separators) is `end`; consumes it if so.
    fn at_end(&mut self, end: u8) -> ParseResult<bool> {
        loop {
            let Some(&b) = self.bytes.get(self.at) else {
                return Err(self.error("unexpected end of file inside an array or map"));
            };
            match b {
                KEY_SEPARATOR | VALUE_SEPARATOR => self.at += 1,
                TOKEN_DEF => {
                    self.at += 1;
                    let key = self.length()?;
                    let s = self.string_bytes()?;
                    self.tokens.insert(key, s);
                }
                _ if b == end => {
                    self.at += 1;
                    return Ok(true);
                }
                _ => return Ok(false),
            }
        }
    }

    fn array_items(&mut self) -> ParseResult<Json> {
        let mut items = Vec::new();
        while !self.at_end(ARRAY_END)? {
            items.push(self.value()?);
        }
        Ok(Json::Array(items))
    }

    fn map_items(&mut self) -> ParseResult<Json> {
        let mut entries = Vec::new();
        while !self.at_end(MAP_END)? {
            let key = match self.value()? {
                Json::Str(s) => s,
                _ => return Err(self.error("a map key must be a string")),
            };
            entries.push((key, self.value()?));
        }
        Ok(Json::Map(entries))
    }

    fn uniform_array(&mut self) -> ParseResult<Json> {
        let ty = self.u8()?;
        let n = self.length()?;
        let width: u64 = match ty {
            INT8 | UINT8 => 1,
            INT16 | UINT16 | REAL16 => 2,
            INT32 | REAL32 => 4,
            INT64 | REAL64 => 8,
            BOOL | FALSE | TRUE => 0,
            _ => return Err(self.error(format!("unsupported uniform array type 0x{ty:02x}"))),
        };
        let bytes = if width == 0 {
            n.div_ceil(32) * 4
        } else {
            n.saturating_mul(width)
        };
        if bytes > (self.bytes.len() - self.at) as u64 {
            return Err(self.error(format!(
                "uniform array of {n} values runs past the end of the file"
            )));
        }
        let data = self.take(bytes as usize)?;
        Ok(match ty {
            INT8 => Json::I32s(data.iter().map(|&b| b as i8 as i32).collect()),
            UINT8 => Json::I32s(data.iter().map(|&b| b as i32).collect()),
            INT16 => Json::I32s(le_chunks(data, |c: [u8; 2]| i16::from_le_bytes(c) as i32)),
            UINT16 => Json::I32s(le_chunks(data, |c: [u8; 2]| u16::from_le_bytes(c) as i32)),
            INT32 => Json::I32s(le_chunks(data, i32::from_le_bytes)),
            INT64 => Json::I64s(le_chunks(data, i64::from_le_bytes)),
            REAL16 => Json::F32s(le_chunks(data, |c: [u8; 2]| {
                f16_to_f32(u16::from_le_bytes(c))
            })),
            REAL32 => Json::F32s(le_chunks(data, f32::from_le_bytes)),
            REAL64 => Json::F64s(le_chunks(data, f64::from_le_bytes)),
            _ => {
                let words: Vec<u32> = le_chunks(data, u32::from_le_bytes);
                Json::Bools(
                    (0..n as usize)
                        .map(|i| words[i / 32] >> (i % 32) & 1 == 1)
                        .collect(),
                )
            }
        })
    }
}

fn le_chunks<const N: usize, T>(data: &[u8], f: impl Fn([u8; N]) -> T) -> Vec<T> {
    data.chunks_exact(N)
        .map(|c| {
            let mut a = [0u8; N];
            a.copy_from_slice(c);
            f(a)
        })
        .collect()
}

/// IEEE half to single precision (Houdini's `fpreal16`).
fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0f32 } else { 1.0 };
    let exp = (h >> 10) & 0x1f;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        0x1f if frac == 0.0 => sign * f32::INFINITY,
        0x1f => f32::NAN,
        _ => sign * (1.0 + frac / 1024.0) * 2f32.powi(exp as i32 - 15),
    }
}

/// Writes a tree as binary JSON. Strings become numbered tokens, each
/// defined at its first use; packed arrays become uniform arrays.
pub fn write_binary(json: &Json, out: &mut Vec<u8>) {
    out.push(MAGIC);
    out.extend_from_slice(&BINARY_MAGIC.to_le_bytes());
    let mut w = BinaryWriter {
        out,
        tokens: HashMap::new(),
    };
    w.value(json);
}

struct BinaryWriter<'a> {
    out: &'a mut Vec<u8>,
    tokens: HashMap<String, u64>,
}

impl BinaryWriter<'_> {
    fn length(&mut self, n: u64) {
        if n < 0xf1 {
            self.out.push(n as u8);
        } else if n <= u16::MAX as u64 {
            self.out.push(0xf2);
            self.out.extend_from_slice(&(n as u16).to_le_bytes());
        } else if n <= u32::MAX as u64 {
            self.out.push(0xf4);
            self.out.extend_from_slice(&(n as u32).to_le_bytes());
        } else {
            self.out.push(0xf8);
            self.out.extend_from_slice(&n.to_le_bytes());
        }
    }

    fn string(&mut self, s: &str) {
        let next = self.tokens.len() as u64;
        let id = *self.tokens.entry(s.to_owned()).or_insert(next);
        if id == next {
            self.out.push(TOKEN_DEF);
            self.length(id);
            self.length(s.len() as u64);
            self.out.extend_from_slice(s.as_bytes());
        }
        self.out.push(TOKEN_REF);
        self.length(id);
    }

    fn uniform<T: Copy>(&mut self, ty: u8, v: &[T], bytes: impl Fn(T) -> Vec<u8>) {
        self.out.push(UNIFORM_ARRAY);
        self.out.push(ty);
        self.length(v.len() as u64);
        for &x in v {
            self.out.extend_from_slice(&bytes(x));
        }
    }

    fn value(&mut self, json: &Json) {
        match json {
            Json::Null => self.out.push(NULL),
            Json::Bool(b) => self.out.push(if *b { TRUE } else { FALSE }),
            Json::Int(i) => self.int(*i),
            Json::Real(r) => {
                self.out.push(REAL64);
                self.out.extend_from_slice(&r.to_le_bytes());
            }
            Json::Str(s) => self.string(s),
            Json::Array(items) => {
                self.out.push(ARRAY_BEGIN);
                for item in items {
                    self.value(item);
                }
                self.out.push(ARRAY_END);
            }
            Json::Map(entries) => {
                self.out.push(MAP_BEGIN);
                for (k, v) in entries {
                    self.string(k);
                    self.value(v);
                }
                self.out.push(MAP_END);
            }
            Json::F32s(v) => self.uniform(REAL32, v, |x| x.to_le_bytes().to_vec()),
            Json::F64s(v) => self.uniform(REAL64, v, |x| x.to_le_bytes().to_vec()),
            Json::I32s(v) => self.uniform(INT32, v, |x| x.to_le_bytes().to_vec()),
            Json::I64s(v) => self.uniform(INT64, v, |x| x.to_le_bytes().to_vec()),
            Json::Bools(v) => {
                self.out.push(UNIFORM_ARRAY);
                self.out.push(BOOL);
                self.length(v.len() as u64);
                for word in v.chunks(32) {
                    let bits = word
                        .iter()
                        .enumerate()
                        .fold(0u32, |acc, (i, &b)| acc | (b as u32) << i);
                    self.out.extend_from_slice(&bits.to_le_bytes());
                }
            }
        }
    }

    fn int(&mut self, i: i64) {
        if let Ok(x) = i8::try_from(i) {
            self.out.push(INT8);
            self.out.push(x as u8);
        } else if let Ok(x) = i16::try_from(i) {
            self.out.push(INT16);
            self.out.extend_from_slice(&x.to_le_bytes());
        } else if let Ok(x) = i32::try_from(i) {
            self.out.push(INT32);
            self.out.extend_from_slice(&x.to_le_bytes());
        } else {
            self.out.push(INT64);
            self.out.extend_from_slice(&i.to_le_bytes());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::houdini::json::{parse_text, write_text};

    fn sample() -> Json {
        Json::pairs(vec![
            ("fileversion", Json::str("20.5.0")),
            ("count", Json::Int(70_000)),
            ("neg", Json::Int(-3)),
            ("real", Json::Real(0.1)),
            ("flags", Json::Bools((0..70).map(|i| i % 3 == 0).collect())),
            ("p", Json::F32s(vec![0.5, -1.25, 3.0e-8])),
            ("i", Json::I32s(vec![1, -2, 300_000])),
            ("map", Json::Map(vec![("type".into(), Json::str("string"))])),
            ("again", Json::str("fileversion")),
        ])
    }

    #[test]
    fn binary_round_trip_keeps_every_value() {
        let mut bytes = Vec::new();
        write_binary(&sample(), &mut bytes);
        assert!(is_binary(&bytes));
        assert_eq!(parse_binary(&bytes).unwrap(), sample());
    }

    #[test]
    fn text_round_trip_keeps_numbers_exact() {
        let mut bytes = Vec::new();
        write_text(&sample(), &mut bytes);
        let back = parse_text(&bytes).unwrap();
        assert_eq!(back.get("count"), Some(&Json::Int(70_000)));
        assert_eq!(back.get("real"), Some(&Json::Real(0.1)));
        let p: Vec<f32> = back
            .get("p")
            .unwrap()
            .numbers()
            .unwrap()
            .iter()
            .map(|&x| x as f32)
            .collect();
        assert_eq!(p, vec![0.5, -1.25, 3.0e-8]);
        assert_eq!(back.get("flags").unwrap().flags().unwrap().len(), 70);
    }

    #[test]
    fn truncated_binary_names_the_byte() {
        let mut bytes = Vec::new();
        write_binary(&sample(), &mut bytes);
        let e = parse_binary(&bytes[..bytes.len() - 5]).unwrap_err();
        assert!(matches!(e.pos, Some(crate::Position::Byte(_))), "{e:?}");
        assert!(e.message.contains("end of file"), "{}", e.message);
    }

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
    }
}
