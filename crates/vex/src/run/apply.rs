//! Applies the effects batches queued, after every element ran: each
//! batch's effects in (element, order) sequence, batches in order, so the
//! result is the sequential one. New points are appended as they come; new
//! primitives are built after (`addvertex` may still grow them); then
//! attribute and group writes; removals last, since they renumber.
//!
//! An array or string that appends grow is kept out of its column until
//! every write applied (`Growing`): put back after each append, the whole
//! value would be copied out and in again, so n appends to one detail
//! array would cost O(n^2).

use std::collections::HashMap;

use geode_geo::{ops, AttribClass, AttribData, AttribValue, Attribute, Geometry, Group, TypeInfo};

use super::build::Builder;
use super::{elem_count, set_value};
use crate::effect::{Effect, EffectKind, EffectQueue, Mode};
use crate::error::RunError;
use crate::value::Val;

/// Applies `batches` to `out`, with what a one-lane run made as it ran
/// (`built`); returns what `printf` printed, in order.
pub fn apply(
    out: &mut Geometry,
    snapshot: &Geometry,
    mut batches: Vec<EffectQueue>,
    built: Option<Builder>,
) -> Result<Vec<String>, RunError> {
    if batches.iter().all(EffectQueue::is_empty) && built.as_ref().is_none_or(Builder::is_empty) {
        return Ok(Vec::new());
    }
    let (base_points, base_prims) = (snapshot.num_points() as i32, snapshot.num_prims() as i32);
    for b in &mut batches {
        b.sort();
    }
    let mut builder = match built {
        Some(b) => b,
        None => {
            let mut b = Builder::new(base_points, base_prims);
            for (k, batch) in batches.iter().enumerate() {
                if k > 0 {
                    b.begin_batch();
                }
                for e in batch.iter() {
                    b.take(e.elem, e.pos, &e.kind).map_err(|msg| RunError::At {
                        elem: e.elem,
                        pos: e.pos,
                        msg,
                    })?;
                }
            }
            b
        }
    };
    let (point_maps, prim_maps) = builder.finish(out)?;
    let prim_id = |k: usize| base_prims as usize + k;
    let mut printed = Vec::new();
    let mut dead_points: Vec<(usize, bool)> = Vec::new();
    let mut dead_prims: Vec<(usize, bool)> = Vec::new();
    // Group writes: ((point group?, name), members), stored once at the end.
    let mut groups: Vec<((bool, String), Group)> = Vec::new();
    // Whether each attribute the run writes took ints (or floats) first.
    let mut written_as: std::collections::HashMap<(AttribClass, &str), bool> =
        std::collections::HashMap::new();
    let mut growing = Growing::default();
    for (b, batch) in batches.iter().enumerate() {
        let point = |h: i32| -> Option<usize> {
            if h >= base_points {
                point_maps[b].get(&h).map(|p| p as usize)
            } else {
                usize::try_from(h).ok()
            }
        };
        let prim = |h: i32| -> Option<usize> {
            if h >= base_prims {
                prim_maps[b].get(&h).map(|k| prim_id(k as usize))
            } else {
                usize::try_from(h).ok()
            }
        };
        for e in batch.iter() {
            match &e.kind {
                EffectKind::SetAttr(set) => {
                    let crate::effect::SetAttr {
                        class,
                        name,
                        target,
                        vtx,
                        value,
                        mode,
                    } = set.as_ref();
                    let idx = match class {
                        AttribClass::Point => point(*target),
                        AttribClass::Primitive => prim(*target),
                        // A primitive of -1 makes the vertex a linear one.
                        AttribClass::Vertex if *target < 0 => usize::try_from(*vtx).ok(),
                        // ... and so does a vertex of -1 with the primitive.
                        AttribClass::Vertex if *vtx < 0 => usize::try_from(*target).ok(),
                        AttribClass::Vertex => prim(*target).and_then(|p| {
                            let r = out.prim_vertex_range(p);
                            usize::try_from(*vtx)
                                .ok()
                                .filter(|v| *v < r.len())
                                .map(|v| r.start + v)
                        }),
                        AttribClass::Detail => Some(0),
                    };
                    let count = elem_count(out, *class);
                    // "Within a VEX program only one type may be written to
                    // a single attribute ... a literal like 1 will be an
                    // integer write so be ignored if floats were previously
                    // written" (setpointattrib): the run's first write to
                    // an attribute sets whether it takes ints or floats.
                    // (Appends convert into the array, as their pages say.)
                    let int = matches!(value, Val::I(_));
                    let numeric = (int || matches!(value, Val::F(..))) && *mode != Mode::Append;
                    let mixed =
                        numeric && *written_as.entry((*class, name.as_str())).or_insert(int) != int;
                    // Writes to elements that do not exist are ignored, as in VEX.
                    if let Some(i) = idx.filter(|&i| i < count && !mixed) {
                        let target = Target {
                            class: *class,
                            name,
                            i,
                        };
                        set_attr(out, &mut growing, target, value, *mode, e)?;
                    }
                }
                EffectKind::SetGroup {
                    class,
                    name,
                    target,
                    on,
                } => {
                    let (idx, len) = if *class == AttribClass::Point {
                        (point(*target), out.num_points())
                    } else {
                        (prim(*target), out.num_prims())
                    };
                    if let Some(i) = idx.filter(|&i| i < len) {
                        // Gathered per group and stored once after the loop:
                        // storing per write would copy the group each time.
                        let key = (*class == AttribClass::Point, name.clone());
                        let grp = match groups.iter().position(|(k, _)| *k == key) {
                            Some(k) => &mut groups[k].1,
                            None => {
                                let existing = if key.0 {
                                    out.point_groups()
                                } else {
                                    out.prim_groups()
                                };
                                let g = existing
                                    .get(name)
                                    .cloned()
                                    .unwrap_or_else(|| Group::new(len));
                                groups.push((key, g));
                                &mut groups.last_mut().expect("just pushed").1
                            }
                        };
                        grp.set(i, on.unwrap_or(!grp.contains(i)));
                    }
                }
                EffectKind::RemovePoint {
                    point: p,
                    and_prims,
                } => dead_points.extend(point(*p).map(|p| (p, *and_prims))),
                EffectKind::RemovePrim {
                    prim: p,
                    and_points,
                } => dead_prims.extend(prim(*p).map(|p| (p, *and_points))),
                EffectKind::Print(s) => printed.push(s.clone()),
                _ => {}
            }
        }
    }
    growing.store(out);
    for ((points, name), g) in groups {
        let r = if points {
            out.set_point_group(&name, g)
        } else {
            out.set_prim_group(&name, g)
        };
        r.map_err(|e| RunError::Geometry(e.to_string()))?;
    }
    // Removing primitives renumbers none of the points: the points
    // removed and those orphaned go in one pass.
    let orphans = remove_prims(out, &dead_prims);
    if !dead_points.is_empty() || !orphans.is_empty() {
        let n = out.num_points();
        let all = dead_points.iter().map(|d| d.0).chain(orphans);
        let group = Group::from_members(n, all);
        let degenerate = Group::from_members(n, dead_points.iter().filter(|d| d.1).map(|d| d.0));
        ops::remove_points(out, &group, &degenerate);
    }
    Ok(printed)
}

/// `removeprim`: deletes the primitives and gives the points of those
/// removed with their points that no primitive uses any more (SideFX
/// removes the others first, so theirs count as unused).
fn remove_prims(out: &mut Geometry, dead: &[(usize, bool)]) -> Vec<usize> {
    if dead.is_empty() {
        return Vec::new();
    }
    let n = out.num_prims();
    let mut orphans = vec![false; out.num_points()];
    for &(prim, with_points) in dead {
        if with_points {
            for &p in out.prim_points(prim) {
                orphans[p as usize] = true;
            }
        }
    }
    let group = Group::from_members(n, dead.iter().map(|d| d.0));
    ops::delete_prims(out, &group, false);
    for &p in out.vertex_points() {
        orphans[p as usize] = false;
    }
    (0..orphans.len()).filter(|&p| orphans[p]).collect()
}

/// Every attribute (position included) of point `src` onto point `id`.
pub(super) fn copy_point(out: &mut Geometry, src: usize, id: usize) {
    let names: Vec<String> = out
        .attribs(AttribClass::Point)
        .names()
        .map(String::from)
        .collect();
    for name in names {
        let table = out.attribs_mut(AttribClass::Point);
        if let Some(a) = table.get_mut(&name) {
            let v = a.data().get(src);
            let _ = a.values_mut().set(id, &v);
        }
    }
}

fn value_type(v: &Val) -> Option<AttribValue> {
    Some(match v {
        Val::I(_) => AttribValue::Int(0),
        Val::S(_) => AttribValue::String(String::new()),
        Val::F(_, 1) => AttribValue::Float(0.0),
        Val::F(_, 2) => AttribValue::Vec2(Default::default()),
        Val::F(_, 3) => AttribValue::Vec3(Default::default()),
        Val::F(_, 4) => AttribValue::Vec4(Default::default()),
        Val::F(_, 16) => AttribValue::Mat4(Default::default()),
        Val::AI(_) => AttribValue::IntArray(Vec::new()),
        Val::AF(_, 1) => AttribValue::FloatArray(Vec::new()),
        Val::AF(_, 3) => AttribValue::Vec3Array(Vec::new()),
        Val::AS(_) => AttribValue::StringArray(Vec::new()),
        Val::F(_, 9) => AttribValue::Mat3(Default::default()),
        _ => return None,
    })
}

/// The element an attribute write goes to.
#[derive(Clone, Copy)]
struct Target<'n> {
    class: AttribClass,
    name: &'n str,
    i: usize,
}

/// Array and string values that `append` (or `add`) writes are growing,
/// by attribute and element, stored into their columns once at the end:
/// each append extends the value in place (amortised O(1) an element), and
/// later writes to the element combine with it here. Stored in the order
/// first grown, so the result is the same at any thread count.
#[derive(Default)]
struct Growing {
    /// (class, attribute) and its growing elements' slots in `values`.
    attribs: Vec<(AttribClass, String, HashMap<usize, usize>)>,
    /// (attribute in `attribs`, element, value so far).
    values: Vec<(usize, usize, Val)>,
}

impl Growing {
    /// The value growing at `t`, if one is.
    fn get_mut(&mut self, t: Target) -> Option<&mut Val> {
        let (_, _, slots) = self
            .attribs
            .iter()
            .find(|(c, n, _)| *c == t.class && n == t.name)?;
        let k = *slots.get(&t.i)?;
        Some(&mut self.values[k].2)
    }

    /// Starts growing `value` at `t`.
    fn insert(&mut self, t: Target, value: Val) {
        let a = match self
            .attribs
            .iter()
            .position(|(c, n, _)| *c == t.class && n == t.name)
        {
            Some(a) => a,
            None => {
                self.attribs
                    .push((t.class, t.name.to_string(), HashMap::new()));
                self.attribs.len() - 1
            }
        };
        self.attribs[a].2.insert(t.i, self.values.len());
        self.values.push((a, t.i, value));
    }

    /// Stores every grown value into its column.
    fn store(self, out: &mut Geometry) {
        for (a, i, value) in self.values {
            let (class, name, _) = &self.attribs[a];
            if let Some(attr) = out.attribs_mut(*class).get_mut(name) {
                set_value(attr, i, value);
            }
        }
    }
}

/// Whether a column's elements are arrays or strings: values appends grow.
fn grows(data: &AttribData) -> bool {
    matches!(
        data,
        AttribData::String(_)
            | AttribData::IntArray(_)
            | AttribData::FloatArray(_)
            | AttribData::Vec3Array(_)
            | AttribData::StringArray(_)
    )
}

/// Writes `value` to `t` (the attribute created from the value when
/// missing), combined with what is there by `mode`.
fn set_attr(
    out: &mut Geometry,
    growing: &mut Growing,
    t: Target,
    value: &Val,
    mode: Mode,
    by: &Effect,
) -> Result<(), RunError> {
    if let Some(v) = growing.get_mut(t) {
        combine_in_place(v, value, mode);
        return Ok(());
    }
    let len = elem_count(out, t.class);
    let table = out.attribs_mut(t.class);
    if table.get(t.name).is_none() {
        let zero = value_type(value).ok_or_else(|| RunError::At {
            elem: by.elem,
            pos: by.pos,
            msg: format!("cannot create attribute '{}' from this value", t.name),
        })?;
        table
            .insert(t.name, Attribute::new(zero, TypeInfo::None, len))
            .map_err(|e| RunError::Geometry(e.to_string()))?;
    }
    let attr = table.get_mut(t.name).expect("just made");
    let mut old = crate::value::attrib_value(attr.data(), t.i);
    if matches!(mode, Mode::Append | Mode::Add) && grows(attr.data()) {
        combine_in_place(&mut old, value, mode);
        growing.insert(t, old);
        return Ok(());
    }
    set_value(attr, t.i, combine(&old, value, mode));
    Ok(())
}

/// `old = old (mode) v`: appends (and adds) extend an array or string in
/// place, converting `v` to its elements; the rest as `combine`.
fn combine_in_place(old: &mut Val, v: &Val, mode: Mode) {
    if !matches!(mode, Mode::Append | Mode::Add) {
        *old = combine(old, v, mode);
        return;
    }
    match old {
        Val::AI(a) => match v {
            Val::AI(x) => a.extend_from_slice(x),
            Val::AF(x, _) => a.extend(x.iter().map(|f| *f as i32)),
            x => a.push(x.i()),
        },
        Val::AS(a) => match v {
            Val::AS(x) => a.extend_from_slice(x),
            x => a.push(x.s().to_string()),
        },
        Val::AF(a, w) => extend_floats(a, (*w).max(1) as usize, v),
        Val::S(a) => a.push_str(v.s()),
        _ => *old = combine(old, v, mode),
    }
}

/// Appends `v` to a float array of `w` floats an element: arrays as they
/// are, a number as a whole element of it (as `push` converts), a vector
/// as its floats. The column keeps whole elements only (see `set_value`),
/// so a partial one is dropped here as storing would drop it.
fn extend_floats(a: &mut Vec<f32>, w: usize, v: &Val) {
    match v {
        Val::AF(x, _) => a.extend_from_slice(x),
        Val::AI(x) => a.extend(x.iter().map(|i| *i as f32)),
        Val::I(_) => a.extend(std::iter::repeat_n(v.f(), w)),
        Val::F(_, 1) => a.extend(std::iter::repeat_n(v.f(), w)),
        x => a.extend_from_slice(x.floats()),
    }
    a.truncate(a.len() - a.len() % w);
}

/// `old (mode) value`, per component; appends as `combine_in_place`.
fn combine(old: &Val, v: &Val, mode: Mode) -> Val {
    let op = |a: f32, b: f32| match mode {
        Mode::Add => a + b,
        Mode::Min => a.min(b),
        Mode::Max => a.max(b),
        Mode::Mult => a * b,
        Mode::Set | Mode::Append => b,
    };
    match (old, v, mode) {
        (_, _, Mode::Set) => v.clone(),
        (Val::AI(_) | Val::AS(_) | Val::AF(..) | Val::S(_), _, Mode::Append | Mode::Add) => {
            let mut grown = old.clone();
            combine_in_place(&mut grown, v, mode);
            grown
        }
        (Val::I(a), b, _) => Val::I(op(*a as f32, b.f()) as i32),
        (Val::F(a, n), b, _) => {
            let f = b.floats();
            let xs: Vec<f32> = (0..*n as usize)
                .map(|k| op(a[k], f.get(k).copied().unwrap_or_else(|| b.f())))
                .collect();
            Val::vec(&xs)
        }
        _ => v.clone(),
    }
}
