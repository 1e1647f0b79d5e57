//! New points and primitives (`addpoint`, `addprim`, `addvertex`), in
//! (batch, element, order) sequence: new points are numbered as they come,
//! primitives gather in one flat list and are added together, so a detail
//! loop making a million of them costs one append per column, not one
//! resize of every column per primitive.
//!
//! `addvertex` on a primitive of the input is kept apart and applied
//! after the new primitives are added, in the same sequence (see
//! `geode_geo::ops::append_vertices`).
//!
//! A batch numbers what it makes provisionally (past the input's points
//! and primitives, counted within the batch); each batch's handles map to
//! the final numbers. A one-lane run (a detail wrangle) makes them in
//! order, so its calls feed the builder directly instead of queueing
//! effects, and its handle maps stay a plain offset.

use std::collections::HashMap;

use geode_geo::glam::Vec3;
use geode_geo::{ops, Geometry, PrimKind};

use crate::compile::Pos;
use crate::effect::EffectKind;
use crate::error::RunError;

/// Final numbers of a batch's provisional handles: `base + k` maps to slot
/// k. Handles made in order map by an offset; others by a table.
pub(super) enum Handles {
    Offset { base: i32, first: u32, count: u32 },
    Table { base: i32, ids: Vec<Option<u32>> },
}

impl Handles {
    fn new(base: i32, first: u32) -> Handles {
        Handles::Offset {
            base,
            first,
            count: 0,
        }
    }

    fn insert(&mut self, h: i32, id: u32) {
        if let Handles::Offset { base, first, count } = self {
            if h == *base + *count as i32 && id == *first + *count {
                *count += 1;
                return;
            }
            let (base, first, count) = (*base, *first, *count);
            let ids = (0..count).map(|k| Some(first + k)).collect();
            *self = Handles::Table { base, ids };
        }
        let Handles::Table { base, ids } = self else {
            unreachable!("a table now")
        };
        let Ok(k) = usize::try_from(h - *base) else {
            return;
        };
        if ids.len() <= k {
            ids.resize(k + 1, None);
        }
        ids[k] = Some(id);
    }

    pub fn get(&self, h: &i32) -> Option<u32> {
        match self {
            Handles::Offset { base, first, count } => u32::try_from(h - base)
                .ok()
                .filter(|k| k < count)
                .map(|k| first + k),
            Handles::Table { base, ids } => usize::try_from(h - base)
                .ok()
                .and_then(|k| ids.get(k).copied().flatten()),
        }
    }
}

/// The bytes `v` would allocate to take `more` (it doubles).
fn grows<T>(v: &Vec<T>, more: usize) -> u64 {
    if v.len() + more <= v.capacity() {
        return 0;
    }
    let cap = (v.capacity() * 2).max(v.len() + more).max(8);
    (cap * std::mem::size_of::<T>()) as u64
}

/// What the batches made so far. New points are numbered `base_points +
/// k` (k in `positions`), new primitives by their index in `shape`, until
/// `finish` gives them their final numbers.
pub(super) struct Builder {
    base_points: i32,
    base_prims: i32,
    positions: Vec<Vec3>,
    /// (source point, new point) for `addpoint(0, src)`.
    copies: Vec<(u32, u32)>,
    /// Each primitive's `(closed, vertex count)` over the next points of
    /// `flat`, plus `addvertex` made after another primitive was started
    /// (`late`, by primitive), and each one's element for errors.
    shape: Vec<(bool, u32)>,
    flat: Vec<u32>,
    late: HashMap<u32, Vec<u32>>,
    /// Who made the primitives from each index on, for errors: a new run
    /// only where the element or the call changes (a loop makes millions
    /// from one call).
    made_by: Vec<(u32, u32, Pos)>,
    /// `addvertex` on the input's primitives: (primitive, point, element,
    /// call).
    existing: Vec<(u32, u32, u32, Pos)>,
    point_maps: Vec<Handles>,
    prim_maps: Vec<Handles>,
}

impl Builder {
    /// A builder over an input of `base_points` points and `base_prims`
    /// primitives, its first batch begun.
    pub fn new(base_points: i32, base_prims: i32) -> Builder {
        let mut b = Builder {
            base_points,
            base_prims,
            positions: Vec::new(),
            copies: Vec::new(),
            shape: Vec::new(),
            flat: Vec::new(),
            late: HashMap::new(),
            made_by: Vec::new(),
            existing: Vec::new(),
            point_maps: Vec::new(),
            prim_maps: Vec::new(),
        };
        b.begin_batch();
        b
    }

    /// Whether nothing was made.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty() && self.shape.is_empty() && self.existing.is_empty()
    }

    /// The next batch's handles start again from the bases.
    pub fn begin_batch(&mut self) {
        let first_point = self.base_points as u32 + self.positions.len() as u32;
        self.point_maps
            .push(Handles::new(self.base_points, first_point));
        self.prim_maps
            .push(Handles::new(self.base_prims, self.shape.len() as u32));
    }

    /// The bytes taking `kind` would allocate (the lists it grows double),
    /// so the memory budget is asked before they are.
    pub fn growth(&self, elem: u32, pos: Pos, kind: &EffectKind) -> u64 {
        match kind {
            EffectKind::AddPoint { from, .. } => self.point_growth(from.is_some()),
            EffectKind::AddPrim { points, .. } => {
                self.prim_growth(elem, pos, points.as_slice().len())
            }
            EffectKind::AddVertex { .. } => grows(&self.flat, 1) + 16,
            _ => 0,
        }
    }

    /// The bytes a new point would allocate (a copy also lists its source).
    pub fn point_growth(&self, copy: bool) -> u64 {
        grows(&self.positions, 1) + if copy { grows(&self.copies, 1) } else { 0 }
    }

    /// The bytes a new primitive of `n` points would allocate.
    pub fn prim_growth(&self, elem: u32, pos: Pos, n: usize) -> u64 {
        grows(&self.flat, n)
            + grows(&self.shape, 1)
            + if self.new_maker(elem, pos) {
                grows(&self.made_by, 1)
            } else {
                0
            }
    }

    /// Takes a construction effect of element `elem` (made by the call at
    /// `pos`); the other effects are not its own.
    pub fn take(&mut self, elem: u32, pos: Pos, kind: &EffectKind) -> Result<(), String> {
        match kind {
            EffectKind::AddPoint { handle, from, pos } => self.add_point(*handle, *from, *pos),
            EffectKind::AddPrim {
                handle,
                polyline,
                points,
            } => self.add_prim(elem, pos, *handle, *polyline, points.as_slice()),
            EffectKind::AddVertex { prim, point } => self.add_vertex(elem, pos, *prim, *point),
            _ => Ok(()),
        }
    }

    /// New point `handle`: a copy of point `from`, or at `at`.
    pub fn add_point(
        &mut self,
        handle: i32,
        from: Option<i32>,
        at: [f32; 3],
    ) -> Result<(), String> {
        let id = self.base_points as u32 + self.positions.len() as u32;
        if let Some(src) = from {
            let s = self
                .point(src)
                .ok_or_else(|| format!("addpoint: point {src} does not exist"))?;
            self.copies.push((s, id));
        }
        self.points().insert(handle, id);
        self.positions.push(at.into());
        Ok(())
    }

    /// New primitive `handle` through `points`, made by `elem` at `pos`.
    pub fn add_prim(
        &mut self,
        elem: u32,
        pos: Pos,
        handle: i32,
        polyline: bool,
        points: &[i32],
    ) -> Result<(), String> {
        let start = self.flat.len();
        for &h in points {
            match self.point(h) {
                Some(p) => self.flat.push(p),
                None => {
                    self.flat.truncate(start);
                    return Err(format!("point {h} does not exist"));
                }
            }
        }
        let k = self.shape.len() as u32;
        self.prims().insert(handle, k);
        self.shape.push((!polyline, points.len() as u32));
        if self.new_maker(elem, pos) {
            self.made_by.push((k, elem, pos));
        }
        Ok(())
    }

    /// A vertex on `point` appended to primitive `prim` (new or the
    /// input's).
    fn add_vertex(&mut self, elem: u32, pos: Pos, prim: i32, point: i32) -> Result<(), String> {
        let pt = self
            .point(point)
            .ok_or_else(|| format!("addvertex: point {point} does not exist"))?;
        if (0..self.base_prims).contains(&prim) {
            self.existing.push((prim as u32, pt, elem, pos));
            return Ok(());
        }
        let Some(k) = self.prim_maps.last().and_then(|m| m.get(&prim)) else {
            return Err(format!("addvertex: primitive {prim} does not exist"));
        };
        if k as usize + 1 == self.shape.len() {
            // The last primitive grows in place.
            self.flat.push(pt);
            self.shape[k as usize].1 += 1;
        } else {
            self.late.entry(k).or_default().push(pt);
        }
        Ok(())
    }

    /// Whether a primitive made by `elem` at `pos` starts a run of makers.
    fn new_maker(&self, elem: u32, pos: Pos) -> bool {
        self.made_by
            .last()
            .is_none_or(|&(_, e, p)| (e, p) != (elem, pos))
    }

    fn points(&mut self) -> &mut Handles {
        self.point_maps.last_mut().expect("a batch begun")
    }

    fn prims(&mut self) -> &mut Handles {
        self.prim_maps.last_mut().expect("a batch begun")
    }

    /// Point `h` (an input point or this batch's handle) as numbered here,
    /// if it exists by now.
    fn point(&self, h: i32) -> Option<u32> {
        let p = if h >= self.base_points {
            self.point_maps.last()?.get(&h)
        } else {
            u32::try_from(h).ok()
        };
        let count = self.base_points as usize + self.positions.len();
        p.filter(|&p| (p as usize) < count)
    }

    /// Adds what was made to `out` (whose points are the input's, so new
    /// ones are numbered as here); returns each batch's point and primitive
    /// handle maps (primitives as their index among the new ones).
    pub fn finish(&mut self, out: &mut Geometry) -> Result<(Vec<Handles>, Vec<Handles>), RunError> {
        if out.num_points() != self.base_points as usize {
            return Err(RunError::Geometry(format!(
                "the output ({} points) is not a copy of input 0 ({} points)",
                out.num_points(),
                self.base_points
            )));
        }
        out.add_points(&self.positions);
        for &(src, id) in &self.copies {
            super::apply::copy_point(out, src as usize, id as usize);
        }
        self.merge_late();
        self.check_sizes()?;
        out.add_polys(&self.shape, &self.flat)
            .map_err(|err| RunError::Geometry(format!("addprim: {err}")))?;
        self.grow_existing(out)?;
        Ok((
            std::mem::take(&mut self.point_maps),
            std::mem::take(&mut self.prim_maps),
        ))
    }

    /// Appends the vertices `addvertex` gave the input's primitives, after
    /// the new primitives (whose vertices keep their numbers' order); a
    /// primitive that takes none (packed) is the element's error.
    fn grow_existing(&self, out: &mut Geometry) -> Result<(), RunError> {
        if self.existing.is_empty() {
            return Ok(());
        }
        for &(prim, _, elem, pos) in &self.existing {
            let kind = out.prim_kinds().get(prim as usize).copied();
            if let Some(kind) =
                kind.filter(|k| !matches!(k, PrimKind::Polygon | PrimKind::Polyline))
            {
                return Err(RunError::At {
                    elem,
                    pos,
                    msg: format!(
                        "addvertex: primitive {prim} is a {} primitive: only polygons and polylines take vertices",
                        kind.name()
                    ),
                });
            }
        }
        let added: Vec<(u32, u32)> = self.existing.iter().map(|&(p, pt, _, _)| (p, pt)).collect();
        ops::append_vertices(out, &added)
            .map_err(|err| RunError::Geometry(format!("addvertex: {err}")))
    }

    /// Moves late vertices into their primitives' runs of `flat`.
    fn merge_late(&mut self) {
        if self.late.is_empty() {
            return;
        }
        let mut flat = Vec::with_capacity(self.flat.len());
        let mut start = 0usize;
        for (k, shape) in self.shape.iter_mut().enumerate() {
            let own = shape.1 as usize;
            flat.extend_from_slice(&self.flat[start..start + own]);
            start += own;
            if let Some(late) = self.late.get(&(k as u32)) {
                flat.extend_from_slice(late);
                shape.1 += late.len() as u32;
            }
        }
        self.flat = flat;
    }

    /// Every primitive at least its kind's minimum size, its element named.
    fn check_sizes(&self) -> Result<(), RunError> {
        for (k, &(closed, n)) in self.shape.iter().enumerate() {
            let least = if closed { 3 } else { 2 };
            if n < least {
                let run = self
                    .made_by
                    .partition_point(|&(first, _, _)| first as usize <= k);
                let (_, elem, pos) = self.made_by[run - 1];
                let what = if closed { "polygon" } else { "polyline" };
                return Err(RunError::At {
                    elem,
                    pos,
                    msg: format!("addprim: a {what} needs at least {least} vertices, got {n}"),
                });
            }
        }
        Ok(())
    }
}
