//! Houdini's group patterns, as `expandpointgroup`, `nearpoint`'s group and
//! friends read them: space-separated tokens, each a number, a range
//! `a-b` (with `:step`), `*`, a group name or a glob over group names;
//! `!token` adds every element the token does not name, `^token` removes
//! what it names from the result so far. Elements come in the order the
//! pattern names them (Houdini's default "ordered" mode), each once; an
//! empty pattern names every element. `@name op value` tokens name the
//! elements whose attribute compares so (`@Cd.x>0.5`, `@id==3`,
//! `@name=piece*`).

use geode_geo::{AttribClass, Geometry};

/// The elements of `class` the pattern names, in order, without repeats.
pub fn expand(g: &Geometry, class: AttribClass, pattern: &str) -> Vec<usize> {
    let n = match class {
        AttribClass::Point => g.num_points(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Detail => 1,
    };
    if pattern.trim().is_empty() {
        return (0..n).collect();
    }
    let mut on = vec![false; n];
    let mut order: Vec<usize> = Vec::new();
    for token in pattern.split_whitespace() {
        if let Some(rest) = token.strip_prefix('^') {
            for i in named(g, class, n, rest) {
                on[i] = false;
            }
            continue;
        }
        let picked = match token.strip_prefix('!') {
            Some(rest) => {
                let mut hit = vec![false; n];
                for i in named(g, class, n, rest) {
                    hit[i] = true;
                }
                (0..n).filter(|&i| !hit[i]).collect()
            }
            None => named(g, class, n, token),
        };
        for i in picked {
            if !on[i] {
                on[i] = true;
                order.push(i);
            }
        }
    }
    order.retain(|&i| on[i]);
    order
}

/// What one token (without `!` or `^`) names.
fn named(g: &Geometry, class: AttribClass, n: usize, token: &str) -> Vec<usize> {
    if token == "*" {
        return (0..n).collect();
    }
    if let Some(test) = token.strip_prefix('@') {
        return by_attribute(g, class, n, test);
    }
    if let Some((lo, hi, step)) = number_range(token) {
        let mut out = Vec::new();
        let mut i = lo;
        while i <= hi && i < n {
            out.push(i);
            i += step;
        }
        return out;
    }
    let groups = match class {
        AttribClass::Point => g.point_groups(),
        AttribClass::Primitive => g.prim_groups(),
        _ => return Vec::new(),
    };
    let mut out = Vec::new();
    for (name, grp) in groups {
        if glob(token, name) {
            out.extend(grp.members().filter(|&i| i < n));
        }
    }
    out
}

/// The elements whose attribute passes `test` (`name op value`, the name
/// with an optional component `.x`..`.w` or `[k]`; the operators are
/// `=`, `==`, `!=`, `<`, `<=`, `>` and `>=`; strings compare by glob with
/// the first three). An attribute the geometry lacks, or a test that does
/// not parse, names nothing.
fn by_attribute(g: &Geometry, class: AttribClass, n: usize, test: &str) -> Vec<usize> {
    let Some(at) = test.find(['=', '!', '<', '>']) else {
        return Vec::new();
    };
    let (lhs, rest) = test.split_at(at);
    let two = rest.len() >= 2 && &rest[1..2] == "=";
    let (op, value) = rest.split_at(if two { 2 } else { 1 });
    let (name, comp) = match lhs.split_once('.') {
        Some((name, c)) => (name, "xyzw".find(c).filter(|_| c.len() == 1)),
        None => match lhs.strip_suffix(']').and_then(|l| l.split_once('[')) {
            Some((name, k)) => (name, k.parse().ok()),
            None => (lhs, Some(0)),
        },
    };
    let (Some(a), Some(k)) = (g.attrib(class, name), comp) else {
        return Vec::new();
    };
    if let Some(strings) = a.as_strings() {
        let want = match op {
            "=" | "==" => true,
            "!=" => false,
            _ => return Vec::new(),
        };
        return (0..n.min(strings.indices.len()))
            .filter(|&i| glob(value, strings.get(i)) == want)
            .collect();
    }
    let Ok(v) = value.parse::<f64>() else {
        return Vec::new();
    };
    let passes = |x: f64| match op {
        "=" | "==" => x == v,
        "!=" => x != v,
        "<" => x < v,
        "<=" => x <= v,
        ">" => x > v,
        ">=" => x >= v,
        _ => false,
    };
    if let Some(ints) = a.as_i32() {
        return (0..n.min(ints.len()))
            .filter(|&i| k == 0 && passes(f64::from(ints[i])))
            .collect();
    }
    match a.data().as_floats() {
        Some((f, w)) if k < w => (0..n.min(f.len() / w))
            .filter(|&i| passes(f64::from(f[i * w + k])))
            .collect(),
        _ => Vec::new(),
    }
}

/// `7`, `2-5` or `0-10:2` as (first, last, step).
fn number_range(s: &str) -> Option<(usize, usize, usize)> {
    let (range, step) = match s.split_once(':') {
        Some((r, st)) => (r, st.parse::<usize>().ok().filter(|&s| s > 0)?),
        None => (s, 1),
    };
    match range.split_once('-') {
        Some((a, b)) => {
            let (a, b): (usize, usize) = (a.parse().ok()?, b.parse().ok()?);
            Some((a.min(b), a.max(b), step))
        }
        None => {
            let a = range.parse().ok()?;
            Some((a, a, step))
        }
    }
}

/// Glob matching with `*` and `?`, linear backtracking (no pattern blows
/// up).
pub fn glob(pattern: &str, s: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), s.chars().collect());
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < t.len() {
        if i < p.len() && (p[i] == '?' || p[i] == t[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}
