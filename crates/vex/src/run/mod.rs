//! Running a compiled snippet over geometry: elements go in batches of
//! `LANES`, in parallel; each batch loads its bindings from the input's
//! snapshot columns, runs, and stores the written bindings into the output
//! columns (disjoint slices per batch). Queued effects apply afterwards in
//! element order (see `apply`), so any thread count gives the same bytes.

use std::sync::atomic::{AtomicBool, Ordering};

use rayon::prelude::*;

use geode_geo::{AttribClass, AttribValue, Attribute, Geometry, StringColumn, TypeInfo};

use crate::effect::EffectQueue;
use crate::error::RunError;
use crate::ir::LANES;
use crate::program::{Program, Source};
use crate::ty::attrib_type;
use crate::value::Val;
use exec::Frame;
use world::{Shared, World};

mod apply;
mod budget;
mod build;
mod call;
mod exec;
mod rules;
mod scalar;
mod world;

/// What a run may be told beyond the program and its geometry.
pub struct RunOptions<'a> {
    /// Only these elements (sorted), as the node's group selects them.
    pub group: Option<&'a [u32]>,
    pub cancel: &'a (dyn Fn() -> bool + Sync),
    /// Bytes the run's strings, arrays and queued geometry changes may
    /// hold at once (the node passes `GEODE_MEMORY_MB`'s budget).
    pub memory_budget: u64,
}

/// What a run printed (`printf`), in element order.
#[derive(Debug, Default)]
pub struct RunReport {
    pub printed: Vec<String>,
}

/// A binding's values for loading, resolved once per run.
enum Read<'g> {
    F(&'g [f32], usize),
    I(&'g [i32]),
    S(&'g StringColumn),
    Zero,
    Elem,
    Table(Vec<u32>),
    Const(f64),
    Uniform(Val),
    AI(&'g [Vec<i32>]),
    AF(&'g [Vec<f32>]),
    AV(&'g [Vec<geode_geo::glam::Vec3>]),
    AS(&'g [Vec<String>]),
    /// A column made for the run (a centroid, a point attribute per vertex).
    OwnedF(Vec<f32>, usize),
    OwnedI(Vec<i32>),
}

/// A batch's queued effects and its sinks back.
type BatchOut<'o> = (EffectQueue, Option<build::Builder>, Vec<Sink<'o>>);

/// Where a batch stores a written binding.
enum Sink<'o> {
    F(&'o mut [f32], usize),
    I(&'o mut [i32]),
    /// Gathered, then written once every batch ran (strings, groups).
    Later(Vec<Val>),
}

/// Elements of `class` in `g` (the detail has one).
pub(crate) fn elem_count(g: &Geometry, class: AttribClass) -> usize {
    match class {
        AttribClass::Point => g.num_points(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Detail => 1,
    }
}

/// Runs `p` on `out` (a copy of input 0, whose snapshot is `inputs[0]`).
pub fn run(
    p: &Program,
    out: &mut Geometry,
    inputs: &[Option<&Geometry>],
    opts: &RunOptions,
) -> Result<RunReport, RunError> {
    let snapshot = inputs.first().copied().flatten().ok_or(RunError::NoInput)?;
    let class = p.run_over;
    let total = elem_count(snapshot, class);
    let n = opts.group.map_or(total, <[u32]>::len);
    let reads = reads(p, snapshot, inputs);
    // Written attributes leave the geometry while batches write them.
    let mut taken: Vec<(usize, AttribClass, String, Attribute)> = Vec::new();
    for (b, bind) in p.bindings.iter().enumerate() {
        if let (
            true,
            Source::Attr {
                input: 0,
                class: c,
                attrib,
            },
        ) = (p.written[b], &bind.source)
        {
            let len = elem_count(out, *c);
            let attr = match out.attribs_mut(*c).remove(attrib) {
                Some(a) => a,
                None => {
                    let ty = attrib_type(bind.ty).ok_or(RunError::Unsupported(format!(
                        "@{} of type {}",
                        bind.name, bind.ty
                    )))?;
                    Attribute::new(AttribValue::zero(ty), TypeInfo::for_name(attrib), len)
                }
            };
            taken.push((b, *c, attrib.clone(), attr));
        }
        if let (true, Source::Group(group)) = (p.written[b], &bind.source) {
            // Written as an int column over the run's class (starting from
            // the membership), turned back into the group after the run.
            let flags = group_flags(out, class, group);
            let column = AttribValue::Int(0);
            let mut attr = Attribute::new(column, TypeInfo::None, flags.len());
            if let Some(v) = attr.as_i32_mut() {
                for (x, f) in v.iter_mut().zip(&flags) {
                    *x = *f as i32;
                }
            }
            taken.push((b, class, group.clone(), attr));
        }
    }
    let batches = n.div_ceil(LANES);
    let contiguous = opts.group.is_none();
    let written: Vec<usize> = taken.iter().map(|t| t.0).collect();
    let gathered = !contiguous
        || taken
            .iter()
            .any(|t| t.3.data().as_floats().is_none() && t.3.as_i32().is_none());
    let mut sinks: Vec<Vec<Sink>> = (0..batches)
        .map(|_| Vec::with_capacity(written.len()))
        .collect();
    for (b, _, _, attr) in taken.iter_mut() {
        let later = || (0..batches).map(|_| Sink::Later(Vec::new())).collect();
        let floats = attr.data().as_floats().map(|(_, w)| w);
        let ints = attr.as_i32().is_some();
        if contiguous && (ints || floats == Some(p.bindings[*b].ty.floats())) {
            // Every element is stored whole from the registers (`store`),
            // so a column shared with the input is not copied first.
            attr.discard_values();
        }
        let floats = floats.is_some();
        let chunks: Vec<Sink> = if !contiguous {
            later()
        } else if floats {
            let (f, w) = attr.floats_mut().expect("a float column");
            f.chunks_mut(LANES * w).map(|c| Sink::F(c, w)).collect()
        } else if ints {
            let i = attr.as_i32_mut().expect("an int column");
            i.chunks_mut(LANES).map(Sink::I).collect()
        } else {
            later()
        };
        for (k, c) in chunks.into_iter().enumerate().take(batches) {
            sinks[k].push(c);
        }
    }
    let shared = Shared::new(inputs.to_vec(), opts.memory_budget, &p.ramps);
    // The first batch to fail stops the others: its error is the run's, and
    // what they would still compute (and allocate) is wasted.
    let failed = AtomicBool::new(false);
    let stop = || failed.load(Ordering::Relaxed) || (opts.cancel)();
    let results: Vec<Result<BatchOut, RunError>> = sinks
        .into_par_iter()
        .enumerate()
        .map_init(
            || Frame::new(p),
            |fr, (k, mut sinks)| {
                if stop() {
                    return Err(RunError::Cancelled);
                }
                let lanes: Vec<u32> = match opts.group {
                    Some(g) => g[k * LANES..((k + 1) * LANES).min(n)].to_vec(),
                    None => (k * LANES..((k + 1) * LANES).min(n))
                        .map(|e| e as u32)
                        .collect(),
                };
                let mut world = World::new(&shared, &stop);
                if p.uniform {
                    let count = |g: &Geometry, c| elem_count(g, c) as i32;
                    world.built = Some(build::Builder::new(
                        count(snapshot, AttribClass::Point),
                        count(snapshot, AttribClass::Primitive),
                    ));
                }
                world.elems = lanes;
                fr.set_lanes(world.elems.len());
                load(p, fr, &reads, &world.elems);
                budget::true_up(&shared.budget, fr);
                let ran = exec::run(p, fr, &mut world);
                if ran.is_ok() {
                    let mut moved = 0;
                    for (sink, &b) in sinks.iter_mut().zip(&written) {
                        moved += store(p, fr, b, sink);
                    }
                    // What moved out stays charged: it becomes the output.
                    fr.held = fr.held.saturating_sub(moved);
                }
                budget::release(&shared.budget, fr);
                if ran.is_err() {
                    failed.store(true, Ordering::Relaxed);
                }
                ran.map(|()| (world.effects, world.built, sinks))
            },
        )
        .collect();
    let mut effects = Vec::with_capacity(batches);
    let mut later: Vec<Vec<Option<Vec<Val>>>> = Vec::new();
    // A batch stopped by another's failure reports Cancelled: the failure
    // is the error to report.
    if let Some(e) = results.iter().find_map(|r| match r {
        Err(e) if *e != RunError::Cancelled => Some(e.clone()),
        _ => None,
    }) {
        return Err(e);
    }
    let mut built = None;
    for r in results {
        let (e, b, s) = r?;
        effects.push(e);
        built = built.or(b);
        if gathered {
            later.push(
                s.into_iter()
                    .map(|s| match s {
                        Sink::Later(v) => Some(v),
                        _ => None,
                    })
                    .collect(),
            );
        }
    }
    // Put the columns back, with values gathered for later.
    for (slot, (b, c, name, mut attr)) in taken.into_iter().enumerate() {
        let mut lane_base = 0;
        for (k, batch) in later.iter_mut().enumerate() {
            if let Some(Some(vals)) = batch.get_mut(slot) {
                for (l, v) in vals.drain(..).enumerate() {
                    let e = opts
                        .group
                        .map_or(k * LANES + l, |g| g[lane_base + l] as usize);
                    set_value(&mut attr, e, v);
                }
            }
            lane_base += LANES;
        }
        let is_group = matches!(p.bindings[b].source, Source::Group(_));
        if is_group {
            let members = attr.as_i32().unwrap_or(&[]);
            let group = geode_geo::Group::from_flags(members.iter().map(|&m| m != 0));
            let r = if c == AttribClass::Point {
                out.set_point_group(&name, group)
            } else {
                out.set_prim_group(&name, group)
            };
            r.map_err(|e| RunError::Geometry(e.to_string()))?;
            continue;
        }
        out.attribs_mut(c)
            .insert(&name, attr)
            .map_err(|e| RunError::Geometry(e.to_string()))?;
    }
    let printed = apply::apply(out, snapshot, effects, built)?;
    Ok(RunReport { printed })
}

/// Writes a lane value into an attribute, converting as VEX does.
/// Sets element `e` of `attr` to `v`, converted to the attribute's type;
/// strings and arrays move in, as they may be as large as the budget.
pub fn set_value(attr: &mut Attribute, e: usize, v: Val) {
    let value = match (attr.default_value(), v) {
        (AttribValue::String(_), Val::S(s)) => AttribValue::String(s),
        (AttribValue::String(_), v) => AttribValue::String(v.s().to_string()),
        (AttribValue::IntArray(_), Val::AI(a)) => AttribValue::IntArray(a),
        (AttribValue::IntArray(_), Val::AF(a, _)) => {
            AttribValue::IntArray(a.iter().map(|x| *x as i32).collect())
        }
        (AttribValue::IntArray(_), v) => AttribValue::IntArray(vec![v.i()]),
        (AttribValue::FloatArray(_), Val::AF(a, _)) => AttribValue::FloatArray(a),
        (AttribValue::FloatArray(_), Val::AI(a)) => {
            AttribValue::FloatArray(a.iter().map(|x| *x as f32).collect())
        }
        (AttribValue::FloatArray(_), v) => AttribValue::FloatArray(v.floats().to_vec()),
        (AttribValue::Vec3Array(_), Val::AF(a, _)) => AttribValue::Vec3Array(
            a.chunks_exact(3)
                .map(|c| geode_geo::glam::Vec3::new(c[0], c[1], c[2]))
                .collect(),
        ),
        (AttribValue::Vec3Array(_), v) => {
            AttribValue::Vec3Array(vec![geode_geo::glam::Vec3::from(v.v3())])
        }
        (AttribValue::StringArray(_), Val::AS(a)) => AttribValue::StringArray(a),
        (AttribValue::StringArray(_), v) => AttribValue::StringArray(vec![v.s().to_string()]),
        (AttribValue::Int(_), v) => AttribValue::Int(v.i()),
        (AttribValue::Float(_), v) => AttribValue::Float(v.f()),
        (d, v) => {
            let f = v.floats();
            let g = |k: usize| {
                f.get(k)
                    .copied()
                    .unwrap_or_else(|| if f.len() == 1 { f[0] } else { 0.0 })
            };
            match d {
                AttribValue::Vec2(_) => AttribValue::Vec2([g(0), g(1)].into()),
                AttribValue::Vec3(_) => AttribValue::Vec3([g(0), g(1), g(2)].into()),
                AttribValue::Vec4(_) => AttribValue::Vec4([g(0), g(1), g(2), g(3)].into()),
                AttribValue::Quat(_) => {
                    AttribValue::Quat(geode_geo::glam::Quat::from_xyzw(g(0), g(1), g(2), g(3)))
                }
                AttribValue::Mat4(_) => AttribValue::Mat4(geode_geo::glam::Mat4::from_cols_array(
                    &std::array::from_fn(g),
                )),
                AttribValue::Mat3(_) => AttribValue::Mat3(geode_geo::glam::Mat3::from_cols_array(
                    &std::array::from_fn(g),
                )),
                other => other.clone(),
            }
        }
    };
    // Types match by construction.
    let _ = attr.values_mut().set(e, &value);
}

/// 1 for each element of `class` in group `name` (none if it is missing).
fn group_flags(g: &Geometry, class: AttribClass, name: &str) -> Vec<u32> {
    let n = elem_count(g, class);
    let groups = if class == AttribClass::Point {
        g.point_groups()
    } else {
        g.prim_groups()
    };
    match groups.get(name) {
        Some(grp) => (0..n)
            .map(|i| u32::from(i < grp.len() && grp.contains(i)))
            .collect(),
        None => vec![0; n],
    }
}

fn reads<'g>(
    p: &Program,
    snapshot: &'g Geometry,
    inputs: &[Option<&'g Geometry>],
) -> Vec<Read<'g>> {
    p.bindings
        .iter()
        .map(|b| match &b.source {
            Source::Attr {
                input,
                class,
                attrib,
            } => {
                let Some(a) = inputs
                    .get(*input)
                    .copied()
                    .flatten()
                    .and_then(|g| g.attrib(*class, attrib))
                else {
                    return Read::Zero;
                };
                match a.data() {
                    geode_geo::AttribData::IntArray(v) => return Read::AI(v),
                    geode_geo::AttribData::FloatArray(v) => return Read::AF(v),
                    geode_geo::AttribData::Vec3Array(v) => return Read::AV(v),
                    geode_geo::AttribData::StringArray(v) => return Read::AS(v),
                    _ => {}
                }
                if let Some((f, w)) = a.data().as_floats() {
                    Read::F(f, w)
                } else if let Some(i) = a.as_i32() {
                    Read::I(i)
                } else if let Some(s) = a.as_strings() {
                    Read::S(s)
                } else {
                    Read::Zero
                }
            }
            Source::Detail(name) => {
                match crate::value::read_attrib(snapshot, AttribClass::Detail, name, 0) {
                    Some(v) => Read::Uniform(v),
                    None => Read::Zero,
                }
            }
            Source::Elem => Read::Elem,
            Source::PointOfVertex => Read::Table(snapshot.vertex_points().to_vec()),
            Source::PrimOfVertex => Read::Table(prim_of_each_vertex(snapshot)),
            Source::Group(group) => Read::Table(group_flags(snapshot, p.run_over, group)),
            Source::PrimVertexCount => {
                let offs = snapshot.prim_offsets();
                let count = |prim: usize| offs[prim + 1] - offs[prim];
                Read::Table(if p.run_over == AttribClass::Vertex {
                    let mut t = vec![0u32; snapshot.num_vertices()];
                    for prim in 0..snapshot.num_prims() {
                        t[offs[prim] as usize..offs[prim + 1] as usize].fill(count(prim));
                    }
                    t
                } else {
                    (0..snapshot.num_prims()).map(count).collect()
                })
            }
            Source::Const(c) => Read::Const(*c),
            Source::Centroid => Read::OwnedF(centroids(snapshot), 3),
            Source::Through { class, attrib } => through(snapshot, *class, attrib),
        })
        .collect()
}

/// The average of each primitive's points (0 for a primitive without).
fn centroids(g: &Geometry) -> Vec<f32> {
    let p = g.positions();
    (0..g.num_prims())
        .flat_map(|prim| {
            let points = g.prim_points(prim);
            let sum = points
                .iter()
                .fold(geode_geo::glam::Vec3::ZERO, |s, &q| s + p[q as usize]);
            (sum / points.len().max(1) as f32).to_array()
        })
        .collect()
}

/// The primitive of every vertex (`@primnum` over vertices, primitive
/// attributes read there).
fn prim_of_each_vertex(g: &Geometry) -> Vec<u32> {
    let offs = g.prim_offsets();
    let mut t = vec![0u32; g.num_vertices()];
    for prim in 0..g.num_prims() {
        t[offs[prim] as usize..offs[prim + 1] as usize].fill(prim as u32);
    }
    t
}

/// A point or primitive attribute per vertex.
fn through<'g>(g: &'g Geometry, class: AttribClass, attrib: &str) -> Read<'g> {
    let owner: Vec<u32> = if class == AttribClass::Point {
        g.vertex_points().to_vec()
    } else {
        prim_of_each_vertex(g)
    };
    let Some(a) = g.attrib(class, attrib) else {
        return Read::Zero;
    };
    if let Some((f, w)) = a.data().as_floats() {
        let gathered = owner
            .iter()
            .flat_map(|&o| &f[o as usize * w..(o as usize + 1) * w])
            .copied()
            .collect();
        Read::OwnedF(gathered, w)
    } else if let Some(i) = a.as_i32() {
        Read::OwnedI(owner.iter().map(|&o| i[o as usize]).collect())
    } else {
        Read::Zero
    }
}

/// Spreads interleaved values (`x y z x y z ...`) into one register row per
/// component, in one pass; fixed widths let the compiler unroll it.
fn deinterleave(src: &[f32], w: usize, rows: &mut [f32]) {
    fn fixed<const W: usize>(src: &[f32], rows: &mut [f32]) {
        let (items, _) = src.as_chunks::<W>();
        let rows: [&mut [f32]; W] = split_rows(rows);
        for (l, item) in items.iter().enumerate().take(LANES) {
            for k in 0..W {
                rows[k][l] = item[k];
            }
        }
    }
    match w {
        1 => rows[..src.len()].copy_from_slice(src),
        2 => fixed::<2>(src, rows),
        3 => fixed::<3>(src, rows),
        4 => fixed::<4>(src, rows),
        _ => {
            for (l, item) in src.chunks_exact(w).enumerate() {
                for (k, x) in item.iter().enumerate() {
                    rows[k * LANES + l] = *x;
                }
            }
        }
    }
}

/// `W` disjoint register rows of `LANES` floats.
fn split_rows<const W: usize>(rows: &mut [f32]) -> [&mut [f32]; W] {
    let mut rest = rows;
    std::array::from_fn(|_| {
        let (row, tail) = std::mem::take(&mut rest).split_at_mut(LANES);
        rest = tail;
        row
    })
}

/// The inverse of `deinterleave`: register rows into interleaved values.
fn interleave(rows: &[f32], w: usize, dst: &mut [f32]) {
    fn fixed<const W: usize>(rows: &[f32], dst: &mut [f32]) {
        let (items, _) = dst.as_chunks_mut::<W>();
        let rows: [&[f32]; W] = std::array::from_fn(|k| &rows[k * LANES..(k + 1) * LANES]);
        for (l, item) in items.iter_mut().enumerate().take(LANES) {
            for k in 0..W {
                item[k] = rows[k][l];
            }
        }
    }
    match w {
        1 => {
            let n = dst.len();
            dst.copy_from_slice(&rows[..n]);
        }
        2 => fixed::<2>(rows, dst),
        3 => fixed::<3>(rows, dst),
        4 => fixed::<4>(rows, dst),
        _ => {
            for (l, item) in dst.chunks_exact_mut(w).enumerate() {
                for (k, x) in item.iter_mut().enumerate() {
                    *x = rows[k * LANES + l];
                }
            }
        }
    }
}

/// The elements as a range when they are consecutive.
fn contiguous(elems: &[u32]) -> Option<std::ops::Range<usize>> {
    let (first, last) = (*elems.first()? as usize, *elems.last()? as usize);
    (last + 1 - first == elems.len()).then_some(first..last + 1)
}

/// Fills every binding's registers for the batch's elements.
fn load(p: &Program, fr: &mut Frame, reads: &[Read], elems: &[u32]) {
    for (b, r) in p.bindings.iter().zip(reads) {
        // A column made for the run reads as one of the geometry's.
        let made;
        let r = match r {
            Read::OwnedF(v, w) => {
                made = Read::F(v, *w);
                &made
            }
            Read::OwnedI(v) => {
                made = Read::I(v);
                &made
            }
            other => other,
        };
        let reg = b.loc.reg as usize;
        let width = b.ty.floats();
        match (r, b.ty) {
            (Read::F(col, w), _)
                if width > 0
                    && *w == width
                    && contiguous(elems).is_some_and(|r| r.end * w <= col.len()) =>
            {
                let r = contiguous(elems).expect("checked");
                let rows = &mut fr.f[reg * LANES..(reg + width) * LANES];
                deinterleave(&col[r.start * w..r.end * w], *w, rows);
            }
            (Read::F(col, w), _) if width > 0 => {
                let run = contiguous(elems).filter(|r| r.end * w <= col.len());
                for k in 0..width {
                    let dst = &mut fr.f[(reg + k) * LANES..][..LANES];
                    if k >= *w {
                        dst.fill(0.0);
                    } else if let Some(r) = &run {
                        // One strided pass over a slice: no per-element checks.
                        let src = &col[r.start * w..r.end * w];
                        for (d, s) in dst.iter_mut().zip(src.chunks_exact(*w)) {
                            *d = s[k];
                        }
                    } else {
                        for (l, &e) in elems.iter().enumerate() {
                            dst[l] = col.get(e as usize * w + k).copied().unwrap_or(0.0);
                        }
                    }
                }
            }
            (Read::I(col), crate::ty::Ty::Int) => {
                let dst = &mut fr.i[reg * LANES..][..LANES];
                for (l, &e) in elems.iter().enumerate() {
                    dst[l] = col.get(e as usize).copied().unwrap_or(0);
                }
            }
            (Read::S(col), _) => {
                for (l, &e) in elems.iter().enumerate() {
                    let s = if (e as usize) < col.indices.len() {
                        col.get(e as usize)
                    } else {
                        ""
                    };
                    fr.s[reg * LANES + l].clear();
                    fr.s[reg * LANES + l].push_str(s);
                }
            }
            (Read::Elem, _) | (Read::Table(_), _) => {
                let dst = &mut fr.i[reg * LANES..][..LANES];
                for (l, &e) in elems.iter().enumerate() {
                    dst[l] = match r {
                        Read::Table(t) => t.get(e as usize).map_or(-1, |&x| x as i32),
                        _ => e as i32,
                    };
                }
            }
            (Read::Const(c), t) => {
                if t == crate::ty::Ty::Int {
                    fr.i[reg * LANES..][..LANES].fill(*c as i32);
                } else {
                    for k in 0..width {
                        fr.f[(reg + k) * LANES..][..LANES].fill(*c as f32);
                    }
                }
            }
            (Read::AI(col), _) => {
                for (l, &e) in elems.iter().enumerate() {
                    let dst = &mut fr.ai[reg * LANES + l];
                    dst.clear();
                    dst.extend_from_slice(col.get(e as usize).map_or(&[][..], Vec::as_slice));
                }
            }
            (Read::AF(col), _) => {
                for (l, &e) in elems.iter().enumerate() {
                    let dst = &mut fr.af[reg * LANES + l];
                    dst.clear();
                    dst.extend_from_slice(col.get(e as usize).map_or(&[][..], Vec::as_slice));
                }
            }
            (Read::AV(col), _) => {
                for (l, &e) in elems.iter().enumerate() {
                    let dst = &mut fr.af[reg * LANES + l];
                    dst.clear();
                    if let Some(row) = col.get(e as usize) {
                        dst.extend(row.iter().flat_map(|p| p.to_array()));
                    }
                }
            }
            (Read::AS(col), _) => {
                for (l, &e) in elems.iter().enumerate() {
                    let dst = &mut fr.as_[reg * LANES + l];
                    dst.clear();
                    dst.extend(col.get(e as usize).into_iter().flatten().cloned());
                }
            }
            (Read::Uniform(v), _) => {
                for l in 0..LANES {
                    call::write(fr, b.loc, l, v.clone());
                }
            }
            _ => {
                // Absent attributes read as zero.
                match b.ty {
                    crate::ty::Ty::Int => fr.i[reg * LANES..][..LANES].fill(0),
                    crate::ty::Ty::Str => fr.s[reg * LANES..][..LANES]
                        .iter_mut()
                        .for_each(String::clear),
                    crate::ty::Ty::Array(crate::ty::Elem::Int) => fr.ai[reg * LANES..][..LANES]
                        .iter_mut()
                        .for_each(Vec::clear),
                    crate::ty::Ty::Array(crate::ty::Elem::Str) => fr.as_[reg * LANES..][..LANES]
                        .iter_mut()
                        .for_each(Vec::clear),
                    crate::ty::Ty::Array(_) => fr.af[reg * LANES..][..LANES]
                        .iter_mut()
                        .for_each(Vec::clear),
                    _ => {
                        for k in 0..width {
                            fr.f[(reg + k) * LANES..][..LANES].fill(0.0);
                        }
                    }
                }
            }
        }
    }
}

/// Stores binding `b`'s registers for the batch's lanes into its sink;
/// strings and arrays move out of the frame. Returns the bytes they hold.
fn store(p: &Program, fr: &mut Frame, b: usize, sink: &mut Sink) -> u64 {
    let bind = &p.bindings[b];
    let reg = bind.loc.reg as usize;
    match sink {
        Sink::F(dst, w) if *w == bind.ty.floats() => {
            interleave(
                &fr.f[reg * LANES..(reg + *w) * LANES],
                *w,
                &mut dst[..fr.n * *w],
            );
        }
        Sink::F(dst, w) => {
            let width = bind.ty.floats().min(*w);
            for k in 0..width {
                let src = &fr.f[(reg + k) * LANES..][..fr.n];
                for (d, &x) in dst.chunks_exact_mut(*w).zip(src) {
                    d[k] = x;
                }
            }
        }
        Sink::I(dst) => dst[..fr.n].copy_from_slice(&fr.i[reg * LANES..][..fr.n]),
        Sink::Later(vals) => {
            vals.clear();
            vals.extend((0..fr.n).map(|l| call::take(fr, bind.loc, l)));
            return budget::slots_bytes(vals);
        }
    }
    0
}
