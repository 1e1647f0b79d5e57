//! Houdini's group patterns, one parser and one matcher for every node's
//! group parameter and the wrangle's group functions: space-separated
//! terms, each `*`, a number, a range `first-last` with `:step` or
//! `:keep,step` (`0-30:2,3` keeps 2 of every 3), a group name or a glob over
//! group names (`*`, `?`, `[chars]`), or an attribute test `@name op value`
//! (`@P.y>0`, `@Cd[2]<=0.5`, `@name="piece*"`; `@ptnum`, `@primnum`,
//! `@vtxnum` and `@elemnum` are the element numbers; a point attribute
//! tested on primitives reads each primitive's points' average, so
//! `@P.y>0` selects primitives by centroid). `!term` adds every
//! element the term does not select, `^term` removes what it selects from
//! the result so far. Elements come in the order the pattern names them
//! (Houdini's ordered selection), each once; a range written high to low
//! runs downward.
//!
//! Parse errors and tests that cannot apply (an attribute the geometry
//! lacks, a string compared with `<`) carry the column where the term
//! starts, counted in characters from 1.

mod parse;

use crate::{AttribClass, Geometry, Group};

pub use parse::MAX_TERMS;

/// A parsed group pattern.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupPattern {
    terms: Vec<Term>,
}

/// What went wrong, and where (1-based column of the pattern text).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {column}: {message}")]
pub struct PatternError {
    pub column: usize,
    pub message: String,
}

impl PatternError {
    /// An error at 0-based character `index`.
    fn at(index: usize, message: impl Into<String>) -> PatternError {
        PatternError {
            column: index + 1,
            message: message.into(),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TermOp {
    Add,
    AllBut,
    Remove,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Compare {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

#[derive(Clone, Debug, PartialEq)]
enum Selector {
    All,
    Range {
        first: usize,
        last: usize,
        keep: usize,
        step: usize,
    },
    Names(String),
    Attribute {
        name: String,
        component: usize,
        op: Compare,
        value: String,
        value_column: usize,
    },
}

#[derive(Clone, Debug, PartialEq)]
struct Term {
    op: TermOp,
    selector: Selector,
    /// 0-based character index of the selector.
    column: usize,
}

impl GroupPattern {
    /// Reads `text`; an empty pattern selects every element.
    pub fn parse(text: &str) -> Result<GroupPattern, PatternError> {
        Ok(GroupPattern {
            terms: parse::terms(text)?,
        })
    }

    /// Whether the pattern selects every element (it is empty or `*`).
    pub fn is_everything(&self) -> bool {
        self.terms.is_empty()
            || (self.terms.len() == 1
                && self.terms[0].op == TermOp::Add
                && self.terms[0].selector == Selector::All)
    }

    /// When the pattern is one plain group name (no wildcard), that name:
    /// a node may then say which groups there are when it is missing.
    pub fn single_name(&self) -> Option<&str> {
        match self.terms.as_slice() {
            [Term {
                op: TermOp::Add,
                selector: Selector::Names(n),
                ..
            }] if !n.contains(['*', '?', '[']) => Some(n),
            _ => None,
        }
    }

    /// The elements of `class` of `g` the pattern selects, in order.
    pub fn select(&self, g: &Geometry, class: AttribClass) -> Result<Vec<usize>, PatternError> {
        let n = count(g, class);
        if self.terms.is_empty() {
            return Ok((0..n).collect());
        }
        let mut on = vec![false; n];
        let mut order: Vec<usize> = Vec::new();
        for term in &self.terms {
            let picked = selected(g, class, n, term)?;
            match term.op {
                TermOp::Remove => {
                    for i in picked {
                        on[i] = false;
                    }
                    continue;
                }
                TermOp::AllBut => {
                    let mut hit = vec![false; n];
                    for i in picked {
                        hit[i] = true;
                    }
                    for (i, _) in hit.iter().enumerate().filter(|(_, h)| !**h) {
                        if !on[i] {
                            on[i] = true;
                            order.push(i);
                        }
                    }
                }
                TermOp::Add => {
                    for i in picked {
                        if !on[i] {
                            on[i] = true;
                            order.push(i);
                        }
                    }
                }
            }
        }
        order.retain(|&i| on[i]);
        Ok(order)
    }

    /// The selection as a group over the elements of `class`.
    pub fn group(&self, g: &Geometry, class: AttribClass) -> Result<Group, PatternError> {
        let n = count(g, class);
        Ok(Group::from_members(n, self.select(g, class)?))
    }
}

/// How many elements of `class` `g` has.
fn count(g: &Geometry, class: AttribClass) -> usize {
    match class {
        AttribClass::Point => g.num_points(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Detail => 1,
    }
}

/// What one term's selector picks, in its order.
fn selected(
    g: &Geometry,
    class: AttribClass,
    n: usize,
    term: &Term,
) -> Result<Vec<usize>, PatternError> {
    Ok(match &term.selector {
        Selector::All => (0..n).collect(),
        &Selector::Range {
            first,
            last,
            keep,
            step,
        } => range(first, last, keep, step, n),
        Selector::Names(glob_text) => by_group(g, class, n, glob_text),
        Selector::Attribute {
            name,
            component,
            op,
            value,
            value_column,
        } => {
            let test = AttributeTest {
                name,
                component: *component,
                op: *op,
                value,
                // Errors of the test point at the attribute's name.
                column: term.column + 1,
                value_column: *value_column,
            };
            test.select(g, class, n)?
        }
    })
}

/// The numbers from `first` to `last` (either way), keeping `keep` of every
/// `step`, below `n`.
fn range(first: usize, last: usize, keep: usize, step: usize, n: usize) -> Vec<usize> {
    let span = first.abs_diff(last);
    let kept = (0..=span).filter(|k| k % step < keep);
    if first <= last {
        kept.map(|k| first + k).take_while(|&i| i < n).collect()
    } else {
        kept.map(|k| first - k).filter(|&i| i < n).collect()
    }
}

/// The members of every group of `class` whose name the glob matches, in
/// the groups' name order, then element order.
fn by_group(g: &Geometry, class: AttribClass, n: usize, glob_text: &str) -> Vec<usize> {
    let groups = match class {
        AttribClass::Point => g.point_groups(),
        AttribClass::Primitive => g.prim_groups(),
        _ => return Vec::new(),
    };
    let mut out = Vec::new();
    for (name, grp) in groups {
        if glob(glob_text, name) {
            out.extend(grp.members().filter(|&i| i < n));
        }
    }
    out
}

/// An `@name op value` term, ready to run.
struct AttributeTest<'a> {
    name: &'a str,
    component: usize,
    op: Compare,
    value: &'a str,
    column: usize,
    value_column: usize,
}

impl AttributeTest<'_> {
    fn select(
        &self,
        g: &Geometry,
        class: AttribClass,
        n: usize,
    ) -> Result<Vec<usize>, PatternError> {
        let element_number = matches!(
            (self.name, class),
            ("elemnum", _)
                | ("ptnum", AttribClass::Point)
                | ("primnum", AttribClass::Primitive)
                | ("vtxnum", AttribClass::Vertex)
        );
        if element_number {
            let v = self.number()?;
            return Ok((0..n).filter(|&i| self.passes(i as f64, v)).collect());
        }
        if class == AttribClass::Primitive && g.attrib(class, self.name).is_none() {
            if let Some((f, w)) = g
                .attrib(AttribClass::Point, self.name)
                .and_then(|a| a.data().as_floats())
            {
                // A point attribute read on primitives: each primitive's
                // points' average (`@P.y>0` selects by centroid).
                self.component_in(w)?;
                let v = self.number()?;
                let k = self.component;
                return Ok((0..n)
                    .filter(|&prim| {
                        let pts = g.prim_points(prim);
                        let sum: f64 = pts.iter().map(|&q| f64::from(f[q as usize * w + k])).sum();
                        !pts.is_empty() && self.passes(sum / pts.len() as f64, v)
                    })
                    .collect());
            }
        }
        let Some(a) = g.attrib(class, self.name) else {
            let what = match class {
                AttribClass::Point => "point",
                AttribClass::Primitive => "primitive",
                AttribClass::Vertex => "vertex",
                AttribClass::Detail => "detail",
            };
            return Err(PatternError::at(
                self.column,
                format!("there is no {what} attribute `{}`", self.name),
            ));
        };
        if let Some(strings) = a.as_strings() {
            let want = match self.op {
                Compare::Eq => true,
                Compare::Ne => false,
                _ => {
                    return Err(PatternError::at(
                        self.column,
                        format!("`{}` holds strings: compare it with `=` or `!=`", self.name),
                    ))
                }
            };
            return Ok((0..n.min(strings.indices.len()))
                .filter(|&i| glob(self.value, strings.get(i)) == want)
                .collect());
        }
        let v = self.number()?;
        if let Some(ints) = a.as_i32() {
            self.component_in(1)?;
            return Ok((0..n.min(ints.len()))
                .filter(|&i| self.passes(f64::from(ints[i]), v))
                .collect());
        }
        match a.data().as_floats() {
            Some((f, w)) => {
                self.component_in(w)?;
                let k = self.component;
                Ok((0..n.min(f.len() / w))
                    .filter(|&i| self.passes(f64::from(f[i * w + k]), v))
                    .collect())
            }
            None => Err(PatternError::at(
                self.column,
                format!(
                    "`{}` is an array attribute: a group test reads numbers and strings",
                    self.name
                ),
            )),
        }
    }

    fn number(&self) -> Result<f64, PatternError> {
        self.value
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                PatternError::at(
                    self.value_column,
                    format!(
                        "expected a number to compare `{}` with, found `{}`",
                        self.name, self.value
                    ),
                )
            })
    }

    fn component_in(&self, width: usize) -> Result<(), PatternError> {
        if self.component < width {
            return Ok(());
        }
        Err(PatternError::at(
            self.column,
            format!(
                "`{}` has {width} component{}: component {} does not exist",
                self.name,
                if width == 1 { "" } else { "s" },
                self.component
            ),
        ))
    }

    fn passes(&self, x: f64, v: f64) -> bool {
        match self.op {
            Compare::Eq => x == v,
            Compare::Ne => x != v,
            Compare::Lt => x < v,
            Compare::Le => x <= v,
            Compare::Gt => x > v,
            Compare::Ge => x >= v,
        }
    }
}

/// The names a name pattern selects, in `names`' order: space-separated
/// globs, `^glob` removing what it matches from what came before
/// (Houdini's attribute name patterns: `* ^P`, `Cd uv*`).
pub fn match_names<'a>(pattern: &str, names: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let names: Vec<&str> = names.into_iter().collect();
    let mut on = vec![false; names.len()];
    for term in pattern.split_whitespace() {
        let (remove, glob_text) = match term.strip_prefix('^') {
            Some(rest) => (true, rest),
            None => (false, term),
        };
        for (k, name) in names.iter().enumerate() {
            if glob(glob_text, name) {
                on[k] = !remove;
            }
        }
    }
    names
        .into_iter()
        .zip(on)
        .filter_map(|(n, o)| o.then_some(n))
        .collect()
}

/// Glob matching with `*`, `?` and `[chars]`, linear backtracking (no
/// pattern blows up).
pub fn glob(pattern: &str, s: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), s.chars().collect());
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < t.len() {
        if let Some(next) = one_char(&p, i, t[j]) {
            i = next;
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

/// Where the pattern continues when its element at `i` matches `c`: a
/// literal, `?`, or a `[chars]` class.
fn one_char(p: &[char], i: usize, c: char) -> Option<usize> {
    match p.get(i)? {
        '?' => Some(i + 1),
        '*' => None,
        '[' => {
            let close = p[i + 1..].iter().position(|&x| x == ']')? + i + 1;
            p[i + 1..close].contains(&c).then_some(close + 1)
        }
        &x => (x == c).then_some(i + 1),
    }
}

#[cfg(test)]
mod tests;
