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
        on: bool,
    },
    Print(String),
}

impl EffectKind {
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
    pub kind: EffectKind,
}
