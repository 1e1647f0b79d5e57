//! What the library sees of the geometry while a batch runs: the inputs'
//! snapshots, indexes built once per input (topology, k-d tree), and the
//! effects the batch queues (writes to other elements, new and removed
//! geometry) to be applied after every element ran.

use std::sync::{Arc, OnceLock};

use geode_geo::{AttribClass, Geometry, Topology};

use crate::budget::{Budget, HeapBytes};
use crate::builtins::{attrib_value, Val};
use crate::kdtree::KdTree;

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

/// A topology and its point count, built on first use.
pub struct Topo {
    pub topo: Arc<Topology>,
    points: usize,
}

impl Topo {
    pub fn point_count(&self) -> usize {
        self.points
    }
}

/// A k-d tree over one point group and the point numbers of its members.
type GroupTree = (KdTree, Vec<u32>);

/// Per-run data shared by every batch.
pub struct Shared<'a> {
    pub inputs: Vec<Option<&'a Geometry>>,
    topo: Vec<OnceLock<Topo>>,
    trees: Vec<OnceLock<KdTree>>,
    /// Trees over one point group of an input, made on first use.
    group_trees: std::sync::Mutex<Vec<(usize, String, Arc<GroupTree>)>>,
    /// The run's memory account.
    pub budget: Budget,
}

impl<'a> Shared<'a> {
    pub fn new(inputs: Vec<Option<&'a Geometry>>, memory_budget: u64) -> Shared<'a> {
        let n = inputs.len();
        Shared {
            inputs,
            topo: (0..n).map(|_| OnceLock::new()).collect(),
            trees: (0..n).map(|_| OnceLock::new()).collect(),
            group_trees: std::sync::Mutex::new(Vec::new()),
            budget: Budget::new(memory_budget),
        }
    }
}

/// One batch's view: the shared inputs and its queued effects.
pub struct World<'s, 'a> {
    pub shared: &'s Shared<'a>,
    pub cancel: &'s (dyn Fn() -> bool + Sync),
    /// Element number of each lane.
    pub elems: Vec<u32>,
    pub effects: Vec<Effect>,
    seq: u32,
    new_points: i32,
    new_prims: i32,
    /// Bytes of effects queued since the budget was last charged.
    uncharged: u64,
}

impl<'s, 'a> World<'s, 'a> {
    pub fn new(shared: &'s Shared<'a>, cancel: &'s (dyn Fn() -> bool + Sync)) -> World<'s, 'a> {
        World {
            shared,
            cancel,
            elems: Vec::new(),
            effects: Vec::new(),
            seq: 0,
            new_points: 0,
            new_prims: 0,
            uncharged: 0,
        }
    }

    pub fn elem_of(&self, lane: usize) -> u32 {
        self.elems.get(lane).copied().unwrap_or(0)
    }

    pub fn input(&self, i: i32) -> Option<&'a Geometry> {
        usize::try_from(i)
            .ok()
            .and_then(|i| self.shared.inputs.get(i).copied().flatten())
    }

    pub fn topology(&self, i: i32) -> Option<&Topo> {
        let g = self.input(i)?;
        Some(self.shared.topo[i as usize].get_or_init(|| Topo {
            topo: g.topology(),
            points: g.num_points(),
        }))
    }

    /// Up to `count` points of input `i` (of point group `group` unless it
    /// is empty) within `radius` of `q`, nearest first.
    pub fn nearest(&self, i: i32, group: &str, q: [f32; 3], radius: f32, count: usize) -> Vec<u32> {
        let Some(g) = self.input(i) else {
            return Vec::new();
        };
        let i = i as usize;
        if group.is_empty() {
            let tree = self.shared.trees[i]
                .get_or_init(|| KdTree::new(g.positions().iter().map(|p| p.to_array()).collect()));
            return tree.nearest(q, radius, count);
        }
        let tree = {
            let mut cache = self
                .shared
                .group_trees
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            match cache.iter().find(|(k, name, _)| *k == i && name == group) {
                Some((_, _, t)) => Arc::clone(t),
                None => {
                    let members: Vec<u32> = match g.point_groups().get(group) {
                        Some(grp) => (0..grp.len())
                            .filter(|&p| grp.contains(p))
                            .map(|p| p as u32)
                            .collect(),
                        None => Vec::new(),
                    };
                    let pts = members
                        .iter()
                        .map(|&p| g.positions()[p as usize].to_array())
                        .collect();
                    let t = Arc::new((KdTree::new(pts), members));
                    cache.push((i, group.to_string(), Arc::clone(&t)));
                    t
                }
            }
        };
        tree.0
            .nearest(q, radius, count)
            .into_iter()
            .map(|k| tree.1[k as usize])
            .collect()
    }

    /// Queues an effect of lane `lane`'s element, charged against the
    /// budget (in steps of `CHARGE_STEP`, so threads seldom meet on the
    /// shared account).
    pub fn queue(&mut self, lane: usize, kind: EffectKind) -> Result<(), String> {
        const CHARGE_STEP: u64 = 1 << 16;
        self.uncharged += std::mem::size_of::<Effect>() as u64 + kind.heap_bytes();
        if self.uncharged >= CHARGE_STEP {
            let bytes = std::mem::take(&mut self.uncharged);
            let budget = &self.shared.budget;
            if !budget.fits(bytes) {
                return Err(budget.refusal(
                    &format!("queueing {} more geometry changes", self.effects.len() + 1),
                    bytes,
                ));
            }
            budget.charge(bytes as i64);
        }
        self.seq += 1;
        self.effects.push(Effect {
            elem: self.elem_of(lane),
            seq: self.seq,
            kind,
        });
        Ok(())
    }

    /// A provisional number for a new point: past the input's points,
    /// counted within this batch (resolved when the batch's effects apply).
    pub fn new_point(&mut self) -> i32 {
        self.new_points += 1;
        self.input(0).map_or(0, |g| g.num_points() as i32) + self.new_points - 1
    }

    pub fn new_prim(&mut self) -> i32 {
        self.new_prims += 1;
        self.input(0).map_or(0, |g| g.num_prims() as i32) + self.new_prims - 1
    }
}

/// An attribute's value at element `idx` of class `class`, if it exists.
pub fn read_attrib(g: &Geometry, class: AttribClass, name: &str, idx: i32) -> Option<Val> {
    if class == AttribClass::Point && name == "P" {
        let p = g.positions().get(usize::try_from(idx).ok()?)?;
        return Some(Val::vec(&p.to_array()));
    }
    let a = g.attrib(class, name)?;
    let i = usize::try_from(idx).ok().filter(|&i| i < a.len())?;
    Some(attrib_value(a.data(), i))
}

/// Half-edges as Houdini's VEX numbers them: a half-edge is the vertex it
/// leaves from, running to the next vertex of its primitive (a polygon
/// wraps; a polyline's last vertex starts none). -1 where there is none.
pub fn hedge(
    g: &Geometry,
    topology: impl Fn() -> Arc<Topology>,
    f: crate::builtins::HedgeFn,
    x: i32,
) -> i32 {
    use crate::builtins::HedgeFn as H;
    use geode_geo::PrimKind;
    let offsets = g.prim_offsets();
    let prim_of = |v: usize| offsets.partition_point(|&o| o as usize <= v) - 1;
    // The vertex after `v` in its primitive, if `v` starts a half-edge.
    let next = |v: usize| -> Option<usize> {
        let p = prim_of(v);
        let r = g.prim_vertex_range(p);
        let closed = g.prim_kind(p) == PrimKind::Polygon;
        if v + 1 < r.end {
            Some(v + 1)
        } else if closed && r.len() > 1 {
            Some(r.start)
        } else {
            None
        }
    };
    let valid = |h: i32| {
        usize::try_from(h)
            .ok()
            .filter(|&v| v < g.num_vertices() && next(v).is_some())
    };
    let out = match f {
        H::PointHedge => {
            // The point's primitives (from the topology), not every vertex.
            let p = usize::try_from(x).ok().filter(|&p| p < g.num_points());
            let topo = p.map(|_| topology());
            p.and_then(|p| {
                topo.as_ref()?
                    .point_prims(p)
                    .iter()
                    .flat_map(|&prim| g.prim_vertex_range(prim as usize))
                    .filter(|&v| g.vertex_points()[v] as usize == p && next(v).is_some())
                    .min()
            })
        }
        H::PrimHedge => usize::try_from(x)
            .ok()
            .filter(|&p| p < g.num_prims())
            .map(|p| g.prim_vertex_range(p).start)
            .filter(|&v| next(v).is_some()),
        H::Next => valid(x).and_then(next).filter(|&v| next(v).is_some()),
        H::SrcPoint => valid(x).map(|v| g.vertex_points()[v] as usize),
        H::DstPoint => valid(x)
            .and_then(next)
            .map(|v| g.vertex_points()[v] as usize),
        H::IsValid => return i32::from(valid(x).is_some()),
        H::Prim => valid(x).map(prim_of),
    };
    out.map_or(-1, |v| v as i32)
}
