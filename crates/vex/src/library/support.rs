//! Helpers the lane functions share: reading matrices, vectors and
//! quaternions out of lane values (VEX matrices are row-major with row
//! vectors, `v * m`; their 9 or 16 slots equal glam's column-major arrays of
//! the same transform, so `v * m` is glam's `m * v` and `a * b` is glam's
//! `b * a`), and array element access, growth and removal.

use geode_geo::glam::{EulerRot, Mat3, Mat4, Quat, Vec3};

use crate::program::{Lane, Stop};
use crate::ty::{Elem, Ty};
use crate::value::Val;

pub fn m3(v: &Val) -> Mat3 {
    let f = v.floats();
    if f.len() == 16 {
        return Mat3::from_mat4(m4(v));
    }
    let mut a = [0.0; 9];
    a[..f.len().min(9)].copy_from_slice(&f[..f.len().min(9)]);
    Mat3::from_cols_array(&a)
}

pub fn m4(v: &Val) -> Mat4 {
    let f = v.floats();
    if f.len() == 9 {
        return Mat4::from_mat3(m3(v));
    }
    let mut a = [0.0; 16];
    a[..f.len().min(16)].copy_from_slice(&f[..f.len().min(16)]);
    Mat4::from_cols_array(&a)
}

pub fn v3(v: &Val) -> Vec3 {
    Vec3::from_array(v.v3())
}

pub fn q(v: &Val) -> Quat {
    let f = v.floats();
    let g = |k: usize| f.get(k).copied().unwrap_or(0.0);
    Quat::from_xyzw(g(0), g(1), g(2), g(3))
}

pub fn of_quat(q: Quat) -> Val {
    Val::vec(&q.to_array())
}

pub fn of_mat(out: Ty, m: Mat4) -> Val {
    if out == Ty::Mat3 {
        Val::vec(&Mat3::from_mat4(m).to_cols_array())
    } else {
        Val::vec(&m.to_cols_array())
    }
}

/// VEX's rotation orders (`XFORM_XYZ` = 0 ...) as glam's extrinsic Euler orders.
pub fn euler_order(order: i32) -> EulerRot {
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
    let c: Vec<char> = euler_axes(rot).chars().collect();
    Quat::from_euler(rot, pick(c[0]), pick(c[1]), pick(c[2]))
}

/// A rotation's Euler angles (radians, VEX order code): the inverse of
/// `euler_quat`.
pub fn euler_of(q: Quat, order: i32) -> Vec3 {
    let rot = euler_order(order);
    let (a, b, c) = q.normalize().to_euler(rot);
    // `euler_quat` hands glam the angles in the order of its axis names.
    let mut r = [0.0f32; 3];
    for (axis, v) in euler_axes(rot).chars().zip([a, b, c]) {
        r[(axis as u8 - b'x') as usize] = v;
    }
    Vec3::from_array(r)
}

/// The axes glam's Euler order takes its three angles for, in order.
pub fn euler_axes(rot: EulerRot) -> &'static str {
    match rot {
        EulerRot::ZYX => "zyx",
        EulerRot::YZX => "yzx",
        EulerRot::ZXY => "zxy",
        EulerRot::XZY => "xzy",
        EulerRot::YXZ => "yxz",
        _ => "xyz",
    }
}

pub fn arr_len(v: &Val) -> usize {
    match v {
        Val::AI(a) => a.len(),
        Val::AS(a) => a.len(),
        Val::AF(a, w) => a.len() / (*w).max(1) as usize,
        _ => 0,
    }
}

/// Resolves a VEX index (negative counts from the end).
pub fn index(i: i32, len: usize) -> Option<usize> {
    let i = if i < 0 {
        len as i64 + i as i64
    } else {
        i as i64
    };
    (0..len as i64).contains(&i).then_some(i as usize)
}

pub fn elem_get(v: &Val, i: usize) -> Val {
    match v {
        Val::AI(a) => Val::I(a[i]),
        Val::AS(a) => Val::S(a[i].clone()),
        Val::AF(a, w) => Val::vec(&a[i * *w as usize..(i + 1) * *w as usize]),
        _ => Val::I(0),
    }
}

pub fn empty_like(out: Ty) -> Val {
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
pub fn push(a: &mut Val, x: &Val) {
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

pub fn remove_at(a: &mut Val, i: usize) {
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

/// Elements a growing fill writes between cancellation polls.
pub const FILL_CHUNK: usize = 1 << 22;

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
pub fn truncate(a: &mut Val, n: usize, pad: bool, cancel: &dyn Fn() -> bool) -> Result<(), Stop> {
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

/// A run with no inputs, for testing lane functions alone.
#[cfg(test)]
pub struct NoHost;

#[cfg(test)]
impl crate::program::Host for NoHost {
    fn input(&self, _: i32) -> Option<&geode_geo::Geometry> {
        None
    }
    fn topology(&self, _: i32) -> Option<std::sync::Arc<geode_geo::Topology>> {
        None
    }
    fn nearest(&self, _: i32, _: &str, _: [f32; 3], _: f32, _: usize) -> Vec<u32> {
        Vec::new()
    }
    fn queue(&mut self, _: crate::effect::EffectKind) -> Result<(), Stop> {
        Ok(())
    }
    fn add_point(&mut self, _: Option<i32>, _: [f32; 3]) -> Result<i32, Stop> {
        Ok(0)
    }
    fn add_prim(&mut self, _: bool, _: &[i32]) -> Result<i32, Stop> {
        Ok(0)
    }
    fn cancelled(&self) -> bool {
        false
    }
    fn elem(&self) -> u32 {
        0
    }
    fn cached(
        &self,
        _: i32,
        _: &'static str,
        _: &str,
        _: &dyn Fn(&geode_geo::Geometry) -> std::sync::Arc<dyn std::any::Any + Send + Sync>,
    ) -> Option<std::sync::Arc<dyn std::any::Any + Send + Sync>> {
        None
    }
    fn ramp(&self, _: usize) -> Option<&geode_geo::Ramp> {
        None
    }
    fn open_query(&mut self, _: crate::program::PointQuery) -> i32 {
        -1
    }
    fn query(&mut self, _: i32) -> Option<&mut crate::program::PointQuery> {
        None
    }
}

/// A lane function computing through its function of numbers (`NumFn`):
/// the arguments' floats in order (ints as floats), the result as many
/// floats as the call's type holds. Calls of numbers run `num` directly;
/// both ways give the same bits.
pub fn through_numbers(l: &Lane, a: &[Val], num: crate::program::NumFn) -> Val {
    let mut buf = [0.0f32; 64];
    let mut heap = Vec::new();
    let mut len = 0;
    for v in a {
        let one = [v.f()];
        let xs = match v {
            Val::I(_) => &one[..],
            v => v.floats(),
        };
        for &x in xs {
            if len < buf.len() {
                buf[len] = x;
            } else {
                if heap.is_empty() {
                    heap.extend_from_slice(&buf);
                }
                heap.push(x);
            }
            len += 1;
        }
    }
    let args = if heap.is_empty() {
        &buf[..len]
    } else {
        &heap[..]
    };
    let n = l.out.floats().clamp(1, 16);
    let mut out = [0.0f32; 16];
    num(args, &mut out[..n]);
    Val::F(out, n as u8)
}

/// A lane function going through its function of edits (`EditFn`): the
/// arguments' ints (int arrays spread), floats and string, each in order.
/// Calls of numbers and string literals run `edit` directly.
pub fn through_edits(l: &mut Lane, a: &[Val], edit: crate::program::EditFn) -> Result<Val, Stop> {
    let mut ints = Vec::new();
    let mut floats = Vec::new();
    let mut text = "";
    for v in a {
        match v {
            Val::I(x) => ints.push(*x),
            Val::AI(xs) => ints.extend_from_slice(xs),
            Val::S(s) => text = s.as_str(),
            v => floats.extend_from_slice(v.floats()),
        }
    }
    let numbers = crate::program::Numbers {
        ints: &ints,
        floats: &floats,
        text,
    };
    edit(&mut *l.host, &numbers).map(Val::I)
}
