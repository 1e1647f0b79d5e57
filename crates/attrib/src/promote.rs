//! Attribute promotion between classes (Houdini's Attribute Promote): each
//! target element combines the values of the elements it gathers from
//! (`relation::sources`) by average, minimum, maximum, sum, first, last,
//! the most common value, or an area-weighted average. Numbers keep their
//! type (an integer average is rounded); strings take first, last, mode,
//! minimum and maximum (by text); arrays first and last. An element with
//! nothing to gather takes the attribute's default.

use geode_geo::{AttribClass, AttribData, Attribute, Geometry};
use rayon::prelude::*;

use crate::error::unless_cancelled;
use crate::relation::{element_areas, sources, Rows};
use crate::AttribError;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combine {
    Average,
    Min,
    Max,
    Sum,
    First,
    Last,
    Mode,
    AreaAverage,
}

impl Combine {
    pub const NAMES: [&'static str; 8] = [
        "average",
        "min",
        "max",
        "sum",
        "first",
        "last",
        "mode",
        "area_average",
    ];

    pub fn from_name(s: &str) -> Option<Combine> {
        use Combine::*;
        let all = [Average, Min, Max, Sum, First, Last, Mode, AreaAverage];
        Combine::NAMES.iter().position(|n| *n == s).map(|i| all[i])
    }
}

/// Rows per cancellation poll.
const CHUNK: usize = 1 << 14;

/// `attr` (of class `from` on `g`) promoted to class `to`.
pub fn promote(
    g: &Geometry,
    attr: &Attribute,
    from: AttribClass,
    to: AttribClass,
    how: Combine,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Attribute, AttribError> {
    let rows = sources(g, from, to)?;
    unless_cancelled(cancel)?;
    let data = attr.data();
    let picked = match how {
        Combine::First => Some(pick(&rows, |r| r.first().copied())),
        Combine::Last => Some(pick(&rows, |r| r.last().copied())),
        Combine::Mode => Some(pick_cancellable(&rows, cancel, |r| mode(data, r))?),
        Combine::Min | Combine::Max if matches!(data, AttribData::String(_)) => {
            let max = how == Combine::Max;
            Some(pick(&rows, |r| extreme_string(data, r, max)))
        }
        _ => None,
    };
    if let Some(picked) = picked {
        return Ok(gathered(attr, &picked));
    }
    let weights = (how == Combine::AreaAverage).then(|| element_areas(g, from));
    numbers(attr, &rows, how, weights.as_deref(), cancel)
}

/// One source element (or none) per row.
fn pick(rows: &Rows, f: impl Fn(&[u32]) -> Option<u32> + Sync) -> Vec<Option<u32>> {
    (0..rows.len())
        .into_par_iter()
        .map(|i| f(rows.row(i)))
        .collect()
}

fn pick_cancellable(
    rows: &Rows,
    cancel: &(dyn Fn() -> bool + Sync),
    f: impl Fn(&[u32]) -> Option<u32> + Sync,
) -> Result<Vec<Option<u32>>, AttribError> {
    let chunks: Vec<Result<Vec<Option<u32>>, AttribError>> = (0..rows.len())
        .collect::<Vec<_>>()
        .par_chunks(CHUNK)
        .map(|c| {
            unless_cancelled(cancel)?;
            Ok(c.iter().map(|&i| f(rows.row(i))).collect())
        })
        .collect();
    let mut out = Vec::with_capacity(rows.len());
    for c in chunks {
        out.extend(c?);
    }
    Ok(out)
}

/// The attribute of the picked elements; rows with none take the default.
fn gathered(attr: &Attribute, picked: &[Option<u32>]) -> Attribute {
    let idx: Vec<u32> = picked.iter().map(|p| p.unwrap_or(0)).collect();
    let mut out = if attr.data().is_empty() {
        Attribute::new(attr.default_value().clone(), attr.type_info, picked.len())
    } else {
        attr.gather(&idx)
    };
    if picked.iter().any(Option::is_none) {
        let d = attr.default_value().clone();
        let mut values = out.values_mut();
        for (i, _) in picked.iter().enumerate().filter(|(_, p)| p.is_none()) {
            let _ = values.set(i, &d);
        }
    }
    out
}

/// The most common value of the row (ties: the one seen first).
fn mode(data: &AttribData, row: &[u32]) -> Option<u32> {
    let mut sorted: Vec<(u32, usize)> = row.iter().enumerate().map(|(k, &e)| (e, k)).collect();
    sorted.sort_by(|a, b| compare(data, a.0, b.0).then(a.1.cmp(&b.1)));
    let mut best: Option<(usize, usize, u32)> = None; // (count, first position, element)
    let mut k = 0;
    while k < sorted.len() {
        let mut end = k + 1;
        while end < sorted.len() && compare(data, sorted[k].0, sorted[end].0).is_eq() {
            end += 1;
        }
        let cand = (end - k, sorted[k].1, sorted[k].0);
        if best.is_none_or(|b| cand.0 > b.0 || (cand.0 == b.0 && cand.1 < b.1)) {
            best = Some(cand);
        }
        k = end;
    }
    best.map(|b| b.2)
}

/// A total order on a column's elements (floats by bits, strings by text).
fn compare(data: &AttribData, a: u32, b: u32) -> std::cmp::Ordering {
    let (a, b) = (a as usize, b as usize);
    if let AttribData::String(s) = data {
        return s.get(a).cmp(s.get(b));
    }
    if let AttribData::Int(v) = data {
        return v[a].cmp(&v[b]);
    }
    if let Some((f, w)) = data.as_floats() {
        let (x, y) = (&f[a * w..(a + 1) * w], &f[b * w..(b + 1) * w]);
        return x
            .iter()
            .map(|v| v.to_bits())
            .cmp(y.iter().map(|v| v.to_bits()));
    }
    format!("{:?}", data.get(a)).cmp(&format!("{:?}", data.get(b)))
}

fn extreme_string(data: &AttribData, row: &[u32], max: bool) -> Option<u32> {
    let AttribData::String(s) = data else {
        return None;
    };
    let by = |a: &&u32, b: &&u32| s.get(**a as usize).cmp(s.get(**b as usize));
    if max {
        // The first of equal maxima.
        row.iter().rev().max_by(by).copied()
    } else {
        row.iter().min_by(by).copied()
    }
}

/// Average, sum, minimum, maximum or area-weighted average of numbers,
/// component by component, in f64.
fn numbers(
    attr: &Attribute,
    rows: &Rows,
    how: Combine,
    weights: Option<&[f32]>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Attribute, AttribError> {
    let data = attr.data();
    let (floats, ints, w): (Option<&[f32]>, Option<&[i32]>, usize) = match data {
        AttribData::Int(v) => (None, Some(v), 1),
        d => match d.as_floats() {
            Some((f, w)) => (Some(f), None, w),
            None => {
                return Err(AttribError::Invalid(format!(
                    "a {} attribute cannot be combined by {}: use first, last, mode, min or max",
                    data.attrib_type(),
                    Combine::NAMES[how as usize]
                )))
            }
        },
    };
    let value = |e: usize, k: usize| match (floats, ints) {
        (Some(f), _) => f64::from(f[e * w + k]),
        (_, Some(v)) => f64::from(v[e]),
        _ => 0.0,
    };
    let default: Vec<f64> = {
        let d = Attribute::new(attr.default_value().clone(), geode_geo::TypeInfo::None, 1);
        match (d.data().as_floats(), d.as_i32()) {
            (Some((f, _)), _) => f.iter().map(|&x| f64::from(x)).collect(),
            (_, Some(v)) => vec![f64::from(v[0])],
            _ => vec![0.0; w],
        }
    };
    let combine_row = |row: &[u32], out: &mut [f64]| {
        if row.is_empty() {
            out.copy_from_slice(&default);
            return;
        }
        for (k, o) in out.iter_mut().enumerate() {
            *o = match how {
                Combine::Min => row
                    .iter()
                    .map(|&e| value(e as usize, k))
                    .fold(f64::INFINITY, f64::min),
                Combine::Max => row
                    .iter()
                    .map(|&e| value(e as usize, k))
                    .fold(f64::NEG_INFINITY, f64::max),
                Combine::Sum => row.iter().map(|&e| value(e as usize, k)).sum(),
                Combine::AreaAverage => {
                    let wt = weights.expect("area weights");
                    let total: f64 = row.iter().map(|&e| f64::from(wt[e as usize])).sum();
                    if total > 0.0 {
                        row.iter()
                            .map(|&e| f64::from(wt[e as usize]) * value(e as usize, k))
                            .sum::<f64>()
                            / total
                    } else {
                        row.iter().map(|&e| value(e as usize, k)).sum::<f64>() / row.len() as f64
                    }
                }
                _ => row.iter().map(|&e| value(e as usize, k)).sum::<f64>() / row.len() as f64,
            };
        }
    };
    let mut out = vec![0.0f64; rows.len() * w];
    out.par_chunks_mut(CHUNK * w)
        .enumerate()
        .try_for_each(|(c, chunk)| {
            unless_cancelled(cancel)?;
            for (j, o) in chunk.chunks_mut(w).enumerate() {
                combine_row(rows.row(c * CHUNK + j), o);
            }
            Ok::<(), AttribError>(())
        })?;
    // The type-info goes along: a promoted normal is still a normal.
    let mut result = Attribute::new(attr.default_value().clone(), attr.type_info, rows.len());
    if let Some((f, _)) = result.floats_mut() {
        for (d, s) in f.iter_mut().zip(&out) {
            *d = *s as f32;
        }
    } else if let Some(v) = result.as_i32_mut() {
        for (d, s) in v.iter_mut().zip(&out) {
            *d = s.round().clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32;
        }
    }
    Ok(result)
}
