//! Point and primitive groups in Houdini's schema: read from `boolRLE`, `i8` or `ordered` selections, written as `boolRLE`.

use geode_geo::Group;

use super::bad;
use super::json::Json;
use crate::error::ParseResult;

/// The groups listed under `key`, each of `n` elements.
pub(super) fn groups(doc: &Json, key: &str, n: usize) -> ParseResult<Vec<(String, Group)>> {
    let Some(list) = doc.get(key).and_then(Json::items) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for entry in list {
        let Some([header, body]) = entry.items() else {
            return Err(bad(key, "expected [header, body] per group"));
        };
        let name = header
            .get("name")
            .and_then(Json::as_str)
            .ok_or_else(|| bad(key, "a group has no name"))?
            .to_owned();
        let what = format!("{key} `{name}`");
        let sel = body
            .get("selection")
            .ok_or_else(|| bad(&what, "missing `selection`"))?;
        let flags = if let Some(unordered) = sel.get("unordered") {
            if let Some(rle) = unordered.get("boolRLE") {
                let items = rle.items().unwrap_or_default();
                let mut flags = Vec::with_capacity(n);
                for (run, pair) in items.chunks(2).enumerate() {
                    let (Some(count), Some(on)) =
                        (pair[0].as_i64(), pair.get(1).and_then(Json::as_bool))
                    else {
                        return Err(bad(&what, "`boolRLE` must alternate counts and flags"));
                    };
                    // The count is the file's: compared with what is left
                    // without adding to it, so no count can overflow.
                    let left = n - flags.len();
                    let count = usize::try_from(count)
                        .ok()
                        .filter(|&c| c <= left)
                        .ok_or_else(|| {
                            bad(
                                &what,
                                format!(
                                    "`boolRLE` run {run} counts {count} elements where {left} of {n} are left"
                                ),
                            )
                        })?;
                    flags.extend(std::iter::repeat_n(on, count));
                }
                flags
            } else if let Some(i8s) = unordered.get("i8") {
                i8s.flags()
                    .ok_or_else(|| bad(&what, "`i8` is not a list of flags"))?
            } else {
                return Err(bad(
                    &what,
                    "unknown group encoding (expected `boolRLE` or `i8`)",
                ));
            }
        } else if let Some(ordered) = sel.get("ordered") {
            let members = ordered
                .integers()
                .ok_or_else(|| bad(&what, "`ordered` is not indices"))?;
            let group = Group::from_members(
                n,
                members.into_iter().filter_map(|m| usize::try_from(m).ok()),
            );
            out.push((name, group));
            continue;
        } else {
            return Err(bad(&what, "selection is neither `unordered` nor `ordered`"));
        };
        let mut flags = flags;
        if flags.len() > n {
            return Err(bad(
                &what,
                format!("{} flags for {n} elements", flags.len()),
            ));
        }
        flags.resize(n, false);
        out.push((name, Group::from_flags(flags)));
    }
    Ok(out)
}

/// A group as Houdini writes it in text files: run-length encoded flags.
pub(super) fn group(name: &str, grp: &Group) -> Json {
    let mut rle = Vec::new();
    let mut i = 0;
    while i < grp.len() {
        let on = grp.contains(i);
        let j = (i..grp.len())
            .find(|&k| grp.contains(k) != on)
            .unwrap_or(grp.len());
        rle.push(Json::Int((j - i) as i64));
        rle.push(Json::Bool(on));
        i = j;
    }
    Json::Array(vec![
        Json::pairs(vec![("name", Json::str(name))]),
        Json::pairs(vec![(
            "selection",
            Json::pairs(vec![(
                "unordered",
                Json::pairs(vec![("boolRLE", Json::Array(rle))]),
            )]),
        )]),
    ])
}
