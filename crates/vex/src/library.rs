//! Per-lane library functions without geometry: arrays, strings, matrices
//! and quaternions. VEX matrices are row-major with row vectors (`v * m`);
//! their 9 or 16 slots equal glam's column-major arrays of the same
//! transform, so `v * m` is glam's `m * v` and `a * b` is glam's `b * a`.

use geode_geo::glam::{EulerRot, Mat3, Mat4, Quat, Vec3, Vec4};

use crate::budget::HeapBytes;
use crate::builtins::{Builtin, Val};
use crate::ir::CallSite;
use crate::ty::{Elem, Ty};
use crate::Program;

fn m3(v: &Val) -> Mat3 {
    let f = v.floats();
    if f.len() == 16 {
        return Mat3::from_mat4(m4(v));
    }
    let mut a = [0.0; 9];
    a[..f.len().min(9)].copy_from_slice(&f[..f.len().min(9)]);
    Mat3::from_cols_array(&a)
}

fn m4(v: &Val) -> Mat4 {
    let f = v.floats();
    if f.len() == 9 {
        return Mat4::from_mat3(m3(v));
    }
    let mut a = [0.0; 16];
    a[..f.len().min(16)].copy_from_slice(&f[..f.len().min(16)]);
    Mat4::from_cols_array(&a)
}

fn v3(v: &Val) -> Vec3 {
    Vec3::from_array(v.v3())
}

fn q(v: &Val) -> Quat {
    let f = v.floats();
    let g = |k: usize| f.get(k).copied().unwrap_or(0.0);
    Quat::from_xyzw(g(0), g(1), g(2), g(3))
}

fn of_quat(q: Quat) -> Val {
    Val::vec(&q.to_array())
}

fn of_mat(out: Ty, m: Mat4) -> Val {
    if out == Ty::Mat3 {
        Val::vec(&Mat3::from_mat4(m).to_cols_array())
    } else {
        Val::vec(&m.to_cols_array())
    }
}

/// VEX's rotation orders (`XFORM_XYZ` = 0 ...) as glam's extrinsic Euler orders.
fn euler_order(order: i32) -> EulerRot {
    // VEX's xyz means rotate about x first: in glam's intrinsic naming the
    // matrix is Rz * Ry * Rx, which is EulerRot::ZYX with angles (z, y, x).
    match order {
        1 => EulerRot::YZX, // xzy
        2 => EulerRot::ZXY, // yxz
        3 => EulerRot::XZY, // yzx
        4 => EulerRot::YXZ, // zxy
        5 => EulerRot::XYZ, // zyx
        _ => EulerRot::ZYX, // xyz
    }
}

/// Euler angles (radians, VEX order code) as a quaternion.
pub fn euler_quat(r: Vec3, order: i32) -> Quat {
    let rot = euler_order(order);
    // glam's from_euler(order, a, b, c) applies the first axis named last.
    let pick = |c: char| match c {
        'x' => r.x,
        'y' => r.y,
        _ => r.z,
    };
    let names = match rot {
        EulerRot::ZYX => "zyx",
        EulerRot::YZX => "yzx",
        EulerRot::ZXY => "zxy",
        EulerRot::XZY => "xzy",
        EulerRot::YXZ => "yxz",
        _ => "xyz",
    };
    let c: Vec<char> = names.chars().collect();
    Quat::from_euler(rot, pick(c[0]), pick(c[1]), pick(c[2]))
}

fn arr_len(v: &Val) -> usize {
    match v {
        Val::AI(a) => a.len(),
        Val::AS(a) => a.len(),
        Val::AF(a, w) => a.len() / (*w).max(1) as usize,
        _ => 0,
    }
}

/// Resolves a VEX index (negative counts from the end).
fn index(i: i32, len: usize) -> Option<usize> {
    let i = if i < 0 {
        len as i64 + i as i64
    } else {
        i as i64
    };
    (0..len as i64).contains(&i).then_some(i as usize)
}

fn elem_get(v: &Val, i: usize) -> Val {
    match v {
        Val::AI(a) => Val::I(a[i]),
        Val::AS(a) => Val::S(a[i].clone()),
        Val::AF(a, w) => Val::vec(&a[i * *w as usize..(i + 1) * *w as usize]),
        _ => Val::I(0),
    }
}

fn empty_like(out: Ty) -> Val {
    match out {
        Ty::Array(Elem::Int) => Val::AI(Vec::new()),
        Ty::Array(Elem::Str) => Val::AS(Vec::new()),
        Ty::Array(e) => Val::AF(Vec::new(), e.ty().floats() as u8),
        Ty::Str => Val::S(String::new()),
        Ty::Int => Val::I(0),
        t => Val::vec(&vec![0.0; t.floats().max(1)]),
    }
}

/// Appends `x` (converted to the array's element type) to array `a`.
fn push(a: &mut Val, x: &Val) {
    match a {
        Val::AI(v) => v.push(x.i()),
        Val::AS(v) => v.push(x.s().to_string()),
        Val::AF(v, w) => {
            let f = x.floats();
            for k in 0..*w as usize {
                v.push(if f.len() == 1 {
                    f[0]
                } else {
                    f.get(k).copied().unwrap_or(x.f())
                });
            }
        }
        _ => {}
    }
}

fn remove_at(a: &mut Val, i: usize) {
    match a {
        Val::AI(v) => {
            v.remove(i);
        }
        Val::AS(v) => {
            v.remove(i);
        }
        Val::AF(v, w) => {
            let w = *w as usize;
            v.drain(i * w..(i + 1) * w);
        }
        _ => {}
    }
}

/// Why a library call stopped: its element's error, or cancellation.
pub enum Stop {
    Msg(String),
    Cancelled,
}

impl From<String> for Stop {
    fn from(msg: String) -> Stop {
        Stop::Msg(msg)
    }
}

/// Elements a growing fill writes between cancellation polls.
const FILL_CHUNK: usize = 1 << 22;

/// Sets `v`'s length to `n`, padding with `fill`: the memory is asked of
/// the allocator first (a refusal is an error, not an abort) and a long
/// fill polls `cancel`.
fn grow<T: Clone>(
    v: &mut Vec<T>,
    n: usize,
    fill: T,
    cancel: &dyn Fn() -> bool,
) -> Result<(), Stop> {
    if n <= v.len() {
        v.truncate(n);
        return Ok(());
    }
    v.try_reserve_exact(n - v.len()).map_err(|_| {
        Stop::Msg(format!(
            "the system could not allocate an array of {n} elements"
        ))
    })?;
    while v.len() < n {
        let to = (v.len() + FILL_CHUNK).min(n);
        v.resize(to, fill.clone());
        if to < n && cancel() {
            return Err(Stop::Cancelled);
        }
    }
    Ok(())
}

/// Shortens an array to `n` elements, or with `pad` also lengthens it.
fn truncate(a: &mut Val, n: usize, pad: bool, cancel: &dyn Fn() -> bool) -> Result<(), Stop> {
    match a {
        Val::AI(v) => grow(v, if pad { n } else { n.min(v.len()) }, 0, cancel),
        Val::AS(v) => grow(
            v,
            if pad { n } else { n.min(v.len()) },
            String::new(),
            cancel,
        ),
        Val::AF(v, w) => {
            let w = *w as usize;
            let len = if pad {
                n.saturating_mul(w)
            } else {
                (n * w).min(v.len())
            };
            grow(v, len, 0.0, cancel)
        }
        _ => Ok(()),
    }
}

/// What a call asks the budget for, in the words a refusal uses; made
/// on every call that grows something, so words are only formatted when
/// the request is refused.
#[derive(Clone, Copy, Debug)]
pub enum Request {
    Resize(u64),
    IndexSet(i32),
    Array(u64),
    Concat(u64),
    Split(u64),
    Format(u64),
    NearPoints(u64),
}

impl std::fmt::Display for Request {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Request::Resize(n) => write!(f, "resize to {n} elements"),
            Request::IndexSet(i) => write!(f, "setting element {i}"),
            Request::Array(n) => write!(f, "an array of {n} elements"),
            Request::Concat(n) => write!(f, "a string of {n} bytes"),
            Request::Split(n) => write!(f, "splitting a string of {n} bytes"),
            Request::Format(n) => write!(f, "formatting a string of {n} bytes"),
            Request::NearPoints(n) => write!(f, "nearpoints finding up to {n} points"),
        }
    }
}

/// What a call's result will hold on the heap, where that can exceed
/// what its arguments hold (growing arrays, joining and formatting
/// strings), with the request a refusal names.
pub fn result_bytes(f: Builtin, a: &[Val]) -> Option<(Request, u64)> {
    let held = |v: &Val| v.heap_bytes();
    let slot = |v: &Val| match v {
        Val::AF(_, w) => 4 * u64::from(*w),
        Val::AI(_) => 4,
        Val::AS(_) => std::mem::size_of::<String>() as u64,
        _ => 0,
    };
    match f {
        Builtin::Resize => {
            let n = a.get(1)?.i().max(0) as u64;
            Some((Request::Resize(n), held(&a[0]).max(n * slot(&a[0]))))
        }
        Builtin::IndexSet => {
            let i = a.get(1)?.i();
            let n = (arr_len(&a[0]) as u64).max(u64::try_from(i).map_or(0, |i| i + 1));
            let extra = held(&a[2]);
            Some((
                Request::IndexSet(i),
                held(&a[0]).max(n * slot(&a[0])) + extra,
            ))
        }
        Builtin::Push | Builtin::Insert | Builtin::ArrayOf => {
            let elems: u64 = a.iter().map(|v| arr_len(v).max(1) as u64).sum();
            let bytes = a.iter().map(|v| held(v) + 16).sum();
            Some((Request::Array(elems), bytes))
        }
        Builtin::Concat => {
            let total: u64 = a.iter().map(|v| v.s().len() as u64).sum();
            Some((Request::Concat(total), total))
        }
        Builtin::Split => {
            // At most a piece per two characters, each a string's slot and
            // the smallest allocation.
            let len = a[0].s().len() as u64;
            let pieces = len / 2 + 1;
            let bytes = pieces * (std::mem::size_of::<String>() as u64 + 16) + len;
            Some((Request::Split(len), bytes))
        }
        Builtin::Sprintf | Builtin::Print => {
            let args: u64 = a.iter().map(|v| held(v) + 32).sum();
            let total = sprintf_bytes(a[0].s()).saturating_add(args);
            Some((Request::Format(total), total))
        }
        _ => None,
    }
}

/// An upper bound on what `sprintf`'s widths and precisions add: every
/// number in a conversion's flags, twice (a conversion is formatted, then
/// copied into the result).
fn sprintf_bytes(fmt: &str) -> u64 {
    let mut total = fmt.len() as u64;
    let mut number: u64 = 0;
    let mut in_spec = false;
    for c in fmt.chars() {
        match (in_spec, c) {
            (false, '%') => in_spec = true,
            (true, '0'..='9') => {
                number = number
                    .saturating_mul(10)
                    .saturating_add(u64::from(c as u8 - b'0'));
            }
            (true, '.' | '-' | '+' | ' ' | '#') => {
                total = total.saturating_add(number.saturating_mul(2));
                number = 0;
            }
            (true, _) => {
                total = total.saturating_add(number.saturating_mul(2));
                number = 0;
                in_spec = false;
            }
            _ => {}
        }
    }
    total.saturating_add(number.saturating_mul(2))
}

fn fmt_val(v: &Val) -> String {
    match v {
        Val::I(i) => i.to_string(),
        Val::S(s) => s.clone(),
        Val::F(a, 1) => fmt_float(a[0]),
        Val::F(a, n) => format!(
            "{{{}}}",
            a[..*n as usize]
                .iter()
                .map(|x| fmt_float(*x))
                .collect::<Vec<_>>()
                .join(",")
        ),
        Val::AI(a) => format!(
            "{{{}}}",
            a.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(",")
        ),
        Val::AS(a) => format!(
            "{{{}}}",
            a.iter()
                .map(|x| format!("'{x}'"))
                .collect::<Vec<_>>()
                .join(",")
        ),
        Val::AF(a, w) => {
            let items: Vec<String> = a
                .chunks((*w).max(1) as usize)
                .map(|c| {
                    if c.len() == 1 {
                        fmt_float(c[0])
                    } else {
                        fmt_val(&Val::vec(c))
                    }
                })
                .collect();
            format!("{{{}}}", items.join(","))
        }
    }
}

/// `%g`-like shortest form, as VEX prints floats.
fn fmt_float(x: f32) -> String {
    let s = format!("{x}");
    s
}

/// C-style formatting of `%d %i %f %g %s %c %x %%` with flags, width and
/// precision; vectors print as `{x,y,z}`.
pub fn sprintf(fmt: &str, args: &[Val]) -> String {
    let mut out = String::new();
    let mut it = fmt.chars().peekable();
    let mut next = args.iter();
    while let Some(c) = it.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut spec = String::new();
        while let Some(&d) = it.peek() {
            if "-+ 0#".contains(d) || d.is_ascii_digit() || d == '.' {
                spec.push(d);
                it.next();
            } else {
                break;
            }
        }
        let Some(conv) = it.next() else {
            break;
        };
        if conv == '%' {
            out.push('%');
            continue;
        }
        let arg = next.next().cloned().unwrap_or(Val::I(0));
        let left = spec.starts_with('-');
        let zero = spec.starts_with('0');
        let plus = spec.contains('+');
        let spec_digits = spec.trim_start_matches(['-', '+', ' ', '0', '#']);
        let (width, prec) = match spec_digits.split_once('.') {
            Some((w, p)) => (w.parse::<usize>().unwrap_or(0), p.parse::<usize>().ok()),
            None => (spec_digits.parse::<usize>().unwrap_or(0), None),
        };
        let one = |x: f32| -> String {
            match conv {
                'd' | 'i' => format!("{}{}", if plus && x >= 0.0 { "+" } else { "" }, x as i64),
                'x' => format!("{:x}", x as i64),
                'f' | 'F' => format!(
                    "{}{:.*}",
                    if plus && x >= 0.0 { "+" } else { "" },
                    prec.unwrap_or(6),
                    x
                ),
                'e' => format!("{:.*e}", prec.unwrap_or(6), x),
                'c' => char::from_u32(x as u32)
                    .map(String::from)
                    .unwrap_or_default(),
                _ => fmt_float(x),
            }
        };
        let body = match (&arg, conv) {
            (Val::S(s), _) => s.clone(),
            (Val::I(i), _) => one(*i as f32),
            (Val::F(a, 1), _) => one(a[0]),
            (Val::F(a, n), _) => format!(
                "{{{}}}",
                a[..*n as usize]
                    .iter()
                    .map(|x| one(*x))
                    .collect::<Vec<_>>()
                    .join(",")
            ),
            (v, _) => fmt_val(v),
        };
        let body = match (conv, &arg) {
            ('d' | 'i', Val::I(i)) => format!("{}{}", if plus && *i >= 0 { "+" } else { "" }, i),
            _ => body,
        };
        // Padding goes straight into the result: a wide field is one
        // allocation, not two.
        let pad = width.saturating_sub(body.chars().count());
        let fill = |out: &mut String, c: char| out.extend(std::iter::repeat_n(c, pad));
        if left {
            out.push_str(&body);
            fill(&mut out, ' ');
        } else if zero && !matches!(arg, Val::S(_)) {
            let (sign, digits) = body.split_at(usize::from(body.starts_with(['-', '+'])));
            out.push_str(sign);
            fill(&mut out, '0');
            out.push_str(digits);
        } else {
            fill(&mut out, ' ');
            out.push_str(&body);
        }
    }
    out
}

/// One lane of a library call; errors are the message for the element.
pub fn lane(
    _p: &Program,
    site: &CallSite,
    a: &[Val],
    cancel: &dyn Fn() -> bool,
) -> Result<Val, Stop> {
    let out = site.out.ty;
    Ok(match site.f {
        Builtin::Len => Val::I(match &a[0] {
            Val::S(s) => s.chars().count(),
            Val::F(_, n) => *n as usize,
            v => arr_len(v),
        } as i32),
        Builtin::StrLen => Val::I(a[0].s().chars().count() as i32),
        Builtin::Push => {
            let mut arr = a[0].clone();
            for x in &a[1..] {
                match x {
                    Val::AI(_) | Val::AS(_) | Val::AF(..) => {
                        for i in 0..arr_len(x) {
                            push(&mut arr, &elem_get(x, i));
                        }
                    }
                    x => push(&mut arr, x),
                }
            }
            arr
        }
        Builtin::Pop => {
            let n = arr_len(&a[0]);
            if n == 0 {
                empty_like(out)
            } else {
                elem_get(&a[0], n - 1)
            }
        }
        Builtin::Insert => {
            let mut arr = a[0].clone();
            let n = arr_len(&arr);
            let at = a[1].i().clamp(0, n as i32) as usize;
            let mut tail = arr.clone();
            truncate(&mut arr, at, false, cancel)?;
            push(&mut arr, &a[2]);
            for i in at..n {
                push(&mut arr, &elem_get(&tail, i));
            }
            tail = arr;
            tail
        }
        Builtin::RemoveIndex => {
            let mut arr = a[0].clone();
            if let Some(i) = index(a[1].i(), arr_len(&arr)) {
                remove_at(&mut arr, i);
            }
            arr
        }
        Builtin::Resize => {
            let mut arr = a[0].clone();
            truncate(&mut arr, a[1].i().max(0) as usize, true, cancel)?;
            arr
        }
        Builtin::Find => {
            let n = arr_len(&a[0]);
            if let Val::S(hay) = &a[0] {
                Val::I(
                    hay.find(a[1].s())
                        .map_or(-1, |b| hay[..b].chars().count() as i32),
                )
            } else {
                let found = (0..n).find(|&i| {
                    let e = elem_get(&a[0], i);
                    match (&e, &a[1]) {
                        (Val::I(x), y) => *x == y.i(),
                        (Val::S(x), y) => x == y.s(),
                        (x, y) => {
                            x.floats() == y.floats() || (x.floats().len() == 1 && x.f() == y.f())
                        }
                    }
                });
                Val::I(found.map_or(-1, |i| i as i32))
            }
        }
        Builtin::Sort => match &a[0] {
            Val::AI(v) => {
                let mut v = v.clone();
                v.sort_unstable();
                Val::AI(v)
            }
            Val::AS(v) => {
                let mut v = v.clone();
                v.sort();
                Val::AS(v)
            }
            Val::AF(v, 1) => {
                let mut v = v.clone();
                v.sort_by(|x, y| x.total_cmp(y));
                Val::AF(v, 1)
            }
            other => other.clone(),
        },
        Builtin::Reverse => match &a[0] {
            Val::S(s) => Val::S(s.chars().rev().collect()),
            v => {
                let n = arr_len(v);
                let mut r = empty_like(out);
                for i in (0..n).rev() {
                    push(&mut r, &elem_get(v, i));
                }
                r
            }
        },
        Builtin::ArrayOf => {
            let mut r = empty_like(out);
            for x in a {
                push(&mut r, x);
            }
            r
        }
        Builtin::IndexGet => {
            if let Val::S(s) = &a[0] {
                let n = s.chars().count();
                return Ok(Val::S(
                    index(a[1].i(), n)
                        .and_then(|i| s.chars().nth(i))
                        .map(String::from)
                        .unwrap_or_default(),
                ));
            }
            match index(a[1].i(), arr_len(&a[0])) {
                Some(i) => elem_get(&a[0], i),
                None => empty_like(out),
            }
        }
        Builtin::IndexSet => {
            // (array, index, value): writing past the end grows the array.
            let mut arr = a[0].clone();
            let n = arr_len(&arr);
            let i = a[1].i();
            let i = if i < 0 { n as i32 + i } else { i };
            if i >= 0 {
                let i = i as usize;
                if i >= n {
                    truncate(&mut arr, i + 1, true, cancel)?;
                }
                match &mut arr {
                    Val::AI(v) => v[i] = a[2].i(),
                    Val::AS(v) => v[i] = a[2].s().to_string(),
                    Val::AF(v, w) => {
                        let w = *w as usize;
                        let f = a[2].floats();
                        for k in 0..w {
                            v[i * w + k] = if f.len() == 1 {
                                f[0]
                            } else {
                                f.get(k).copied().unwrap_or(a[2].f())
                            };
                        }
                    }
                    _ => {}
                }
            }
            arr
        }
        Builtin::Sprintf => Val::S(sprintf(a[0].s(), &a[1..])),
        Builtin::Itoa => Val::S(a[0].i().to_string()),
        Builtin::Atof => Val::float(
            a[0].s()
                .trim()
                .parse::<f32>()
                .unwrap_or_else(|_| leading_number(a[0].s())),
        ),
        Builtin::Atoi => Val::I(
            a[0].s()
                .trim()
                .parse::<i32>()
                .unwrap_or_else(|_| leading_number(a[0].s()) as i32),
        ),
        Builtin::Concat => Val::S(a.iter().map(|v| v.s()).collect()),
        Builtin::StartsWith => Val::I(i32::from(a[0].s().starts_with(a[1].s()))),
        Builtin::EndsWith => Val::I(i32::from(a[0].s().ends_with(a[1].s()))),
        Builtin::Split => {
            let s = a[0].s();
            let pieces: Box<dyn Iterator<Item = &str>> = match a.get(1).map(Val::s) {
                Some(sep) if !sep.is_empty() => {
                    Box::new(s.split(|c| sep.contains(c)).filter(|p| !p.is_empty()))
                }
                _ => Box::new(s.split_whitespace()),
            };
            let mut parts = Vec::new();
            for (k, piece) in pieces.enumerate() {
                if k % FILL_CHUNK == FILL_CHUNK - 1 && cancel() {
                    return Err(Stop::Cancelled);
                }
                parts.push(piece.to_string());
            }
            Val::AS(parts)
        }
        Builtin::MatMul => {
            // VEX a * b (a applied first).
            let (x, y) = (m4(&a[0]), m4(&a[1]));
            of_mat(out, y * x)
        }
        Builtin::VecMat => {
            let v = a[0].floats();
            match a[1].floats().len() {
                9 => Val::vec(&(m3(&a[1]) * v3(&a[0])).to_array()),
                _ if v.len() == 4 => Val::vec(&(m4(&a[1]) * Vec4::from_slice(v)).to_array()),
                _ => Val::vec(&m4(&a[1]).transform_point3(v3(&a[0])).to_array()),
            }
        }
        Builtin::Invert => match out {
            Ty::Mat3 => {
                let m = m3(&a[0]);
                if m.determinant() == 0.0 {
                    a[0].clone()
                } else {
                    Val::vec(&m.inverse().to_cols_array())
                }
            }
            Ty::Float => Val::float(if a[0].f() == 0.0 { 0.0 } else { 1.0 / a[0].f() }),
            _ => {
                let m = m4(&a[0]);
                if m.determinant() == 0.0 {
                    a[0].clone()
                } else {
                    Val::vec(&m.inverse().to_cols_array())
                }
            }
        },
        Builtin::Transpose => match out {
            Ty::Mat3 => Val::vec(&m3(&a[0]).transpose().to_cols_array()),
            _ => Val::vec(&m4(&a[0]).transpose().to_cols_array()),
        },
        Builtin::Determinant => Val::float(if a[0].floats().len() == 9 {
            m3(&a[0]).determinant()
        } else {
            m4(&a[0]).determinant()
        }),
        Builtin::Ident => of_mat(out, Mat4::IDENTITY),
        Builtin::QMultiply => of_quat(q(&a[0]) * q(&a[1])),
        Builtin::QRotate => Val::vec(&(q(&a[0]) * v3(&a[1])).to_array()),
        Builtin::QConvert => Val::vec(&Mat3::from_quat(q(&a[0]).normalize()).to_cols_array()),
        Builtin::Quaternion => {
            if a[0].floats().len() >= 9 {
                of_quat(Quat::from_mat3(&m3(&a[0])).normalize())
            } else {
                // A rotation vector: axis times angle in radians.
                let v = v3(&a[0]);
                let angle = v.length();
                of_quat(if angle == 0.0 {
                    Quat::IDENTITY
                } else {
                    Quat::from_axis_angle(v / angle, angle)
                })
            }
        }
        Builtin::QuaternionAxis => {
            let axis = v3(&a[1]).normalize_or_zero();
            of_quat(if axis == Vec3::ZERO {
                Quat::IDENTITY
            } else {
                Quat::from_axis_angle(axis, a[0].f())
            })
        }
        Builtin::EulerToQuaternion => of_quat(euler_quat(v3(&a[0]), a.get(1).map_or(0, Val::i))),
        Builtin::Dihedral => {
            let (x, y) = (v3(&a[0]).normalize_or_zero(), v3(&a[1]).normalize_or_zero());
            let r = Quat::from_rotation_arc(x, y);
            if out == Ty::Mat3 {
                Val::vec(&Mat3::from_quat(r).to_cols_array())
            } else {
                of_quat(r)
            }
        }
        Builtin::Rotate => {
            // rotate(m, angle, axis): m = m * R.
            let axis = v3(&a[2]).normalize_or_zero();
            let r = Mat4::from_axis_angle(axis, a[1].f());
            of_mat(out, r * m4(&a[0]))
        }
        Builtin::Scale => of_mat(out, Mat4::from_scale(v3(&a[1])) * m4(&a[0])),
        Builtin::Translate => of_mat(out, Mat4::from_translation(v3(&a[1])) * m4(&a[0])),
        Builtin::MakeTransform => {
            if a.len() <= 3 && a[0].floats().len() == 3 && a[1].floats().len() == 3 {
                // (zaxis, yaxis[, translate])
                let z = v3(&a[0]).normalize_or_zero();
                let x = v3(&a[1]).cross(z).normalize_or_zero();
                let y = z.cross(x);
                let mut m = Mat4::from_mat3(Mat3::from_cols(x, y, z));
                if let Some(t) = a.get(2) {
                    m.w_axis = v3(t).extend(1.0);
                }
                of_mat(out, m)
            } else {
                // (trs, xyz, t, r (degrees), s[, pivot]): scale, rotate, translate.
                let t = v3(&a[2]);
                let r = v3(&a[3]) * std::f32::consts::PI / 180.0;
                let s = a.get(4).map_or(Vec3::ONE, v3);
                let rot = euler_quat(r, a[1].i());
                of_mat(out, Mat4::from_scale_rotation_translation(s, rot, t))
            }
        }
        Builtin::LookAt => {
            let (from, to) = (v3(&a[0]), v3(&a[1]));
            let up = a.get(2).map_or(Vec3::Y, v3);
            let z = (from - to).normalize_or_zero();
            let x = up.cross(z).normalize_or_zero();
            let y = z.cross(x);
            of_mat(out, Mat4::from_mat3(Mat3::from_cols(x, y, z)))
        }
        Builtin::Print => Val::S(sprintf(a[0].s(), &a[1..])),
        other => return Err(Stop::Msg(format!("{other:?} is not a library function"))),
    })
}

/// The number at the start of `s` (`atof("3.5abc")` is 3.5), else 0.
fn leading_number(s: &str) -> f32 {
    let s = s.trim_start();
    let end = s
        .char_indices()
        .take_while(|(i, c)| {
            c.is_ascii_digit() || *c == '.' || (*i == 0 && (*c == '-' || *c == '+'))
        })
        .map(|(i, c)| i + c.len_utf8())
        .last()
        .unwrap_or(0);
    s[..end].parse().unwrap_or(0.0)
}
