//! Bindings between a snippet and geometry: which `@name`s it uses and
//! their types (prefix, VEX's implicit names, the attribute itself), the
//! pre-pass that finds them, and loading and storing them as columns.

use geode_geo::{AttribClass, Geometry};

use crate::compile::ast::*;
use crate::error::CompileError;
use crate::ir::Loc;
use crate::program::{Binding, Counts, Source};
use crate::ty::ty_of;
use crate::ty::Ty;

/// A spare parameter's value, as `ch()` reads it.
#[derive(Clone, Debug, PartialEq)]
pub enum Channel {
    Num(Vec<f64>),
    Str(String),
    /// A ramp parameter: `chramp` evaluates it, `ch` gives its key count.
    Ramp(geode_geo::Ramp),
}

/// What the compiler knows of the run: the element class, the inputs (for
/// attribute types) and the node's parameters.
pub struct BindSpec<'a> {
    pub run_over: AttribClass,
    pub inputs: Vec<Option<&'a Geometry>>,
    pub channels: &'a dyn Fn(&str) -> Option<Channel>,
    pub channel_names: &'a dyn Fn() -> Vec<String>,
    pub frame: f64,
    pub time: f64,
}

/// VEX's implicitly typed names (SideFX, "VEX > Attributes").
fn implicit(name: &str) -> Option<Ty> {
    Some(match name {
        "P" | "N" | "Cd" | "v" | "up" | "scale" | "accel" | "force" | "rest" | "torque" | "uv"
        | "w" | "center" => Ty::Vec3,
        "orient" | "rot" | "backtrack" => Ty::Vec4,
        "ptnum" | "primnum" | "vtxnum" | "elemnum" | "numpt" | "numprim" | "numvtx" | "numelem"
        | "id" | "nextid" | "pstate" => Ty::Int,
        "name" | "instance" => Ty::Str,
        "transform" => Ty::Mat3,
        _ => return None,
    })
}

/// Every `@name` in the snippet with its prefix and position.
fn collect(s: &Snippet) -> Vec<(String, Option<char>, bool, crate::compile::lex::Pos)> {
    let mut out = Vec::new();
    fn expr(e: &Expr, out: &mut Vec<(String, Option<char>, bool, crate::compile::lex::Pos)>) {
        match &e.kind {
            ExprKind::Binding {
                prefix,
                array,
                name,
            } => out.push((name.clone(), *prefix, *array, e.pos)),
            ExprKind::Braces(v) | ExprKind::Call(_, v) => v.iter().for_each(|x| expr(x, out)),
            ExprKind::Unary(_, a) | ExprKind::Member(a, _) | ExprKind::Cast(_, a) => expr(a, out),
            ExprKind::IncDec { target, .. } => expr(target, out),
            ExprKind::Binary(_, a, b) | ExprKind::Assign(_, a, b) | ExprKind::Index(a, b) => {
                expr(a, out);
                expr(b, out);
            }
            ExprKind::Ternary(a, b, c) => {
                expr(a, out);
                expr(b, out);
                expr(c, out);
            }
            ExprKind::Slice {
                seq,
                start,
                end,
                step,
            } => {
                expr(seq, out);
                for part in [start, end, step].into_iter().flatten() {
                    expr(part, out);
                }
            }
            _ => {}
        }
    }
    fn stmt(s: &Stmt, out: &mut Vec<(String, Option<char>, bool, crate::compile::lex::Pos)>) {
        match s {
            Stmt::Expr(e) => expr(e, out),
            Stmt::Decls(ds) => ds
                .iter()
                .filter_map(|d| d.init.as_ref())
                .for_each(|e| expr(e, out)),
            Stmt::Block(b) => b.iter().for_each(|x| stmt(x, out)),
            Stmt::If(c, a, b) => {
                expr(c, out);
                stmt(a, out);
                if let Some(b) = b {
                    stmt(b, out);
                }
            }
            Stmt::While(c, b) | Stmt::DoWhile(b, c) => {
                expr(c, out);
                stmt(b, out);
            }
            Stmt::For(i, c, st, b) => {
                if let Some(i) = i {
                    stmt(i, out);
                }
                if let Some(c) = c {
                    expr(c, out);
                }
                if let Some(st) = st {
                    expr(st, out);
                }
                stmt(b, out);
            }
            Stmt::Foreach { array, body, .. } => {
                expr(array, out);
                stmt(body, out);
            }
            Stmt::Return(Some(e), _) => expr(e, out),
            _ => {}
        }
    }
    for f in &s.functions {
        f.body.iter().for_each(|x| stmt(x, &mut out));
    }
    s.body.iter().for_each(|x| stmt(x, &mut out));
    out
}

/// Resolves every binding's type and source and gives it registers.
pub fn bindings(
    s: &Snippet,
    spec: &BindSpec,
    counts: &mut Counts,
) -> Result<Vec<Binding>, CompileError> {
    let uses = collect(s);
    let mut out: Vec<Binding> = Vec::new();
    // Typed uses decide first; untyped uses adopt them.
    let mut typed: Vec<(String, Ty, crate::compile::lex::Pos, char)> = Vec::new();
    for (name, prefix, array, pos) in &uses {
        if *array && !matches!(prefix, Some('i') | Some('f') | Some('v') | Some('s')) {
            return Err(CompileError::at(
                *pos,
                format!(
                    "@{name}: only int and float array attributes (i[]@, f[]@) are supported yet"
                ),
            ));
        }
        if let Some(p) = prefix {
            // The lexer folds `2@` too (VEX's matrix2), which has no type here.
            let Some(ty) = Ty::from_prefix(*p) else {
                return Err(CompileError::at(
                    *pos,
                    format!("{p}@{name}: the type prefix {p}@ is not supported"),
                ));
            };
            let ty = if *array {
                ty.array().expect("a scalar type")
            } else {
                ty
            };
            if let Some((_, t0, _, p0)) = typed.iter().find(|t| t.0 == *name) {
                if *t0 != ty {
                    return Err(CompileError::at(
                        *pos,
                        format!("@{name} is bound as {p0}@{name} ({t0}) and {p}@{name} ({ty})"),
                    ));
                }
            } else {
                typed.push((name.clone(), ty, *pos, *p));
            }
        }
    }
    let input0 = spec.inputs.first().copied().flatten();
    for (name, _, _, pos) in &uses {
        if out.iter().any(|b| b.name == *name) {
            continue;
        }
        let explicit = typed.iter().find(|t| t.0 == *name).map(|t| t.1);
        let (source, found) = source(name, spec, input0);
        let ty = explicit
            .or(found)
            .or_else(|| implicit(name))
            .unwrap_or(Ty::Float);
        if let (Some(e), Some(f)) = (explicit, found) {
            if e != f && matches!(source, Source::Attr { .. }) {
                return Err(CompileError::at(
                    *pos,
                    format!("@{name} is a {f} attribute; it cannot be bound as a {e}"),
                ));
            }
        }
        let reg = match ty {
            Ty::Int => bump(&mut counts.i, 1),
            Ty::Str => bump(&mut counts.s, 1),
            Ty::Array(crate::ty::Elem::Int) => bump(&mut counts.ai, 1),
            Ty::Array(crate::ty::Elem::Str) => bump(&mut counts.as_, 1),
            Ty::Array(_) => bump(&mut counts.af, 1),
            t => bump(&mut counts.f, t.floats() as u32),
        };
        out.push(Binding {
            name: name.clone(),
            ty,
            loc: Loc { ty, reg },
            source,
        });
    }
    Ok(out)
}

fn bump(c: &mut u32, n: u32) -> u32 {
    let r = *c;
    *c += n;
    r
}

/// Where `@name` reads from, and the type of the attribute if one exists.
fn source(name: &str, spec: &BindSpec, input0: Option<&Geometry>) -> (Source, Option<Ty>) {
    let class = spec.run_over;
    let count = |c: AttribClass| input0.map_or(0.0, |g| crate::run::elem_count(g, c) as f64);
    let special = match (name, class) {
        ("elemnum", _) => Some(Source::Elem),
        ("ptnum", AttribClass::Point)
        | ("primnum", AttribClass::Primitive)
        | ("vtxnum", AttribClass::Vertex) => Some(Source::Elem),
        ("primnum", AttribClass::Vertex) => Some(Source::PrimOfVertex),
        ("ptnum", AttribClass::Vertex) => Some(Source::PointOfVertex),
        ("ptnum" | "primnum" | "vtxnum", _) => Some(Source::Const(-1.0)),
        ("numpt", _) => Some(Source::Const(count(AttribClass::Point))),
        ("numprim", _) => Some(Source::Const(count(AttribClass::Primitive))),
        ("numvtx", AttribClass::Primitive | AttribClass::Vertex) => Some(Source::PrimVertexCount),
        ("numvtx", _) => Some(Source::Const(count(AttribClass::Vertex))),
        ("numelem", c) => Some(Source::Const(count(c))),
        (n, AttribClass::Point | AttribClass::Primitive)
            if n.starts_with("group_") && n.len() > 6 =>
        {
            return (
                Source::Group(n["group_".len()..].to_string()),
                Some(Ty::Int),
            );
        }
        ("Frame", _) => Some(Source::Const(spec.frame)),
        ("Time", _) => Some(Source::Const(spec.time)),
        _ => None,
    };
    if let Some(s) = special {
        return (s, None);
    }
    if let Some(rest) = name.strip_prefix("opinput") {
        if let Some((k, attrib)) = rest.split_once('_') {
            if let Ok(input) = k.parse::<usize>() {
                let found = spec
                    .inputs
                    .get(input)
                    .copied()
                    .flatten()
                    .and_then(|g| g.attrib(class, attrib))
                    .and_then(|a| ty_of(a.data()));
                return (
                    Source::Attr {
                        input,
                        class,
                        attrib: attrib.to_string(),
                    },
                    found,
                );
            }
        }
    }
    let on_class = input0
        .and_then(|g| g.attrib(class, name))
        .and_then(|a| ty_of(a.data()));
    if on_class.is_none() && input0.and_then(|g| g.attrib(class, name)).is_none() {
        if class == AttribClass::Primitive && name == "P" {
            return (Source::Centroid, Some(Ty::Vec3));
        }
        if class == AttribClass::Vertex {
            for c in [AttribClass::Point, AttribClass::Primitive] {
                let numeric = input0
                    .and_then(|g| g.attrib(c, name))
                    .filter(|a| a.data().as_floats().is_some() || a.as_i32().is_some())
                    .and_then(|a| ty_of(a.data()));
                if let Some(t) = numeric {
                    let attrib = name.to_string();
                    return (Source::Through { class: c, attrib }, Some(t));
                }
            }
        }
    }
    if on_class.is_none() && class != AttribClass::Detail {
        if let Some(t) = input0
            .and_then(|g| g.attrib(AttribClass::Detail, name))
            .and_then(|a| ty_of(a.data()))
        {
            // A detail attribute read by every element (read-only here).
            return (Source::Detail(name.to_string()), Some(t));
        }
    }
    (
        Source::Attr {
            input: 0,
            class,
            attrib: name.to_string(),
        },
        on_class,
    )
}
