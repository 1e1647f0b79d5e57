//! Running a call site over a batch: each selected lane's arguments are
//! read from (or, for strings and arrays used once, moved out of) their
//! registers, the form's lane function runs, outputs and moved arguments go
//! back, and the result is written. Strings and arrays are reserved against
//! the run's memory budget before they are copied or made.

use super::exec::Frame;
use super::world::{LaneHost, World};
use crate::error::RunError;
use crate::ir::{Loc, LANES};
use crate::program::{ArgMode, CallSite, Lane, Program, Stop};
use crate::ty::{Elem, Ty};
use crate::value::{HeapBytes, Val};

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

/// Lane `l` of the value at `loc` into `slot`: a number or vector over
/// the one the slot holds from the last call (a call's arguments are read
/// millions of times in a loop; building each anew costs more than it).
fn read_into(fr: &Frame, loc: Loc, l: usize, slot: &mut Val) {
    let r = loc.reg as usize;
    match (loc.ty, &mut *slot) {
        (Ty::Int, Val::I(x)) => *x = fr.i[r * LANES + l],
        (t, Val::F(a, n)) if t.is_floaty() && usize::from(*n) == t.floats() => {
            for (k, x) in a.iter_mut().enumerate().take(t.floats()) {
                *x = fr.f[(r + k) * LANES + l];
            }
        }
        _ => *slot = read(fr, loc, l),
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

/// Runs call site `call` of `p` over the lanes its mask selects.
pub fn call(p: &Program, call: usize, fr: &mut Frame, world: &mut World) -> Result<(), RunError> {
    let site = &p.calls[call];
    if let Some(num) = site.num {
        call_numbers(site, num, fr);
        return Ok(());
    }
    if let Some(edit) = site.edit {
        return call_edits(site, edit, fr, world);
    }
    // The site's argument list is the frame's, kept call after call (a
    // detail loop makes millions of calls): a literal is copied in again
    // only when a lane function changed it.
    let mut args = std::mem::take(&mut fr.args[call]);
    if args.len() != site.args.len() {
        args = site
            .consts
            .iter()
            .map(|c| c.clone().unwrap_or(Val::I(0)))
            .collect();
    } else {
        for (a, c) in args.iter_mut().zip(&site.consts) {
            if let Some(c) = c.as_ref().filter(|c| *c != a) {
                a.clone_from(c);
            }
        }
    }
    let result = call_lanes(site, &site.modes, &mut args, fr, world);
    fr.args[call] = args;
    result
}

/// A call of numbers (`NumFn`) over the lanes its mask selects: each
/// lane's argument floats gathered from the registers (ints as floats),
/// the function run, its result's floats stored. No value is built.
fn call_numbers(site: &CallSite, num: crate::program::NumFn, fr: &mut Frame) {
    let mut ins = [0.0f32; crate::program::NUM_ARGS];
    let mut out = [0.0f32; 16];
    let width = site.out.ty.floats().clamp(1, 16);
    let o = site.out.reg as usize;
    for l in 0..fr.n {
        if site.mask.is_some_and(|m| fr.i[m as usize * LANES + l] == 0) {
            continue;
        }
        let mut k = 0;
        for a in &site.args {
            let r = a.reg as usize;
            if a.ty == Ty::Int {
                ins[k] = fr.i[r * LANES + l] as f32;
                k += 1;
            } else {
                for c in 0..a.ty.floats() {
                    ins[k] = fr.f[(r + c) * LANES + l];
                    k += 1;
                }
            }
        }
        num(&ins[..k], &mut out[..width]);
        for (c, x) in out[..width].iter().enumerate() {
            fr.f[(o + c) * LANES + l] = *x;
        }
    }
}

/// A call of edits (`EditFn`) over the lanes its mask selects: each
/// lane's ints and floats gathered from the registers, the string from the
/// site's literal, the int result stored. No value is built.
fn call_edits(
    site: &CallSite,
    edit: crate::program::EditFn,
    fr: &mut Frame,
    world: &mut World,
) -> Result<(), RunError> {
    let text = site
        .consts
        .iter()
        .find_map(|c| match c {
            Some(Val::S(s)) => Some(s.as_str()),
            _ => None,
        })
        .unwrap_or("");
    let o = site.out.reg as usize;
    let mut ints = [0i32; crate::program::EDIT_ARGS];
    let mut floats = [0.0f32; crate::program::EDIT_ARGS];
    let mut result = Ok(());
    for l in 0..fr.n {
        if site.mask.is_some_and(|m| fr.i[m as usize * LANES + l] == 0) {
            continue;
        }
        let (mut ni, mut nf) = (0, 0);
        for a in &site.args {
            let r = a.reg as usize;
            match a.ty {
                Ty::Int => {
                    ints[ni] = fr.i[r * LANES + l];
                    ni += 1;
                }
                Ty::Str => {}
                t => {
                    for c in 0..t.floats() {
                        floats[nf] = fr.f[(r + c) * LANES + l];
                        nf += 1;
                    }
                }
            }
        }
        let numbers = crate::program::Numbers {
            ints: &ints[..ni],
            floats: &floats[..nf],
            text,
        };
        world.pos = site.pos;
        let mut host = LaneHost {
            world: &mut *world,
            lane: l,
        };
        match edit(&mut host, &numbers) {
            Ok(x) => fr.i[o * LANES + l] = x,
            Err(stop) => {
                result = Err(stopped(stop, world.elem_of(l), site));
                break;
            }
        }
    }
    result
}

fn call_lanes(
    site: &CallSite,
    modes: &[ArgMode],
    args: &mut [Val],
    fr: &mut Frame,
    world: &mut World,
) -> Result<(), RunError> {
    for l in 0..fr.n {
        if site.mask.is_some_and(|m| fr.i[m as usize * LANES + l] == 0) {
            continue;
        }
        if site.counted {
            // A call can be slow (a point cloud query of a million
            // results): each lane's asks whether to stop.
            if (world.cancel)() {
                return Err(RunError::Cancelled);
            }
            let copied: u64 = site
                .args
                .iter()
                .zip(modes)
                .filter(|(_, m)| **m == ArgMode::Copy)
                .map(|(a, _)| held_at(fr, *a, l))
                .sum();
            reserve(
                site,
                fr,
                world,
                l,
                &|| format!("copying the arguments of {}", site.name),
                copied,
            )?;
        }
        // Copies first: a register an output also names is read before
        // the output moves it.
        for (k, a) in site.args.iter().enumerate() {
            if modes[k] == ArgMode::Copy {
                read_into(fr, *a, l, &mut args[k]);
            }
        }
        let mut before = 0u64;
        for (k, a) in site.args.iter().enumerate() {
            if modes[k] == ArgMode::Move {
                before += held_at(fr, *a, l);
                args[k] = take(fr, *a, l);
            }
        }
        let result = run_lane(site, args, fr, world, l);
        // Moved arguments go back whatever happened, so an error leaves
        // the registers as they were.
        let mut after = 0u64;
        for (k, a) in site.args.iter().enumerate() {
            if modes[k] == ArgMode::Move {
                write(fr, *a, l, std::mem::replace(&mut args[k], Val::I(0)));
                after += held_at(fr, *a, l);
            }
        }
        let out = match result? {
            Ok(out) => out,
            Err(stop) => return Err(stopped(stop, world.elem_of(l), site)),
        };
        if site.counted {
            super::budget::charge_write(&world.shared.budget, fr, before, after);
            let before = held_at(fr, site.out, l);
            write(fr, site.out, l, out);
            let after = held_at(fr, site.out, l);
            super::budget::charge_write(&world.shared.budget, fr, before, after);
        } else {
            match (site.out.ty, &out) {
                // The common results of a loop's calls, without moving them.
                (Ty::Void, _) => {}
                (Ty::Int, Val::I(x)) => fr.i[site.out.reg as usize * LANES + l] = *x,
                _ => write(fr, site.out, l, out),
            }
        }
    }
    Ok(())
}

/// The lane function of lane `l`, after its predicted result is reserved.
fn run_lane(
    site: &CallSite,
    args: &mut [Val],
    fr: &mut Frame,
    world: &mut World,
    l: usize,
) -> Result<Result<Val, Stop>, RunError> {
    if let Some(bytes) = site.bytes {
        let predicted = {
            let host = LaneHost {
                world: &mut *world,
                lane: l,
            };
            bytes(args, &host)
        };
        if let Some((request, bytes)) = predicted {
            reserve(site, fr, world, l, &|| request.to_string(), bytes)?;
        }
    }
    world.pos = site.pos;
    let mut host = LaneHost { world, lane: l };
    let mut lane = Lane {
        host: &mut host,
        out: site.out.ty,
    };
    // The lane's own result goes on as it is: converting it here would
    // copy every value a loop's calls return.
    Ok((site.lane)(&mut lane, args))
}

/// A lane function's stop as the run's error, at its element and call.
fn stopped(stop: Stop, elem: u32, site: &CallSite) -> RunError {
    match stop {
        Stop::Msg(msg) => RunError::At {
            elem,
            pos: site.pos,
            msg,
        },
        Stop::OverBudget(msg) => RunError::OverBudget {
            elem,
            pos: site.pos,
            msg,
        },
        Stop::Cancelled => RunError::Cancelled,
    }
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
    if super::budget::reserve(budget, fr, bytes) {
        return Ok(());
    }
    Err(RunError::OverBudget {
        elem: world.elem_of(l),
        pos: site.pos,
        msg: budget.refusal(&what(), bytes),
    })
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
