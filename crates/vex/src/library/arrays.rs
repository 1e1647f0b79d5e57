//! Array functions (SideFX's "Arrays" category) and the operators on
//! arrays and strings that lower to calls: indexing, element assignment,
//! slices and array literals. Functions that change an array take it by
//! reference: the runtime moves it out of its register and back, so
//! `push` in a loop is amortised O(1).

use super::support::{arr_len, elem_get, empty_like, index, push, remove_at, truncate};
use super::{a, compiler, form, lane, out, shape, Category, Function, Ret, I, IA, S, T};
use crate::program::{Host, Lane, Request, Stop};
use crate::ty::{Elem, Ty};
use crate::value::{HeapBytes, Val};

const C: Category = Category::Arrays;

#[rustfmt::skip]
pub const FUNCTIONS: &[Function] = &[
    lane("len", C, "Number of elements of an array, characters of a string or components of a vector.", &[
        form(Ret::Is(Ty::Int), &[a(T::Seq, "array")], len),
        form(Ret::Is(Ty::Int), &[a(T::Vector, "v")], len),
    ]),
    lane("push", C, "Appends a value (or every value of an array) to an array.", &[
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(T::Elem, "value")], push_values).bytes(growth),
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(T::Array, "values")], push_values).bytes(growth),
    ]),
    lane("append", C, "Appends a value or an array's values to an array, or a string to a string.", &[
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(T::Elem, "value")], push_values).bytes(growth),
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(T::Array, "values")], push_values).bytes(growth),
        form(Ret::Is(Ty::Void), &[out(S, "s"), a(S, "value")], append_string).bytes(growth),
    ]),
    lane("upush", C, "Appends a uniform value to an array (as push).", &[
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(T::Elem, "value")], push_values).bytes(growth),
    ]),
    lane("pop", C, "Removes and gives the last element (or the one at index) of an array.", &[
        form(Ret::Elem, &[out(T::Array, "array")], pop),
        form(Ret::Elem, &[out(T::Array, "array"), a(I, "index")], pop),
    ]),
    lane("insert", C, "Inserts a value (or an array's values) at index; past the end pads with zeros.", &[
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(I, "index"), a(T::Elem, "value")], insert).bytes(growth),
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(I, "index"), a(T::Array, "values")], insert).bytes(growth),
        form(Ret::Is(Ty::Void), &[out(S, "s"), a(I, "index"), a(S, "value")], insert_string).bytes(growth),
    ]),
    lane("removeindex", C, "Removes the element at index (negative from the end) and gives it.", &[
        form(Ret::Elem, &[out(T::Array, "array"), a(I, "index")], removeindex),
    ]),
    lane("removevalue", C, "Removes the first element equal to value; 1 if one was removed.", &[
        form(Ret::Is(Ty::Int), &[out(T::Array, "array"), a(T::Elem, "value")], removevalue),
    ]),
    lane("resize", C, "Sets an array's length; new elements are zero (or value).", &[
        form(Ret::Is(Ty::Void), &[out(T::Array, "array"), a(I, "size"), a(T::Elem, "value")], resize).opt(1).bytes(resize_bytes),
    ]),
    lane("isvalidindex", C, "1 if index (negative from the end) names an element of the array or string.", &[
        form(Ret::Is(Ty::Int), &[a(T::Seq, "array"), a(I, "index")], isvalidindex),
    ]),
    lane("find", C, "Index of the first element equal to value (-1 if none); all of them when an int array is wanted. On strings, the first index of a substring from start.", &[
        form(Ret::Context(&[Ty::Int, Ty::Array(Elem::Int)]), &[a(T::Array, "array"), a(T::Elem, "value"), a(I, "start"), a(I, "end")], find).opt(2),
        form(Ret::Context(&[Ty::Int, Ty::Array(Elem::Int)]), &[a(S, "s"), a(S, "search"), a(I, "start"), a(I, "end")], find).opt(2),
    ]),
    lane("sort", C, "The array in ascending order.", &[
        form(Ret::Same, &[a(T::Array, "array")], sort),
    ]),
    lane("argsort", C, "The indices that put the array in ascending order (stable).", &[
        form(Ret::Is(Ty::Array(Elem::Int)), &[a(T::Array, "array")], argsort),
    ]),
    lane("reorder", C, "The array's elements (or the string's characters) at the given indices, in their order.", &[
        form(Ret::Same, &[a(T::Seq, "array"), a(IA, "indices")], reorder),
    ]),
    lane("slice", C, "The sub-array (or sub-string) seq[start:end:step]: negative bounds count from the end, bounds clamp, a zero step gives an empty one; the seven-argument form says which of start, end and step are given.", &[
        form(Ret::Same, &[a(T::Seq, "seq"), a(I, "start"), a(I, "end"), a(I, "step")], slice_call).opt(1),
        form(Ret::Same, &[a(T::Seq, "seq"), a(I, "hasstart"), a(I, "start"), a(I, "hasend"), a(I, "end"), a(I, "hasstep"), a(I, "step")], slice_call),
    ]),
    lane("reverse", C, "The array (or string) in reverse order.", &[
        form(Ret::Same, &[a(T::Seq, "array")], reverse),
    ]),
    lane("sum", C, "The sum of an array's elements (zero for an empty array), or of a vector's components.", &[
        form(Ret::Elem, &[a(T::Array, "array")], sum),
        form(Ret::Is(Ty::Float), &[a(T::Vector, "v")], sum),
    ]),
    compiler("array", C, "An array of the arguments; its type is the declared one, else the first argument's.", &[
        shape(Ret::Same, &[a(T::Elem, "value")]).opt(1).many(),
    ]),
];

/// The operators on arrays and strings lowered to calls.
pub mod intrinsics {
    use super::super::Callee;

    pub const INDEX_GET: Callee = Callee {
        name: "[]",
        lane: super::index_get,
        bytes: None,
    };
    pub const INDEX_SET: Callee = Callee {
        name: "[]=",
        lane: super::index_set,
        bytes: Some(super::index_set_bytes),
    };
    /// `s += t` on a string variable: appended in place (amortised O(1)
    /// in a loop, where `s = s + t` copies `s` each time).
    pub const APPEND_STRING: Callee = Callee {
        name: "+=",
        lane: super::append_string,
        bytes: Some(super::growth),
    };
    pub const SLICE: Callee = Callee {
        name: "[:]",
        lane: super::slice,
        bytes: None,
    };
    pub const ARRAY_OF: Callee = Callee {
        name: "array",
        lane: super::array_of,
        bytes: Some(super::array_bytes),
    };
    pub const LEN: Callee = Callee {
        name: "len",
        lane: super::len,
        bytes: None,
    };
}

fn len(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(match &a[0] {
        Val::S(s) => s.chars().count(),
        Val::F(_, n) => *n as usize,
        v => arr_len(v),
    } as i32))
}

/// Bytes an element slot of the array takes.
fn slot(v: &Val) -> u64 {
    match v {
        Val::AF(_, w) => 4 * u64::from(*w),
        Val::AI(_) => 4,
        Val::AS(_) => std::mem::size_of::<String>() as u64,
        _ => 1,
    }
}

/// What appending the other arguments to the first may add: the values,
/// and a doubling of the array's allocation when it is full.
fn growth(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let added: u64 = a.iter().skip(1).map(|v| v.heap_bytes() + 16).sum();
    let elems: u64 = a.iter().map(|v| arr_len(v).max(1) as u64).sum();
    let regrow = match a.first().unwrap_or(&Val::I(0)) {
        Val::AF(v, _) if v.len() == v.capacity() => v.capacity() as u64 * 4,
        Val::AI(v) if v.len() == v.capacity() => v.capacity() as u64 * 4,
        Val::AS(v) if v.len() == v.capacity() => v.capacity() as u64 * 24,
        Val::S(s) if s.len() == s.capacity() => s.capacity() as u64,
        _ => 0,
    };
    Some((Request::Array(elems), added + regrow + 64))
}

/// An array of the arguments: each value and its slot.
fn array_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let bytes = a.iter().map(|v| v.heap_bytes() + 16).sum();
    Some((Request::Array(a.len() as u64), bytes))
}

fn resize_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let n = a.get(1)?.i().max(0) as u64;
    Some((Request::Resize(n), n.saturating_mul(slot(&a[0]))))
}

fn index_set_bytes(a: &[Val], _: &dyn Host) -> Option<(Request, u64)> {
    let i = a.get(1)?.i();
    let n = (arr_len(&a[0]) as u64).max(u64::try_from(i).map_or(0, |i| i + 1));
    let grown = n.saturating_mul(slot(&a[0]));
    Some((
        Request::IndexSet(i),
        grown.saturating_sub(a[0].heap_bytes()) + a[2].heap_bytes(),
    ))
}

/// Appends `x`, or each element of `x` when it is an array.
fn extend(arr: &mut Val, x: &Val) {
    match x {
        Val::AI(_) | Val::AS(_) | Val::AF(..) => {
            for i in 0..arr_len(x) {
                push(arr, &elem_get(x, i));
            }
        }
        x => push(arr, x),
    }
}

fn push_values(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let (arr, rest) = a.split_at_mut(1);
    extend(&mut arr[0], &rest[0]);
    Ok(Val::I(0))
}

fn append_string(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let add = a[1].s().to_string();
    if let Val::S(s) = &mut a[0] {
        s.push_str(&add);
    }
    Ok(Val::I(0))
}

fn pop(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = arr_len(&a[0]);
    let at = match a.get(1) {
        Some(i) => index(i.i(), n),
        None => n.checked_sub(1),
    };
    Ok(match at {
        Some(i) => {
            let v = elem_get(&a[0], i);
            remove_at(&mut a[0], i);
            v
        }
        None => empty_like(lane.out),
    })
}

fn insert(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = arr_len(&a[0]);
    // Past the end pads with zeros; a negative index counts from the end.
    let at = a[1].i();
    let at = if at < 0 {
        (n as i64 + at as i64).max(0) as usize
    } else {
        at as usize
    };
    let cancel = || lane.host.cancelled();
    let mut tail = a[0].clone();
    if at > n {
        truncate(&mut a[0], at, true, &cancel)?;
        tail = empty_like_val(&a[0]);
    } else {
        truncate(&mut a[0], at, false, &cancel)?;
        let mut rest = empty_like_val(&tail);
        for i in at..n {
            push(&mut rest, &elem_get(&tail, i));
        }
        tail = rest;
    }
    let value = a[2].clone();
    extend(&mut a[0], &value);
    let arr = &mut a[0];
    for i in 0..arr_len(&tail) {
        push(arr, &elem_get(&tail, i));
    }
    Ok(Val::I(0))
}

fn insert_string(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let add = a[2].s().to_string();
    let at = a[1].i();
    if let Val::S(s) = &mut a[0] {
        let n = s.chars().count() as i64;
        let at = if at < 0 {
            (n + at as i64).max(0)
        } else {
            (at as i64).min(n)
        };
        let byte = s
            .char_indices()
            .nth(at as usize)
            .map_or(s.len(), |(b, _)| b);
        s.insert_str(byte, &add);
    }
    Ok(Val::I(0))
}

/// An empty array of `v`'s element type.
fn empty_like_val(v: &Val) -> Val {
    match v {
        Val::AI(_) => Val::AI(Vec::new()),
        Val::AS(_) => Val::AS(Vec::new()),
        Val::AF(_, w) => Val::AF(Vec::new(), *w),
        Val::S(_) => Val::S(String::new()),
        other => other.clone(),
    }
}

fn removeindex(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match index(a[1].i(), arr_len(&a[0])) {
        Some(i) => {
            let v = elem_get(&a[0], i);
            remove_at(&mut a[0], i);
            v
        }
        None => empty_like(lane.out),
    })
}

fn removevalue(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::I(match position(&a[0], &a[1]) {
        Some(i) => {
            remove_at(&mut a[0], i);
            1
        }
        None => 0,
    }))
}

fn resize(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = arr_len(&a[0]);
    let to = a[1].i().max(0) as usize;
    truncate(&mut a[0], to, true, &|| lane.host.cancelled())?;
    if let Some(fill) = a.get(2).cloned() {
        for i in n..to {
            set_elem(&mut a[0], i, &fill);
        }
    }
    Ok(Val::I(0))
}

fn isvalidindex(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = match &a[0] {
        Val::S(s) => s.chars().count(),
        v => arr_len(v),
    };
    Ok(Val::I(i32::from(index(a[1].i(), n).is_some())))
}

/// Whether element `e` equals `x` (numbers compared as VEX compares them).
fn equal(e: &Val, x: &Val) -> bool {
    match (e, x) {
        (Val::I(a), y) => *a == y.i(),
        (Val::S(a), y) => a == y.s(),
        (a, b) => a.floats() == b.floats() || (a.floats().len() == 1 && a.f() == b.f()),
    }
}

fn position(arr: &Val, x: &Val) -> Option<usize> {
    (0..arr_len(arr)).find(|&i| equal(&elem_get(arr, i), x))
}

fn find(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let all = lane.out == Ty::Array(Elem::Int);
    if let Val::S(hay) = &a[0] {
        // (s, search[, start[, end]]): character offsets.
        let chars: Vec<char> = hay.chars().collect();
        let n = chars.len();
        let start = a.get(2).map_or(0, |v| v.i().clamp(0, n as i32) as usize);
        let end = a.get(3).map_or(n, |v| v.i().clamp(0, n as i32) as usize);
        let needle: Vec<char> = a[1].s().chars().collect();
        let mut found = Vec::new();
        if start <= end {
            // A match starts at or after start and at or before end.
            for i in start..=end.min(n) {
                if i + needle.len() <= n && chars[i..i + needle.len()] == needle[..] {
                    found.push(i as i32);
                    if !all || needle.is_empty() {
                        break;
                    }
                }
            }
        }
        return Ok(if all {
            Val::AI(found)
        } else {
            Val::I(found.first().copied().unwrap_or(-1))
        });
    }
    let n = arr_len(&a[0]);
    let start = a.get(2).map_or(0, |v| v.i().clamp(0, n as i32) as usize);
    let end = a.get(3).map_or(n, |v| (v.i().max(0) as usize).min(n));
    let mut hits = (start..end).filter(|&i| equal(&elem_get(&a[0], i), &a[1]));
    if all {
        return Ok(Val::AI(hits.map(|i| i as i32).collect()));
    }
    Ok(Val::I(hits.next().map_or(-1, |i| i as i32)))
}

/// The order that sorts the array: stable, floats by total order, vectors
/// by components in turn.
fn order(v: &Val) -> Vec<usize> {
    let n = arr_len(v);
    let mut idx: Vec<usize> = (0..n).collect();
    match v {
        Val::AI(x) => idx.sort_by_key(|&i| x[i]),
        Val::AS(x) => idx.sort_by(|&i, &j| x[i].cmp(&x[j])),
        Val::AF(x, w) => {
            let w = (*w).max(1) as usize;
            idx.sort_by(|&i, &j| {
                let (p, q) = (&x[i * w..(i + 1) * w], &x[j * w..(j + 1) * w]);
                p.iter()
                    .zip(q)
                    .map(|(a, b)| a.total_cmp(b))
                    .find(|o| o.is_ne())
                    .unwrap_or(std::cmp::Ordering::Equal)
            });
        }
        _ => {}
    }
    idx
}

fn sort(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let idx = order(&a[0]);
    Ok(pick(&a[0], &idx))
}

fn argsort(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(Val::AI(
        order(&a[0]).into_iter().map(|i| i as i32).collect(),
    ))
}

/// The elements of `v` at `idx`, skipping indices out of range.
fn pick(v: &Val, idx: &[usize]) -> Val {
    let mut r = empty_like_val(v);
    let n = arr_len(v);
    for &i in idx.iter().filter(|&&i| i < n) {
        push(&mut r, &elem_get(v, i));
    }
    r
}

fn reorder(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    if let Val::S(s) = &a[0] {
        let chars: Vec<char> = s.chars().collect();
        let picked = match &a[1] {
            Val::AI(ix) => ix
                .iter()
                .filter_map(|&i| index(i, chars.len()))
                .map(|i| chars[i])
                .collect(),
            _ => String::new(),
        };
        return Ok(Val::S(picked));
    }
    let n = arr_len(&a[0]);
    let idx: Vec<usize> = match &a[1] {
        Val::AI(ix) => ix.iter().filter_map(|&i| index(i, n)).collect(),
        _ => Vec::new(),
    };
    Ok(pick(&a[0], &idx))
}

fn reverse(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match &a[0] {
        Val::S(s) => Val::S(s.chars().rev().collect()),
        v => {
            let idx: Vec<usize> = (0..arr_len(v)).rev().collect();
            pick(v, &idx)
        }
    })
}

fn sum(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    Ok(match &a[0] {
        Val::AI(x) => Val::I(x.iter().fold(0i32, |s, v| s.wrapping_add(*v))),
        Val::AF(x, w) => {
            let w = (*w).max(1) as usize;
            let mut acc = vec![0.0f32; w];
            for c in x.chunks(w) {
                for (s, v) in acc.iter_mut().zip(c) {
                    *s += v;
                }
            }
            Val::vec(&acc)
        }
        Val::F(f, n) => Val::float(f[..*n as usize].iter().sum()),
        _ => empty_like(lane.out),
    })
}

fn index_get(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    if let Val::S(s) = &a[0] {
        let n = s.chars().count();
        return Ok(Val::S(
            index(a[1].i(), n)
                .and_then(|i| s.chars().nth(i))
                .map(String::from)
                .unwrap_or_default(),
        ));
    }
    if let Val::F(f, n) = &a[0] {
        // A vector or matrix component by a run-time index.
        let i = a[1].i();
        return Ok(Val::float(if (0..i32::from(*n)).contains(&i) {
            f[i as usize]
        } else {
            0.0
        }));
    }
    Ok(match index(a[1].i(), arr_len(&a[0])) {
        Some(i) => elem_get(&a[0], i),
        None => empty_like(lane.out),
    })
}

/// Writes element `i` of `arr` (which is long enough).
fn set_elem(arr: &mut Val, i: usize, x: &Val) {
    match arr {
        Val::AI(v) => v[i] = x.i(),
        Val::AS(v) => v[i] = x.s().to_string(),
        Val::AF(v, w) => {
            let w = *w as usize;
            let f = x.floats();
            for k in 0..w {
                v[i * w + k] = if f.len() == 1 {
                    f[0]
                } else {
                    f.get(k).copied().unwrap_or(x.f())
                };
            }
        }
        _ => {}
    }
}

/// `array[index] = value`, the array by reference: writing past the end
/// grows it; a negative index counts from the end.
fn index_set(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = arr_len(&a[0]);
    let i = a[1].i();
    let i = if i < 0 { n as i64 + i as i64 } else { i as i64 };
    if i < 0 {
        return Ok(Val::I(0));
    }
    let i = i as usize;
    let value = a[2].s().to_string();
    if let Val::S(s) = &mut a[0] {
        // One character replaced by the value's text.
        if let Some((b, c)) = s.char_indices().nth(i) {
            s.replace_range(b..b + c.len_utf8(), &value);
        }
        return Ok(Val::I(0));
    }
    if i >= n {
        truncate(&mut a[0], i + 1, true, &|| lane.host.cancelled())?;
    }
    let x = a[2].clone();
    set_elem(&mut a[0], i, &x);
    Ok(Val::I(0))
}

/// `slice(seq, start, end[, step])` or `slice(seq, hasstart, start,
/// hasend, end, hasstep, step)`, as the slicing syntax runs it.
fn slice_call(l: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let seq = std::mem::replace(&mut a[0], Val::I(0));
    let mut args = if a.len() == 7 {
        let has = |k: usize| a[k].i() != 0;
        let step = if has(5) { a[6].i() } else { 1 };
        let given = i32::from(has(1)) | (i32::from(has(3)) << 1);
        [
            seq,
            Val::I(a[2].i()),
            Val::I(a[4].i()),
            Val::I(step),
            Val::I(given),
        ]
    } else {
        let step = a.get(3).map_or(1, Val::i);
        [
            seq,
            Val::I(a[1].i()),
            Val::I(a[2].i()),
            Val::I(step),
            Val::I(3),
        ]
    };
    let r = slice(l, &mut args);
    a[0] = std::mem::replace(&mut args[0], Val::I(0));
    r
}

/// `seq[start:end:step]` as Python slices: negative bounds count from the
/// end, bounds clamp, a negative step walks back. Arguments: the sequence,
/// start, end, step, and which of start and end were given (bit 0, 1).
fn slice(_: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let n = match &a[0] {
        Val::S(s) => s.chars().count(),
        v => arr_len(v),
    } as i64;
    let step = i64::from(a[3].i());
    let given = a[4].i();
    if step == 0 {
        // "If step is zero, the function returns an empty string/array."
        return Ok(match &a[0] {
            Val::S(_) => Val::S(String::new()),
            v => empty_like_val(v),
        });
    }
    let bound = |v: i64, dflt: i64, lo: i64, hi: i64| {
        let v = if v < 0 { v + n } else { v };
        let _ = dflt;
        v.clamp(lo, hi)
    };
    let (start, end) = if step > 0 {
        (
            if given & 1 != 0 {
                bound(i64::from(a[1].i()), 0, 0, n)
            } else {
                0
            },
            if given & 2 != 0 {
                bound(i64::from(a[2].i()), n, 0, n)
            } else {
                n
            },
        )
    } else {
        (
            if given & 1 != 0 {
                bound(i64::from(a[1].i()), n - 1, -1, n - 1)
            } else {
                n - 1
            },
            if given & 2 != 0 {
                bound(i64::from(a[2].i()), -1, -1, n - 1)
            } else {
                -1
            },
        )
    };
    let mut idx = Vec::new();
    let mut i = start;
    while (step > 0 && i < end) || (step < 0 && i > end) {
        idx.push(i as usize);
        i += step;
    }
    Ok(match &a[0] {
        Val::S(s) => {
            let chars: Vec<char> = s.chars().collect();
            Val::S(idx.iter().map(|&i| chars[i]).collect())
        }
        v => pick(v, &idx),
    })
}

fn array_of(lane: &mut Lane, a: &mut [Val]) -> Result<Val, Stop> {
    let mut r = empty_like(lane.out);
    for x in a.iter() {
        push(&mut r, x);
    }
    Ok(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slice_of(v: Val, s: Option<i32>, e: Option<i32>, step: i32) -> Val {
        let mut host = super::super::support::NoHost;
        let mut lane = Lane {
            host: &mut host,
            out: Ty::Array(Elem::Int),
        };
        let given = i32::from(s.is_some()) | (i32::from(e.is_some()) << 1);
        let mut args = [
            v,
            Val::I(s.unwrap_or(0)),
            Val::I(e.unwrap_or(0)),
            Val::I(step),
            Val::I(given),
        ];
        slice(&mut lane, &mut args).unwrap()
    }

    #[test]
    fn slices_follow_python() {
        let a = || Val::AI(vec![0, 1, 2, 3, 4]);
        assert_eq!(slice_of(a(), Some(-2), None, 1), Val::AI(vec![3, 4]));
        assert_eq!(slice_of(a(), None, None, -1), Val::AI(vec![4, 3, 2, 1, 0]));
        assert_eq!(slice_of(a(), Some(1), Some(3), 1), Val::AI(vec![1, 2]));
        assert_eq!(slice_of(a(), None, None, 2), Val::AI(vec![0, 2, 4]));
        assert_eq!(slice_of(a(), Some(3), Some(0), -1), Val::AI(vec![3, 2, 1]));
        assert_eq!(slice_of(a(), Some(10), None, 1), Val::AI(vec![]));
        assert_eq!(
            slice_of(Val::S("hello".into()), Some(1), Some(3), 1),
            Val::S("el".into())
        );
        assert_eq!(
            slice_of(Val::S("hello".into()), Some(-1), None, 1),
            Val::S("o".into())
        );
    }
}
