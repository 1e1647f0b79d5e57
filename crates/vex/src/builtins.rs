//! Library functions that run as calls over a batch (per lane): random and
//! noise, geometry reads, queued geometry writes, strings, arrays and the
//! matrix and quaternion functions. Component-wise math is lowered to IR
//! instructions instead (see `lower`).

use std::sync::Arc;

use geode_geo::{AttribClass, AttribData};

use crate::budget::HeapBytes;
use crate::exec::Frame;
use crate::ir::{CallSite, Loc, LANES};
use crate::ty::{Elem, Ty};
use crate::world::{EffectKind, World};
use crate::{noise, Program, RunError};

pub use crate::world::Mode;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    Rand,
    Noise,
    SNoise,
    CurlNoise,
    /// point/prim/vertex/detail: read an attribute of class `0`.
    Read(AttribClass),
    NPoints,
    NPrims,
    NVertices,
    PrimPoints,
    PointPrims,
    Neighbours,
    NeighbourCount,
    /// With a point group as the second argument when true.
    NearPoint(bool),
    NearPoints(bool),
    InGroup(AttribClass),
    /// The half-edge functions (a half-edge is the vertex it leaves from).
    Hedge(HedgeFn),
    HasAttrib(AttribClass),
    SetAttrib(AttribClass),
    AddPoint,
    AddPrim,
    AddVertex,
    RemovePoint,
    RemovePrim,
    SetGroup(AttribClass),
    // Arrays and strings.
    Len,
    Push,
    Pop,
    Insert,
    RemoveIndex,
    Find,
    Sort,
    Reverse,
    Resize,
    ArrayOf,
    IndexGet,
    IndexSet,
    Sprintf,
    Itoa,
    Atof,
    Atoi,
    Concat,
    StartsWith,
    EndsWith,
    Split,
    StrLen,
    // Matrices and quaternions.
    MatMul,
    VecMat,
    Invert,
    Transpose,
    Determinant,
    Ident,
    QMultiply,
    QRotate,
    QConvert,
    Quaternion,
    QuaternionAxis,
    EulerToQuaternion,
    Dihedral,
    Rotate,
    Scale,
    Translate,
    MakeTransform,
    LookAt,
    Print,
}

impl Builtin {
    /// The function's name as errors show it (`push`, `nearpoints`).
    pub fn name(&self) -> String {
        let debug = format!("{self:?}");
        debug
            .split('(')
            .next()
            .unwrap_or(&debug)
            .to_ascii_lowercase()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HedgeFn {
    PointHedge,
    PrimHedge,
    Next,
    SrcPoint,
    DstPoint,
    IsValid,
    Prim,
}

/// A value of one lane, as the per-lane library reads and writes it.
#[derive(Clone, Debug, PartialEq)]
pub enum Val {
    I(i32),
    /// Float slots (1, 2, 3, 4, 9 or 16 used).
    F([f32; 16], u8),
    S(String),
    AF(Vec<f32>, u8),
    AI(Vec<i32>),
    AS(Vec<String>),
}

impl Val {
    pub fn float(x: f32) -> Val {
        Val::vec(&[x])
    }

    pub fn vec(xs: &[f32]) -> Val {
        let mut a = [0.0; 16];
        a[..xs.len()].copy_from_slice(xs);
        Val::F(a, xs.len() as u8)
    }

    pub fn floats(&self) -> &[f32] {
        match self {
            Val::F(a, n) => &a[..*n as usize],
            _ => &[],
        }
    }

    pub fn f(&self) -> f32 {
        match self {
            Val::I(i) => *i as f32,
            Val::F(a, _) => a[0],
            _ => 0.0,
        }
    }

    pub fn i(&self) -> i32 {
        match self {
            Val::I(i) => *i,
            Val::F(a, _) => a[0] as i32,
            _ => 0,
        }
    }

    pub fn s(&self) -> &str {
        match self {
            Val::S(s) => s,
            _ => "",
        }
    }

    pub fn v3(&self) -> [f32; 3] {
        let f = self.floats();
        [
            f.first().copied().unwrap_or(0.0),
            f.get(1).copied().unwrap_or(0.0),
            f.get(2).copied().unwrap_or(0.0),
        ]
    }
}

/// Lane `l` of the value at `loc`.
pub fn read(fr: &Frame, loc: Loc, l: usize) -> Val {
    let r = loc.reg as usize;
    match loc.ty {
        Ty::Int => Val::I(fr.i[r * LANES + l]),
        Ty::Str => Val::S(fr.s[r * LANES + l].clone()),
        Ty::Array(e) => match e {
            Elem::Int => Val::AI(fr.ai[r * LANES + l].clone()),
            Elem::Str => Val::AS(fr.as_[r * LANES + l].clone()),
            _ => Val::AF(fr.af[r * LANES + l].clone(), e.ty().floats() as u8),
        },
        Ty::Void => Val::I(0),
        t => {
            let mut a = [0.0; 16];
            for (k, x) in a.iter_mut().enumerate().take(t.floats()) {
                *x = fr.f[(r + k) * LANES + l];
            }
            Val::F(a, t.floats() as u8)
        }
    }
}

/// Lane `l` of the value at `loc`, moved out where it is a string or an
/// array (the register is left empty).
pub fn take(fr: &mut Frame, loc: Loc, l: usize) -> Val {
    let k = loc.reg as usize * LANES + l;
    match loc.ty {
        Ty::Str => Val::S(std::mem::take(&mut fr.s[k])),
        Ty::Array(Elem::Int) => Val::AI(std::mem::take(&mut fr.ai[k])),
        Ty::Array(Elem::Str) => Val::AS(std::mem::take(&mut fr.as_[k])),
        Ty::Array(e) => Val::AF(std::mem::take(&mut fr.af[k]), e.ty().floats() as u8),
        _ => read(fr, loc, l),
    }
}

/// Stores `v` in lane `l` of `loc`, converting int and float as VEX does.
pub fn write(fr: &mut Frame, loc: Loc, l: usize, v: Val) {
    let r = loc.reg as usize;
    match (loc.ty, v) {
        (Ty::Void, _) => {}
        (Ty::Int, v) => fr.i[r * LANES + l] = v.i(),
        (Ty::Str, Val::S(s)) => fr.s[r * LANES + l] = s,
        (Ty::Str, _) => fr.s[r * LANES + l].clear(),
        (Ty::Array(Elem::Int), Val::AI(a)) => fr.ai[r * LANES + l] = a,
        (Ty::Array(Elem::Str), Val::AS(a)) => fr.as_[r * LANES + l] = a,
        (Ty::Array(_), Val::AF(a, _)) => fr.af[r * LANES + l] = a,
        (Ty::Array(Elem::Int), _) => fr.ai[r * LANES + l].clear(),
        (Ty::Array(Elem::Str), _) => fr.as_[r * LANES + l].clear(),
        (Ty::Array(_), _) => fr.af[r * LANES + l].clear(),
        (t, v) => {
            let n = t.floats();
            match v {
                Val::F(a, m) if m as usize >= n => {
                    for (k, x) in a.iter().enumerate().take(n) {
                        fr.f[(r + k) * LANES + l] = *x;
                    }
                }
                Val::F(a, 1) => {
                    for k in 0..n {
                        fr.f[(r + k) * LANES + l] = a[0];
                    }
                }
                Val::F(a, m) => {
                    for (k, x) in a.iter().enumerate().take(n) {
                        fr.f[(r + k) * LANES + l] = if k < m as usize { *x } else { 0.0 };
                    }
                }
                other => {
                    let x = other.f();
                    for k in 0..n {
                        fr.f[(r + k) * LANES + l] = x;
                    }
                }
            }
        }
    }
}

/// Runs one call over the lanes its mask selects. Each lane's arguments
/// and result are reserved against the run's memory budget before they
/// are copied or made.
pub fn call(
    p: &Program,
    site: &CallSite,
    fr: &mut Frame,
    world: &mut World,
) -> Result<(), RunError> {
    let mut args: Vec<Val> = site
        .consts
        .iter()
        .map(|c| c.clone().unwrap_or(Val::I(0)))
        .collect();
    // Calls on numbers alone (noise, fit, matrices) allocate nothing the
    // budget counts and are quick: they skip the accounting, which would
    // otherwise cost them a third of their time.
    let heap = |t: Ty| matches!(t, Ty::Str | Ty::Array(_));
    let counted = heap(site.out.ty)
        || site.args.iter().any(|a| heap(a.ty))
        || matches!(site.f, Builtin::NearPoints(_) | Builtin::NearPoint(_));
    if !counted {
        for l in 0..fr.n {
            if site.mask.is_some_and(|m| fr.i[m as usize * LANES + l] == 0) {
                continue;
            }
            for (k, a) in site.args.iter().enumerate() {
                if site.consts[k].is_none() {
                    args[k] = read(fr, *a, l);
                }
            }
            let out = lane(p, site, &args, l, world)?;
            write(fr, site.out, l, out);
        }
        return Ok(());
    }
    for l in 0..fr.n {
        if let Some(m) = site.mask {
            if fr.i[m as usize * LANES + l] == 0 {
                continue;
            }
        }
        // A call can be slow (a point cloud query of a million results):
        // each lane's asks whether to stop.
        if (world.cancel)() {
            return Err(RunError::Cancelled);
        }
        let copied: u64 = site
            .args
            .iter()
            .zip(&site.consts)
            .filter(|(_, c)| c.is_none())
            .map(|(a, _)| held_at(fr, *a, l))
            .sum();
        reserve(
            site,
            fr,
            world,
            l,
            &|| format!("copying the arguments of {}", site.f.name()),
            copied,
        )?;
        for (k, a) in site.args.iter().enumerate() {
            if site.consts[k].is_none() {
                args[k] = read(fr, *a, l);
            }
        }
        let predicted =
            crate::library::result_bytes(site.f, &args).or_else(|| query_bytes(site, &args, world));
        if let Some((request, bytes)) = predicted {
            let total = copied.saturating_add(bytes);
            reserve(site, fr, world, l, &|| request.to_string(), total)?;
        }
        let out = lane(p, site, &args, l, world)?;
        let before = held_at(fr, site.out, l);
        write(fr, site.out, l, out);
        let after = held_at(fr, site.out, l);
        crate::budget::charge_write(&world.shared.budget, fr, before, after);
    }
    Ok(())
}

/// Refuses `bytes` more for lane `l` unless they fit the budget once this
/// frame's own account is brought up to date.
fn reserve(
    site: &CallSite,
    fr: &mut Frame,
    world: &World,
    l: usize,
    what: &dyn Fn() -> String,
    bytes: u64,
) -> Result<(), RunError> {
    /// Requests from here on also poll cancellation: making them is slow.
    const LARGE: u64 = 1 << 20;
    if bytes >= LARGE && (world.cancel)() {
        return Err(RunError::Cancelled);
    }
    let budget = &world.shared.budget;
    if crate::budget::reserve(budget, fr, bytes) {
        return Ok(());
    }
    Err(RunError::OverBudget {
        elem: world.elem_of(l),
        pos: site.pos,
        msg: budget.refusal(&what(), bytes),
    })
}

/// What a point cloud query's result will hold: up to the input's points
/// (found as indices, then converted), before the query runs.
fn query_bytes(site: &CallSite, a: &[Val], w: &World) -> Option<(crate::library::Request, u64)> {
    let Builtin::NearPoints(grouped) = site.f else {
        return None;
    };
    let points = w.input(a[0].i()).map_or(0, |g| g.num_points()) as u64;
    let count = a
        .get(3 + usize::from(grouped))
        .map_or(u64::MAX, |c| c.i().max(0) as u64);
    let n = points.min(count);
    // The search heap (distance, index), the indices and their conversion.
    Some((crate::library::Request::NearPoints(n), n * 16))
}

/// Bytes lane `l` of `loc` holds on the heap (strings and arrays).
fn held_at(fr: &Frame, loc: Loc, l: usize) -> u64 {
    let k = loc.reg as usize * LANES + l;
    match loc.ty {
        Ty::Str => fr.s[k].heap_bytes(),
        Ty::Array(Elem::Int) => fr.ai[k].heap_bytes(),
        Ty::Array(Elem::Str) => fr.as_[k].heap_bytes(),
        Ty::Array(_) => fr.af[k].heap_bytes(),
        _ => 0,
    }
}

fn rand_of(seed: &[f32], salt: u64) -> f32 {
    let mut h: u64 = 0x9e37_79b9_7f4a_7c15 ^ salt;
    for s in seed {
        h = (h ^ u64::from(s.to_bits())).wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
    }
    geode_geo::random::unit(h, 0, salt)
}

fn lane(p: &Program, site: &CallSite, a: &[Val], l: usize, w: &mut World) -> Result<Val, RunError> {
    let out_ty = site.out.ty;
    let elem = w.elem_of(l);
    let err = |msg: String| RunError::At {
        elem,
        pos: site.pos,
        msg,
    };
    let over = |msg: String| RunError::OverBudget {
        elem,
        pos: site.pos,
        msg,
    };
    Ok(match site.f {
        Builtin::Rand => {
            let seed: Vec<f32> = a
                .iter()
                .flat_map(|v| match v {
                    Val::I(i) => vec![*i as f32],
                    v => v.floats().to_vec(),
                })
                .collect();
            let n = out_ty.floats().max(1);
            let xs: Vec<f32> = (0..n).map(|k| rand_of(&seed, k as u64)).collect();
            Val::vec(&xs)
        }
        Builtin::Noise | Builtin::SNoise => {
            let pos = a[0].v3();
            let n = out_ty.floats().max(1);
            let xs: Vec<f32> = (0..n)
                .map(|k| {
                    let v = noise::perlin(pos, k as i32);
                    if site.f == Builtin::Noise {
                        0.5 + 0.5 * v
                    } else {
                        v
                    }
                })
                .collect();
            Val::vec(&xs)
        }
        Builtin::CurlNoise => Val::vec(&noise::curl(a[0].v3())),
        Builtin::Read(class) => {
            let g = w.input(a[0].i());
            let name = a[1].s();
            let idx = if class == AttribClass::Detail {
                0
            } else {
                a[2].i()
            };
            match g.and_then(|g| crate::world::read_attrib(g, class, name, idx)) {
                Some(v) => v,
                None => Val::I(0),
            }
        }
        Builtin::NPoints => Val::I(w.input(a[0].i()).map_or(0, |g| g.num_points() as i32)),
        Builtin::NPrims => Val::I(w.input(a[0].i()).map_or(0, |g| g.num_prims() as i32)),
        Builtin::NVertices => Val::I(w.input(a[0].i()).map_or(0, |g| g.num_vertices() as i32)),
        Builtin::PrimPoints => {
            let g = w.input(a[0].i());
            let prim = a[1].i();
            Val::AI(
                g.filter(|g| prim >= 0 && (prim as usize) < g.num_prims())
                    .map_or(Vec::new(), |g| {
                        g.prim_points(prim as usize)
                            .iter()
                            .map(|&p| p as i32)
                            .collect()
                    }),
            )
        }
        Builtin::PointPrims | Builtin::Neighbours | Builtin::NeighbourCount => {
            let input = a[0].i();
            let pt = a[1].i();
            let list: Vec<i32> = match w.topology(input) {
                Some(t) if pt >= 0 && (pt as usize) < t.point_count() => {
                    if site.f == Builtin::PointPrims {
                        t.topo
                            .point_prims(pt as usize)
                            .iter()
                            .map(|&p| p as i32)
                            .collect()
                    } else {
                        t.topo
                            .point_neighbours(pt as usize)
                            .iter()
                            .map(|&p| p as i32)
                            .collect()
                    }
                }
                _ => Vec::new(),
            };
            if site.f == Builtin::NeighbourCount {
                Val::I(list.len() as i32)
            } else {
                Val::AI(list)
            }
        }
        Builtin::NearPoint(grouped) | Builtin::NearPoints(grouped) => {
            let k = usize::from(grouped);
            let group = if grouped { a[1].s() } else { "" };
            let max = a.get(2 + k).map_or(f32::INFINITY, Val::f);
            let single = matches!(site.f, Builtin::NearPoint(_));
            let count = if single {
                1
            } else {
                a.get(3 + k).map_or(usize::MAX, |c| c.i().max(0) as usize)
            };
            let found = w.nearest(a[0].i(), group, a[1 + k].v3(), max, count);
            if single {
                Val::I(found.first().map_or(-1, |&p| p as i32))
            } else {
                Val::AI(found.into_iter().map(|p| p as i32).collect())
            }
        }
        Builtin::InGroup(class) => {
            let g = w.input(a[0].i());
            let idx = a[2].i();
            let groups = g.map(|g| {
                if class == AttribClass::Point {
                    g.point_groups()
                } else {
                    g.prim_groups()
                }
            });
            Val::I(i32::from(
                groups.and_then(|gs| gs.get(a[1].s())).is_some_and(|grp| {
                    idx >= 0 && (idx as usize) < grp.len() && grp.contains(idx as usize)
                }),
            ))
        }
        Builtin::Hedge(f) => {
            let input = a[0].i();
            let topology = || {
                w.topology(input)
                    .map(|t| Arc::clone(&t.topo))
                    .expect("the input exists")
            };
            Val::I(
                w.input(input)
                    .map_or(-1, |g| crate::world::hedge(g, topology, f, a[1].i())),
            )
        }
        Builtin::HasAttrib(class) => Val::I(i32::from(
            w.input(a[0].i())
                .is_some_and(|g| g.attrib(class, a[1].s()).is_some()),
        )),
        Builtin::SetAttrib(class) => {
            // (geo, name, [elem, [vtx,]] value, [mode])
            let (target, vtx, value, mode) = match class {
                AttribClass::Detail => (0, -1, 2, 3),
                AttribClass::Vertex => (a[2].i(), a[3].i(), 4, 5),
                _ => (a[2].i(), -1, 3, 4),
            };
            let mode = match a.get(mode).map(Val::s) {
                None | Some("set") => Mode::Set,
                Some("add") => Mode::Add,
                Some("min") => Mode::Min,
                Some("max") => Mode::Max,
                Some("mult") | Some("multiply") => Mode::Mult,
                Some("append") => Mode::Append,
                Some(other) => {
                    return Err(err(format!(
                        "unknown mode \"{other}\": expected set, add, min, max, mult or append"
                    )))
                }
            };
            w.queue(
                l,
                EffectKind::SetAttr(Box::new(crate::world::SetAttr {
                    class,
                    name: a[1].s().to_string(),
                    target,
                    vtx,
                    value: a[value].clone(),
                    mode,
                })),
            )
            .map_err(over)?;
            Val::I(0)
        }
        Builtin::AddPoint => {
            let from = match &a[1] {
                Val::I(pt) => Some(*pt),
                _ => None,
            };
            let handle = w.new_point();
            w.queue(
                l,
                EffectKind::AddPoint {
                    handle,
                    from,
                    pos: a[1].v3(),
                },
            )
            .map_err(over)?;
            Val::I(handle)
        }
        Builtin::AddPrim => {
            let kind = a[1].s();
            let polyline = match kind {
                "poly" => false,
                "polyline" => true,
                other => {
                    return Err(err(format!(
                        "addprim: unknown type \"{other}\": expected \"poly\" or \"polyline\""
                    )))
                }
            };
            let mut points = crate::world::Points::new();
            for v in &a[2..] {
                match v {
                    Val::AI(v) => v.iter().for_each(|p| points.push(*p)),
                    v => points.push(v.i()),
                }
            }
            let handle = w.new_prim();
            w.queue(
                l,
                EffectKind::AddPrim {
                    handle,
                    polyline,
                    points,
                },
            )
            .map_err(over)?;
            Val::I(handle)
        }
        Builtin::AddVertex => {
            w.queue(
                l,
                EffectKind::AddVertex {
                    prim: a[1].i(),
                    point: a[2].i(),
                },
            )
            .map_err(over)?;
            Val::I(0)
        }
        Builtin::RemovePoint => {
            w.queue(l, EffectKind::RemovePoint { point: a[1].i() })
                .map_err(over)?;
            Val::I(1)
        }
        Builtin::RemovePrim => {
            w.queue(
                l,
                EffectKind::RemovePrim {
                    prim: a[1].i(),
                    and_points: a.get(2).is_some_and(|v| v.i() != 0),
                },
            )
            .map_err(over)?;
            Val::I(1)
        }
        Builtin::SetGroup(class) => {
            let on = a.get(3).is_none_or(|v| v.i() != 0);
            w.queue(
                l,
                EffectKind::SetGroup {
                    class,
                    name: a[1].s().to_string(),
                    target: a[2].i(),
                    on,
                },
            )
            .map_err(over)?;
            Val::I(0)
        }
        Builtin::Print => {
            w.queue(
                l,
                EffectKind::Print(crate::library::sprintf(a[0].s(), &a[1..])),
            )
            .map_err(over)?;
            Val::S(String::new())
        }
        _ => {
            return crate::library::lane(p, site, a, w.cancel).map_err(|stop| match stop {
                crate::library::Stop::Msg(msg) => err(msg),
                crate::library::Stop::Cancelled => RunError::Cancelled,
            })
        }
    })
}

/// An attribute's value at an element, as a lane value.
pub fn attrib_value(data: &AttribData, i: usize) -> Val {
    match data {
        AttribData::Float(v) => Val::float(v[i]),
        AttribData::Int(v) => Val::I(v[i]),
        AttribData::Vec2(v) => Val::vec(&v[i].to_array()),
        AttribData::Vec3(v) => Val::vec(&v[i].to_array()),
        AttribData::Vec4(v) => Val::vec(&v[i].to_array()),
        AttribData::Quat(v) => Val::vec(&v[i].to_array()),
        AttribData::Mat4(v) => Val::vec(&v[i].to_cols_array()),
        AttribData::String(s) => Val::S(s.get(i).to_string()),
        AttribData::IntArray(v) => Val::AI(v[i].clone()),
        AttribData::FloatArray(v) => Val::AF(v[i].clone(), 1),
        AttribData::Mat3(v) => Val::vec(&v[i].to_cols_array()),
        AttribData::Vec3Array(v) => Val::AF(v[i].iter().flat_map(|p| p.to_array()).collect(), 3),
        AttribData::StringArray(v) => Val::AS(v[i].clone()),
    }
}
