//! The table checked against the compiler: every form of every function
//! compiles when called with its argument types (generic ones instantiated,
//! optional arguments left out in turn, a repeatable one repeated) and
//! gives its return type; names are unique and documented.

use std::collections::BTreeSet;

use geode_geo::{AttribClass, Geometry};

use super::*;
use crate::compile::{BindSpec, Channel};

/// The concrete argument lists a form stands for.
fn instances(form: &Form) -> Vec<Vec<(Ty, bool)>> {
    let mut counts: Vec<usize> = (0..=form.optional as usize)
        .map(|dropped| form.args.len() - dropped)
        .collect();
    if form.variadic {
        counts.push(form.args.len() + 1);
    }
    let nums = [Ty::Float, Ty::Vec3];
    let seqs = [Ty::Array(Elem::Float), Ty::Array(Elem::Str), Ty::Str];
    let mut lists = Vec::new();
    for n in counts {
        for num in nums {
            for seq in seqs {
                let elem = match seq {
                    Ty::Array(e) => e.ty(),
                    _ => Ty::Str,
                };
                let has_array = (0..n).any(|k| form.arg(k).is_some_and(|a| a.ty == T::Array));
                if has_array && seq == Ty::Str {
                    continue;
                }
                let list: Vec<(Ty, bool)> = (0..n)
                    .map(|k| {
                        let arg = form.arg(k).expect("within the form");
                        let ty = match arg.ty {
                            T::Is(t) => t,
                            T::Num => num,
                            T::Vector => Ty::Vec3,
                            T::Array | T::Seq => seq,
                            T::Elem => elem,
                            T::Any => Ty::Float,
                        };
                        (ty, arg.out)
                    })
                    .collect();
                if !lists.contains(&list) {
                    lists.push(list);
                }
            }
        }
    }
    lists
}

/// The type a form gives for an argument list.
fn expected(ret: Ret, args: &[(Ty, bool)], form: &Form) -> Option<Ty> {
    let seq = args
        .iter()
        .enumerate()
        .find(|(k, _)| matches!(form.arg(*k).map(|a| a.ty), Some(T::Array | T::Seq)))
        .map(|(_, (t, _))| *t);
    let num = args
        .iter()
        .enumerate()
        .filter(|(k, _)| form.arg(*k).map(|a| a.ty) == Some(T::Num))
        .map(|(_, (t, _))| *t)
        .find(|t| *t != Ty::Float)
        .unwrap_or(Ty::Float);
    match ret {
        Ret::Is(t) => Some(t),
        Ret::Num => Some(num),
        Ret::Same => seq,
        Ret::Elem => seq.map(|s| match s {
            Ty::Array(e) => e.ty(),
            t => t,
        }),
        Ret::Context(ts) => Some(ts[0]),
        Ret::Attrib(_) | Ret::Intrinsic => None,
    }
}

fn two_points() -> Geometry {
    let mut g = Geometry::new();
    g.add_points(&[[0.0, 0.0, 0.0].into(), [1.0, 0.0, 0.0].into()]);
    g
}

/// The argument as written: ints and strings as literals where they are
/// read (some must be constants: a component index, a parameter name),
/// everything else a variable declared before.
fn arg_text(k: usize, ty: Ty, out: bool) -> (Option<String>, String) {
    match (ty, out) {
        (Ty::Int, false) => (None, "0".into()),
        (Ty::Str, false) => (None, "\"P\"".into()),
        (Ty::Array(e), _) => (Some(format!("{} a{k}[];", e.ty())), format!("a{k}")),
        (t, _) => (Some(format!("{t} a{k};")), format!("a{k}")),
    }
}

#[test]
fn every_form_compiles_with_its_argument_types_and_gives_its_return_type() {
    let g = two_points();
    let mut failures = Vec::new();
    for f in functions() {
        let channels = |_: &str| Some(Channel::Num(vec![0.5; 4]));
        let strings = |_: &str| Some(Channel::Str("x".into()));
        let ramp = geode_geo::Ramp::new(geode_geo::RampKind::Float, Vec::new()).unwrap();
        let ramps = move |_: &str| Some(Channel::Ramp(ramp.clone()));
        let names = Vec::new;
        for form in f.forms {
            let reads_string = form.ret == Ret::Is(Ty::Str);
            let spec = BindSpec {
                run_over: AttribClass::Point,
                inputs: vec![Some(&g)],
                channels: if f.name == "chramp" {
                    &ramps
                } else if reads_string {
                    &strings
                } else {
                    &channels
                },
                channel_names: &names,
                frame: 1.0,
                time: 0.0,
            };
            for args in instances(form) {
                let (decls, texts): (Vec<_>, Vec<_>) = args
                    .iter()
                    .enumerate()
                    .map(|(k, (t, o))| arg_text(k, *t, *o))
                    .unzip();
                let decls: Vec<String> = decls.into_iter().flatten().collect();
                let call = format!("{}({})", f.name, texts.join(", "));
                let src = format!("{}\n{call};", decls.join("\n"));
                let want = expected(form.ret, &args, form);
                let hint = want.filter(|t| *t != Ty::Void);
                match crate::compile::last_call_type(&src, hint, &spec) {
                    Ok(got) if want.is_none_or(|w| w == got || w == Ty::Void) => {}
                    Ok(got) => failures.push(format!(
                        "{} with {args:?}: gives {got}, not {want:?}",
                        form.display(f.name)
                    )),
                    Err(e) => failures.push(format!("{}\n{src}\n{e}", form.display(f.name))),
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn names_are_unique_and_documented() {
    let mut seen = BTreeSet::new();
    for f in functions() {
        assert!(seen.insert(f.name), "{} is in the table twice", f.name);
        assert!(
            !f.summary.is_empty() && f.summary.ends_with('.'),
            "{}: {}",
            f.name,
            f.summary
        );
        assert!(!f.forms.is_empty(), "{} has no form", f.name);
        for form in f.forms {
            assert!(form.optional as usize <= form.args.len());
            assert_eq!(
                form.lane.is_some(),
                f.lowering == Lowering::Lane,
                "{}: a lane function's forms have lanes, the compiler's none",
                f.name
            );
        }
    }
    assert!(seen.len() > 200, "{} functions", seen.len());
}

#[test]
fn forms_display_as_vex_documents_them() {
    let show = |name: &str, k: usize| find(name).unwrap().forms[k].display(name);
    assert_eq!(
        show("fit01", 0),
        "<float|vector> fit01(<float|vector> x, <float|vector> nmin, <float|vector> nmax)"
    );
    assert_eq!(
        show("nearpoints", 0),
        "int[] nearpoints(int geo, vector pos, float maxdist[, int maxpoints])"
    );
    assert_eq!(show("push", 0), "void push(<type>[]& array, <type> value)");
    assert_eq!(
        show("xyzdist", 0),
        "float xyzdist(int geo, vector pos[, int& prim][, vector& uv][, float maxdist])"
    );
    let docs = docs_markdown();
    for f in functions() {
        assert!(
            docs.contains(&format!("{}(", f.name)),
            "{} not in the docs",
            f.name
        );
    }
}
