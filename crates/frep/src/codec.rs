//! A versioned binary form of a `Field` (the disk cache's): its distinct nodes children first, each naming its operands by index, and its datasets (capsule sets with their built hierarchies, meshes as points and triangles, volumes as their leaves and tiles).
//!
//! A decoded field is rebuilt through the same constructors, so it has the
//! identity of the one encoded; capsule sets are stored as built (segments
//! in hierarchy order, the hierarchy's boxes) and read back as they were,
//! not rebuilt; a mesh's hierarchy is rebuilt from its triangles. Traversal is iterative: a field millions of nodes deep is
//! no deeper a recursion here. Counts and indices are checked against the
//! bytes before anything is allocated from them.

use std::collections::HashMap;
use std::sync::Arc;

use crate::dataset::Dataset;
use crate::field::{Binary, Field, Node, Unary};

const MAGIC: &[u8; 4] = b"GEOF";
pub const CODEC_VERSION: u32 = 3;

/// Why bytes are not a field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FieldDecodeError {
    #[error("truncated at byte {0}")]
    Truncated(usize),
    #[error("not an encoded field")]
    Magic,
    #[error("encoded by field codec version {0}, this is {CODEC_VERSION}")]
    Version(u32),
    #[error("inconsistent: {0}")]
    Invalid(String),
}

/// The distinct nodes of `root`, every node after its operands.
fn post_order(root: &Field) -> Vec<Field> {
    let mut index: HashMap<*const (), usize> = HashMap::new();
    let mut out = Vec::new();
    let mut stack = vec![(root.clone(), false)];
    while let Some((f, expanded)) = stack.pop() {
        let key = Arc::as_ptr(&f.0) as *const ();
        if index.contains_key(&key) {
            continue;
        }
        if expanded {
            index.insert(key, out.len());
            out.push(f);
            continue;
        }
        stack.push((f.clone(), true));
        match f.node() {
            Node::Unary(_, a) => stack.push((a.clone(), false)),
            Node::Binary(_, a, b) => {
                stack.push((b.clone(), false));
                stack.push((a.clone(), false));
            }
            Node::Dataset(_, args) => args
                .iter()
                .rev()
                .for_each(|a| stack.push((a.clone(), false))),
            Node::X | Node::Y | Node::Z | Node::Const(_) => {}
        }
    }
    out
}

/// Appends `field` to `out`.
pub fn encode(field: &Field, out: &mut Vec<u8>) {
    let nodes = post_order(field);
    let at: HashMap<*const (), u32> = nodes
        .iter()
        .enumerate()
        .map(|(i, f)| (Arc::as_ptr(&f.0) as *const (), i as u32))
        .collect();
    let idx = |f: &Field| at[&(Arc::as_ptr(&f.0) as *const ())];
    let mut sets: Vec<&Arc<Dataset>> = Vec::new();
    let mut set_at: HashMap<*const Dataset, u32> = HashMap::new();
    for f in &nodes {
        if let Node::Dataset(s, _) = f.node() {
            set_at.entry(Arc::as_ptr(s)).or_insert_with(|| {
                sets.push(s);
                sets.len() as u32 - 1
            });
        }
    }
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&CODEC_VERSION.to_le_bytes());
    out.extend_from_slice(&(sets.len() as u64).to_le_bytes());
    for s in &sets {
        s.encode(out);
    }
    out.extend_from_slice(&(nodes.len() as u64).to_le_bytes());
    let u32s = |out: &mut Vec<u8>, v: &[u32]| {
        v.iter()
            .for_each(|x| out.extend_from_slice(&x.to_le_bytes()))
    };
    for f in &nodes {
        match f.node() {
            Node::X => out.push(0),
            Node::Y => out.push(1),
            Node::Z => out.push(2),
            Node::Const(c) => {
                out.push(3);
                out.extend_from_slice(&c.to_le_bytes());
            }
            Node::Unary(op, a) => {
                out.push(4);
                out.push(number_of(&Unary::ALL, op));
                u32s(out, &[idx(a)]);
            }
            Node::Binary(op, a, b) => {
                out.push(5);
                out.push(number_of(&Binary::ALL, op));
                u32s(out, &[idx(a), idx(b)]);
            }
            Node::Dataset(s, args) => {
                out.push(6);
                u32s(
                    out,
                    &[
                        set_at[&Arc::as_ptr(s)],
                        idx(&args[0]),
                        idx(&args[1]),
                        idx(&args[2]),
                    ],
                );
            }
        }
    }
}

pub(crate) struct Reader<'a> {
    pub bytes: &'a [u8],
    pub at: usize,
}

impl<'a> Reader<'a> {
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], FieldDecodeError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or(FieldDecodeError::Truncated(self.at))?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
    pub fn u32(&mut self) -> Result<u32, FieldDecodeError> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().expect("four bytes"),
        ))
    }
    pub fn f32(&mut self) -> Result<f32, FieldDecodeError> {
        Ok(f32::from_le_bytes(
            self.take(4)?.try_into().expect("four bytes"),
        ))
    }
    pub fn f64(&mut self) -> Result<f64, FieldDecodeError> {
        Ok(f64::from_le_bytes(
            self.take(8)?.try_into().expect("eight bytes"),
        ))
    }
    /// A count of items of at least `min_bytes` each, checked against the bytes left.
    pub fn count(&mut self, min_bytes: usize) -> Result<usize, FieldDecodeError> {
        let n = u64::from_le_bytes(self.take(8)?.try_into().expect("eight bytes"));
        let left = (self.bytes.len() - self.at) as u64;
        if n.saturating_mul(min_bytes as u64) > left {
            return Err(FieldDecodeError::Truncated(self.at));
        }
        Ok(n as usize)
    }
}

/// An operation's number: its place in its `ALL` list (append only).
fn number_of<T: PartialEq>(all: &[T], op: &T) -> u8 {
    all.iter().position(|o| o == op).expect("every op listed") as u8
}

/// The operation numbered `number` in `all`.
fn op_numbered<T: Copy>(all: &[T], number: u8, what: &str) -> Result<T, FieldDecodeError> {
    all.get(number as usize)
        .copied()
        .ok_or_else(|| FieldDecodeError::Invalid(what.to_owned()))
}

/// Reads a field encoded by [`encode`]; the whole of `bytes` must be the field.
pub fn decode(bytes: &[u8]) -> Result<Field, FieldDecodeError> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(4)? != MAGIC {
        return Err(FieldDecodeError::Magic);
    }
    let version = r.u32()?;
    if version != CODEC_VERSION {
        return Err(FieldDecodeError::Version(version));
    }
    let n_sets = r.count(8)?;
    let sets: Vec<Arc<Dataset>> = (0..n_sets)
        .map(|_| Dataset::decode(&mut r).map(Arc::new))
        .collect::<Result<_, _>>()?;
    let n = r.count(1)?;
    let mut nodes: Vec<Field> = Vec::with_capacity(n);
    let invalid = |m: &str| FieldDecodeError::Invalid(m.to_owned());
    for _ in 0..n {
        let get = |r: &mut Reader, nodes: &Vec<Field>| -> Result<Field, FieldDecodeError> {
            let i = r.u32()? as usize;
            nodes
                .get(i)
                .cloned()
                .ok_or_else(|| invalid("an operand after its node"))
        };
        let tag = r.take(1)?[0];
        let f = match tag {
            0 => Field::x(),
            1 => Field::y(),
            2 => Field::z(),
            3 => Field::constant(r.f64()?),
            4 => {
                let op = op_numbered(&Unary::ALL, r.take(1)?[0], "unary op")?;
                get(&mut r, &nodes)?.unary(op)
            }
            5 => {
                let op = op_numbered(&Binary::ALL, r.take(1)?[0], "binary op")?;
                let a = get(&mut r, &nodes)?;
                let b = get(&mut r, &nodes)?;
                a.binary(op, b)
            }
            6 => {
                let s = r.u32()? as usize;
                let set = sets.get(s).ok_or_else(|| invalid("dataset index"))?.clone();
                let args = [
                    get(&mut r, &nodes)?,
                    get(&mut r, &nodes)?,
                    get(&mut r, &nodes)?,
                ];
                Field::dataset_at(&set, args)
            }
            t => return Err(FieldDecodeError::Invalid(format!("node tag {t}"))),
        };
        nodes.push(f);
    }
    if r.at != bytes.len() {
        return Err(invalid("bytes after the field"));
    }
    nodes.pop().ok_or_else(|| invalid("no nodes"))
}
