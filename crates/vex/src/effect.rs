//! The geometry changes a lane queues (attribute writes to other
//! elements, new points, primitives and vertices, removals, group
//! membership, prints), applied after every element ran.

use geode_geo::AttribClass;

use crate::value::{HeapBytes, Val};

/// How `set*attrib` combines with the value already there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Set,
    Add,
    Min,
    Max,
    Mult,
    Append,
}

#[derive(Clone, Debug, PartialEq)]
pub enum EffectKind {
    /// Boxed: the rare large variant stays out of every effect's size.
    SetAttr(Box<SetAttr>),
    AddPoint {
        handle: i32,
        from: Option<i32>,
        pos: [f32; 3],
    },
    AddPrim {
        handle: i32,
        polyline: bool,
        points: Points,
    },
    AddVertex {
        prim: i32,
        point: i32,
    },
    RemovePoint {
        point: i32,
        /// Also remove the primitives the removal leaves degenerate.
        and_prims: bool,
    },
    RemovePrim {
        prim: i32,
        and_points: bool,
    },
    SetGroup {
        class: AttribClass,
        name: String,
        target: i32,
        /// The membership to set; `None` toggles it.
        on: Option<bool>,
    },
    Print(String),
}

impl EffectKind {
    /// Whether the effect makes points or primitives (see `run::build`).
    pub fn builds(&self) -> bool {
        matches!(
            self,
            EffectKind::AddPoint { .. } | EffectKind::AddPrim { .. } | EffectKind::AddVertex { .. }
        )
    }

    /// Bytes the effect holds beyond its own size.
    pub fn heap_bytes(&self) -> u64 {
        match self {
            EffectKind::SetAttr(s) => {
                (std::mem::size_of::<SetAttr>() + s.name.capacity()) as u64 + s.value.heap_bytes()
            }
            EffectKind::AddPrim {
                points: Points::Heap(v),
                ..
            } => (v.capacity() * 4) as u64,
            EffectKind::SetGroup { name, .. } => name.capacity() as u64,
            EffectKind::Print(s) => s.capacity() as u64,
            _ => 0,
        }
    }
}

/// The points `addprim` was given: up to four kept inline (the common
/// segment, triangle and quad allocate nothing), more on the heap.
#[derive(Clone, Debug, PartialEq)]
pub enum Points {
    Inline([i32; 4], u8),
    Heap(Vec<i32>),
}

impl Points {
    pub fn new() -> Points {
        Points::Inline([0; 4], 0)
    }

    pub fn push(&mut self, p: i32) {
        match self {
            Points::Inline(a, n) if (*n as usize) < a.len() => {
                a[*n as usize] = p;
                *n += 1;
            }
            Points::Inline(a, n) => {
                let mut v = a[..*n as usize].to_vec();
                v.push(p);
                *self = Points::Heap(v);
            }
            Points::Heap(v) => v.push(p),
        }
    }

    pub fn as_slice(&self) -> &[i32] {
        match self {
            Points::Inline(a, n) => &a[..*n as usize],
            Points::Heap(v) => v,
        }
    }
}

impl Default for Points {
    fn default() -> Points {
        Points::new()
    }
}

/// A write to another element's attribute.
#[derive(Clone, Debug, PartialEq)]
pub struct SetAttr {
    pub class: AttribClass,
    pub name: String,
    pub target: i32,
    pub vtx: i32,
    pub value: Val,
    pub mode: Mode,
}

/// An effect with the element that queued it and its order in that element.
#[derive(Clone, Debug)]
pub struct Effect {
    pub elem: u32,
    pub seq: u32,
    /// The call that queued it, for errors when it applies.
    pub pos: crate::compile::Pos,
    pub kind: EffectKind,
}

/// Effects in a batch's first chunk; each next chunk doubles, up to 4 MiB
/// (whole huge pages, where the binary's allocator asks for them).
const FIRST_CHUNK: usize = 64;
const CHUNK_BYTES: usize = 4 << 20;

/// A batch's queued effects, in chunks: a detail loop queues millions, and
/// a chunk never moves what it holds (one long array would be copied each
/// time it grows, touching twice the memory).
#[derive(Debug, Default)]
pub struct EffectQueue {
    chunks: Vec<Vec<Effect>>,
    len: usize,
}

impl EffectQueue {
    pub fn push(&mut self, e: Effect) {
        match self.chunks.last_mut() {
            Some(c) if c.len() < c.capacity() => c.push(e),
            _ => {
                let most = CHUNK_BYTES / std::mem::size_of::<Effect>();
                let next = self.chunks.last().map_or(FIRST_CHUNK, |c| c.capacity() * 2);
                let mut c = Vec::with_capacity(next.min(most));
                c.push(e);
                self.chunks.push(c);
            }
        }
        self.len += 1;
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn iter(&self) -> impl Iterator<Item = &Effect> {
        self.chunks.iter().flatten()
    }

    /// Puts the effects in (element, order) sequence: a batch's calls run
    /// lane after lane, so effects come call by call. One element's (a
    /// detail run's) are in sequence already.
    pub fn sort(&mut self) {
        let key = |e: &Effect| (e.elem, e.seq);
        if self.iter().map(key).is_sorted() {
            return;
        }
        let mut all: Vec<Effect> = std::mem::take(&mut self.chunks)
            .into_iter()
            .flatten()
            .collect();
        all.sort_by_key(key);
        self.chunks = vec![all];
    }
}
