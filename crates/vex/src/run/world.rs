//! What the library sees of the geometry while a batch runs: the inputs'
//! snapshots, indexes built once per input (topology, k-d tree), and the
//! effects the batch queues (writes to other elements, new and removed
//! geometry) to be applied after every element ran.

use std::any::Any;
use std::sync::{Arc, OnceLock};

use geode_geo::{Geometry, Topology};

use super::budget::Budget;
use super::build::Builder;
use crate::effect::{Effect, EffectKind, EffectQueue};
use crate::kdtree::KdTree;
use crate::program::{Host, PointQuery, Stop};

/// A k-d tree over one point group and the point numbers of its members.
type GroupTree = (KdTree, Vec<u32>);

/// An index over an input: (input, key, variant, index).
type Cached = (usize, &'static str, String, Arc<dyn Any + Send + Sync>);

/// Per-run data shared by every batch.
pub struct Shared<'a> {
    pub inputs: Vec<Option<&'a Geometry>>,
    topo: Vec<OnceLock<Arc<Topology>>>,
    trees: Vec<OnceLock<KdTree>>,
    /// Trees over one point group of an input, made on first use.
    group_trees: std::sync::Mutex<Vec<(usize, String, Arc<GroupTree>)>>,
    /// Indexes the library builds over an input once per run (by input,
    /// key and variant).
    caches: std::sync::Mutex<Vec<Cached>>,
    /// The run's memory account.
    pub budget: Budget,
    /// The program's ramp parameters (`chramp`).
    pub ramps: &'a [geode_geo::Ramp],
}

impl<'a> Shared<'a> {
    pub fn new(
        inputs: Vec<Option<&'a Geometry>>,
        memory_budget: u64,
        ramps: &'a [geode_geo::Ramp],
    ) -> Shared<'a> {
        let n = inputs.len();
        Shared {
            inputs,
            topo: (0..n).map(|_| OnceLock::new()).collect(),
            trees: (0..n).map(|_| OnceLock::new()).collect(),
            group_trees: std::sync::Mutex::new(Vec::new()),
            caches: std::sync::Mutex::new(Vec::new()),
            budget: Budget::new(memory_budget),
            ramps,
        }
    }
}

/// One batch's view: the shared inputs and its queued effects.
pub struct World<'s, 'a> {
    pub shared: &'s Shared<'a>,
    pub cancel: &'s (dyn Fn() -> bool + Sync),
    /// Element number of each lane.
    pub elems: Vec<u32>,
    pub effects: EffectQueue,
    seq: u32,
    new_points: i32,
    new_prims: i32,
    /// Bytes of effects queued since the budget was last charged.
    uncharged: u64,
    /// Point cloud queries opened in this batch, by handle.
    queries: Vec<PointQuery>,
    /// A one-lane run's new points and primitives, made as its calls run
    /// rather than queued (see `build`).
    pub built: Option<Builder>,
    /// Changes queued (or built) by this batch, for messages.
    queued: usize,
    /// The call running, whose position its effects keep.
    pub pos: crate::compile::Pos,
}

impl<'s, 'a> World<'s, 'a> {
    pub fn new(shared: &'s Shared<'a>, cancel: &'s (dyn Fn() -> bool + Sync)) -> World<'s, 'a> {
        World {
            shared,
            cancel,
            elems: Vec::new(),
            effects: EffectQueue::default(),
            seq: 0,
            new_points: 0,
            new_prims: 0,
            uncharged: 0,
            queries: Vec::new(),
            built: None,
            queued: 0,
            pos: Default::default(),
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

    /// Input `i`'s topology, built on first use.
    pub fn topology(&self, i: i32) -> Option<&Arc<Topology>> {
        let g = self.input(i)?;
        Some(self.shared.topo[i as usize].get_or_init(|| g.topology()))
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
                    // A group pattern, as Houdini reads the argument.
                    let mut members: Vec<u32> =
                        crate::pattern::expand(g, geode_geo::AttribClass::Point, group)
                            .into_iter()
                            .map(|p| p as u32)
                            .collect();
                    members.sort_unstable();
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
    pub fn queue(&mut self, lane: usize, kind: EffectKind) -> Result<(), Stop> {
        let elem = self.elem_of(lane);
        self.queued += 1;
        let pos = self.pos;
        let growth = self.built.as_ref().filter(|_| kind.builds());
        if let Some(bytes) = growth.map(|b| b.growth(elem, pos, &kind)) {
            // Built as it comes: the budget is asked for what the lists
            // grow by before they grow.
            self.charge(bytes)?;
            if let Some(b) = self.built.as_mut() {
                b.take(elem, pos, &kind).map_err(Stop::Msg)?;
            }
        } else {
            self.charge(std::mem::size_of::<Effect>() as u64 + kind.heap_bytes())?;
            self.seq += 1;
            self.effects.push(Effect {
                elem,
                seq: self.seq,
                pos: self.pos,
                kind,
            });
        }
        Ok(())
    }

    /// Charges `bytes` more of queued changes against the budget, in steps
    /// of `CHARGE_STEP` so threads seldom meet on the shared count.
    fn charge(&mut self, bytes: u64) -> Result<(), Stop> {
        const CHARGE_STEP: u64 = 1 << 16;
        self.uncharged += bytes;
        if self.uncharged >= CHARGE_STEP {
            let bytes = std::mem::take(&mut self.uncharged);
            let budget = &self.shared.budget;
            if !budget.fits(bytes) {
                return Err(Stop::OverBudget(budget.refusal(
                    &format!("queueing {} more geometry changes", self.queued),
                    bytes,
                )));
            }
            budget.charge(bytes as i64);
        }
        Ok(())
    }

    /// A provisional number for a new point: past the input's points,
    /// counted within this batch (resolved when the batch's effects apply).
    fn new_point(&mut self) -> i32 {
        self.new_points += 1;
        self.input(0).map_or(0, |g| g.num_points() as i32) + self.new_points - 1
    }

    fn new_prim(&mut self) -> i32 {
        self.new_prims += 1;
        self.input(0).map_or(0, |g| g.num_prims() as i32) + self.new_prims - 1
    }

    /// A new point of lane `lane`'s element (a copy of `from`, or at
    /// `at`): made at once where the run builds as it goes, else queued.
    pub fn add_point(&mut self, lane: usize, from: Option<i32>, at: [f32; 3]) -> Result<i32, Stop> {
        let handle = self.new_point();
        if let Some(bytes) = self.built.as_ref().map(|b| b.point_growth(from.is_some())) {
            self.queued += 1;
            self.charge(bytes)?;
            if let Some(b) = self.built.as_mut() {
                b.add_point(handle, from, at).map_err(Stop::Msg)?;
            }
        } else {
            self.queue(
                lane,
                EffectKind::AddPoint {
                    handle,
                    from,
                    pos: at,
                },
            )?;
        }
        Ok(handle)
    }

    /// A new polygon or polyline of lane `lane`'s element through
    /// `points`, made at once or queued like `add_point`.
    pub fn add_prim(&mut self, lane: usize, polyline: bool, points: &[i32]) -> Result<i32, Stop> {
        let handle = self.new_prim();
        let (elem, pos) = (self.elem_of(lane), self.pos);
        if let Some(bytes) = self
            .built
            .as_ref()
            .map(|b| b.prim_growth(elem, pos, points.len()))
        {
            self.queued += 1;
            self.charge(bytes)?;
            if let Some(b) = self.built.as_mut() {
                b.add_prim(elem, pos, handle, polyline, points)
                    .map_err(Stop::Msg)?;
            }
        } else {
            let mut list = crate::effect::Points::new();
            points.iter().for_each(|p| list.push(*p));
            self.queue(
                lane,
                EffectKind::AddPrim {
                    handle,
                    polyline,
                    points: list,
                },
            )?;
        }
        Ok(handle)
    }
}

/// One lane's view of its batch, as the library's lane functions see it.
pub struct LaneHost<'w, 's, 'a> {
    pub world: &'w mut World<'s, 'a>,
    pub lane: usize,
}

impl Host for LaneHost<'_, '_, '_> {
    fn input(&self, i: i32) -> Option<&Geometry> {
        self.world.input(i)
    }

    fn topology(&self, i: i32) -> Option<Arc<Topology>> {
        self.world.topology(i).map(Arc::clone)
    }

    fn nearest(&self, i: i32, group: &str, q: [f32; 3], radius: f32, count: usize) -> Vec<u32> {
        self.world.nearest(i, group, q, radius, count)
    }

    fn queue(&mut self, kind: EffectKind) -> Result<(), Stop> {
        self.world.queue(self.lane, kind)
    }

    fn add_point(&mut self, from: Option<i32>, at: [f32; 3]) -> Result<i32, Stop> {
        self.world.add_point(self.lane, from, at)
    }

    fn add_prim(&mut self, polyline: bool, points: &[i32]) -> Result<i32, Stop> {
        self.world.add_prim(self.lane, polyline, points)
    }

    fn cancelled(&self) -> bool {
        (self.world.cancel)()
    }

    fn elem(&self) -> u32 {
        self.world.elem_of(self.lane)
    }

    fn cached(
        &self,
        i: i32,
        key: &'static str,
        variant: &str,
        build: &dyn Fn(&Geometry) -> Arc<dyn Any + Send + Sync>,
    ) -> Option<Arc<dyn Any + Send + Sync>> {
        let g = self.world.input(i)?;
        let i = i as usize;
        let shared = self.world.shared;
        let find = |cache: &[Cached]| {
            cache
                .iter()
                .find(|(k, n, v, _)| *k == i && *n == key && v == variant)
                .map(|(.., index)| Arc::clone(index))
        };
        if let Some(index) = find(&shared.caches.lock().unwrap_or_else(|p| p.into_inner())) {
            return Some(index);
        }
        // Built outside the lock (other batches wait on nothing); a race
        // builds twice and keeps the first.
        let built = build(g);
        let mut cache = shared.caches.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(index) = find(&cache) {
            return Some(index);
        }
        cache.push((i, key, variant.to_string(), Arc::clone(&built)));
        Some(built)
    }

    fn ramp(&self, k: usize) -> Option<&geode_geo::Ramp> {
        self.world.shared.ramps.get(k)
    }

    fn open_query(&mut self, q: PointQuery) -> i32 {
        self.world.queries.push(q);
        self.world.queries.len() as i32 - 1
    }

    fn query(&mut self, handle: i32) -> Option<&mut PointQuery> {
        usize::try_from(handle)
            .ok()
            .and_then(|h| self.world.queries.get_mut(h))
    }
}
