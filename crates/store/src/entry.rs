//! One disk cache entry's bytes: a header (kind, key, identity, size, warnings), the value in the geometry codec, and a checksum over all of it.
//!
//! The header names the key the entry was written under (a cook key, or a
//! packed source's content hash) and what kind of value it holds, so an
//! entry found under another name (copied, renamed, a bug) is refused
//! before its value is decoded rather than served as the wrong result.
//! Geometry, bundles and fields are stored (fields in geode-frep's codec,
//! capsule sets with their built hierarchies); a packed instance's source
//! is its own entry, named by its content hash and shared by every entry
//! placing it. Geometry carrying a payload (a typed Rust value) has no byte
//! form and is not stored.

use std::collections::BTreeMap;
use std::sync::Arc;

use geode_geo::codec::{self, DecodeError};
use geode_geo::Geometry;
use geode_graph::Cached;
use geode_op::{Bundle, Value};
use xxhash_rust::xxh3::xxh3_128;

const MAGIC: &[u8; 8] = b"GEODEVAL";
/// The entry layout's version (the geometry codec carries its own); 2 added
/// the key, so entries of version 1 are misses.
const ENTRY_VERSION: u32 = 2;
const CHECKSUM: usize = 16;

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Kind {
    Geometry = 0,
    Bundle = 1,
    /// A packed source: geometry found by content hash.
    Source = 2,
    Field = 3,
}

/// What a read asks an entry for: a cook result under its cook key, or a
/// packed source under its content hash.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Asked {
    CookResult(u128),
    Source(u128),
}

impl Asked {
    fn key(self) -> u128 {
        match self {
            Asked::CookResult(k) | Asked::Source(k) => k,
        }
    }
    fn admits(self, kind: Kind) -> bool {
        (kind == Kind::Source) == matches!(self, Asked::Source(_))
    }
    fn what(self) -> &'static str {
        match self {
            Asked::CookResult(_) => "cook result",
            Asked::Source(_) => "packed source",
        }
    }
}

/// Why an entry cannot serve a read.
#[derive(Debug, thiserror::Error)]
pub(crate) enum EntryError {
    #[error("entry layout version {0}, this is {ENTRY_VERSION}")]
    Version(u32),
    #[error("the entry holds key {found:032x}, not {asked:032x} as its name says")]
    OtherKey { asked: u128, found: u128 },
    #[error("a {found:?} entry where a {asked} was expected")]
    OtherKind { asked: &'static str, found: Kind },
    #[error(transparent)]
    Decode(#[from] DecodeError),
}

/// Bytes of one entry for `cached` under cook key `key`, and the packed
/// sources it needs (`None` when the value has no byte form).
pub(crate) fn encode(key: u128, cached: &Cached) -> Option<(Vec<u8>, Vec<Arc<Geometry>>)> {
    let mut sources = Vec::new();
    let mut out = header(
        match cached.value {
            Value::Geometry(_) => Kind::Geometry,
            Value::Bundle(_) => Kind::Bundle,
            Value::Field(_) => Kind::Field,
        },
        key,
        cached.identity(),
        cached.bytes as u64,
        &cached.warnings,
    );
    let mut geometry = |g: &Geometry, out: &mut Vec<u8>| -> Option<()> {
        let mut body = Vec::new();
        codec::encode(g, &mut body, &mut |s| sources.push(Arc::clone(s))).ok()?;
        out.extend_from_slice(&(body.len() as u64).to_le_bytes());
        out.extend_from_slice(&body);
        Some(())
    };
    match &cached.value {
        Value::Geometry(g) => geometry(g, &mut out)?,
        Value::Bundle(b) => {
            out.extend_from_slice(&(b.entries.len() as u64).to_le_bytes());
            for (name, g) in &b.entries {
                put_str(&mut out, name);
                geometry(g, &mut out)?;
            }
        }
        Value::Field(f) => {
            let mut body = Vec::new();
            geode_frep::codec::encode(f, &mut body);
            out.extend_from_slice(&(body.len() as u64).to_le_bytes());
            out.extend_from_slice(&body);
        }
    }
    seal(&mut out);
    Some((out, sources))
}

/// Bytes of a packed source's entry, and the sources it places in turn.
pub(crate) fn encode_source(g: &Geometry) -> Option<(Vec<u8>, Vec<Arc<Geometry>>)> {
    let mut sources = Vec::new();
    let hash = g.content_hash();
    let mut out = header(Kind::Source, hash, hash, 0, &[]);
    let mut body = Vec::new();
    codec::encode(g, &mut body, &mut |s| sources.push(Arc::clone(s))).ok()?;
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(&body);
    seal(&mut out);
    Some((out, sources))
}

fn header(kind: Kind, key: u128, identity: u128, bytes: u64, warnings: &[String]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&ENTRY_VERSION.to_le_bytes());
    out.push(kind as u8);
    out.extend_from_slice(&key.to_le_bytes());
    out.extend_from_slice(&identity.to_le_bytes());
    out.extend_from_slice(&bytes.to_le_bytes());
    out.extend_from_slice(&(warnings.len() as u64).to_le_bytes());
    for w in warnings {
        put_str(&mut out, w);
    }
    out
}

fn put_str(out: &mut Vec<u8>, s: &str) {
    out.extend_from_slice(&(s.len() as u64).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

fn seal(out: &mut Vec<u8>) {
    let sum = xxh3_128(out);
    out.extend_from_slice(&sum.to_le_bytes());
}

/// The body of an entry whose checksum holds, `None` otherwise.
pub(crate) fn verified(bytes: &[u8]) -> Option<&[u8]> {
    let body_len = bytes.len().checked_sub(CHECKSUM)?;
    let (body, sum) = bytes.split_at(body_len);
    (xxh3_128(body).to_le_bytes() == sum).then_some(body)
}

/// Decodes a verified entry if it holds what `asked` names (the key and the
/// kind are checked before the value is read); `source` finds packed sources.
pub(crate) fn decode(
    body: &[u8],
    asked: Asked,
    source: &dyn Fn(u128) -> Option<Arc<Geometry>>,
) -> Result<Cached, EntryError> {
    let mut r = Reader { b: body, at: 0 };
    if r.take(8)? != MAGIC {
        return Err(DecodeError::Magic.into());
    }
    let version = u32::from_le_bytes(r.array()?);
    if version != ENTRY_VERSION {
        return Err(EntryError::Version(version));
    }
    let kind = match r.take(1)?[0] {
        0 => Kind::Geometry,
        1 => Kind::Bundle,
        2 => Kind::Source,
        3 => Kind::Field,
        k => return Err(DecodeError::Invalid(format!("entry kind {k}")).into()),
    };
    if !asked.admits(kind) {
        return Err(EntryError::OtherKind {
            asked: asked.what(),
            found: kind,
        });
    }
    let key = u128::from_le_bytes(r.array()?);
    if key != asked.key() {
        return Err(EntryError::OtherKey {
            asked: asked.key(),
            found: key,
        });
    }
    let identity = u128::from_le_bytes(r.array()?);
    let bytes = u64::from_le_bytes(r.array()?) as usize;
    let n = r.len()?;
    let warnings: Vec<String> = (0..n).map(|_| r.string()).collect::<Result<_, _>>()?;
    let value = match kind {
        Kind::Geometry | Kind::Source => Value::Geometry(Arc::new(r.geometry(source)?)),
        Kind::Bundle => {
            let n = r.len()?;
            let mut entries = BTreeMap::new();
            for _ in 0..n {
                let name = r.string()?;
                entries.insert(name, Arc::new(r.geometry(source)?));
            }
            Value::Bundle(Arc::new(Bundle { entries }))
        }
        Kind::Field => {
            let n = r.len()?;
            let f = geode_frep::codec::decode(r.take(n)?)
                .map_err(|e| DecodeError::Invalid(e.to_string()))?;
            Value::Field(f)
        }
    };
    if r.at != body.len() {
        return Err(DecodeError::Invalid("bytes after the value".into()).into());
    }
    Ok(Cached::stored(value, identity, bytes, warnings.into()))
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or(DecodeError::Truncated(self.at))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn array<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }
    fn len(&mut self) -> Result<usize, DecodeError> {
        let n = u64::from_le_bytes(self.array()?);
        usize::try_from(n)
            .ok()
            .filter(|&n| n <= self.b.len())
            .ok_or(DecodeError::Truncated(self.at))
    }
    fn string(&mut self) -> Result<String, DecodeError> {
        let n = self.len()?;
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| DecodeError::Invalid("text is not UTF-8".into()))
    }
    fn geometry(
        &mut self,
        source: &dyn Fn(u128) -> Option<Arc<Geometry>>,
    ) -> Result<Geometry, DecodeError> {
        let n = self.len()?;
        codec::decode(self.take(n)?, source)
    }
}
