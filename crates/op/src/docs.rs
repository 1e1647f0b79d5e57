//! Markdown documentation of a node type, generated from its declaration.

use std::fmt::Write;

use crate::{NodeSpec, ParamDefault};

fn default_text(d: &ParamDefault) -> String {
    match d {
        ParamDefault::Float(x) => format!("{x}"),
        ParamDefault::Int(x) => format!("{x}"),
        ParamDefault::Toggle(x) => format!("{x}"),
        ParamDefault::Vec2(v) => format!("{v:?}"),
        ParamDefault::Vec3(v) => format!("{v:?}"),
        ParamDefault::Vec4(v) => format!("{v:?}"),
        ParamDefault::Str(s) => format!("{s:?}"),
        ParamDefault::EmptyList => "no rows".into(),
        ParamDefault::Ramp(kind, keys) => {
            let keys: Vec<String> = keys
                .iter()
                .map(|k| match kind {
                    geode_geo::RampKind::Float => format!("{}: {} {}", k.pos, k.value[0], k.basis),
                    geode_geo::RampKind::Color => {
                        format!("{}: {:?} {}", k.pos, k.value, k.basis)
                    }
                })
                .collect();
            keys.join("; ")
        }
    }
}

/// One table row per parameter (or list field).
fn param_rows(s: &mut String, params: &[crate::ParamSpec]) {
    s.push_str("| name | label | type | default | range | animatable | description |\n|---|---|---|---|---|---|---|\n");
    for p in params {
        let range = match (p.min, p.max) {
            (Some(a), Some(b)) => format!("{a} to {b}"),
            (Some(a), None) => format!(">= {a}"),
            (None, Some(b)) => format!("<= {b}"),
            (None, None) => String::new(),
        };
        let ty = match p.ty {
            crate::ParamType::List(_) => "list (rows below)".to_string(),
            crate::ParamType::Ramp(_) => format!("{} (keys below)", p.ty),
            t => t.to_string(),
        };
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} | {} | {} | {} |",
            p.name,
            p.label,
            ty,
            default_text(&p.default),
            range,
            if p.animatable { "yes" } else { "no" },
            p.help.replace('|', "\\|")
        );
    }
}

/// The page for one node type: summary, inputs, output and a parameter table.
pub fn markdown(spec: &NodeSpec) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# {} (`{}`)\n", spec.label, spec.name);
    let _ = writeln!(
        s,
        "Category: {}. Version {}.\n",
        spec.category, spec.version
    );
    let _ = writeln!(s, "{}\n", spec.help);
    s.push_str("## Inputs\n\n");
    if spec.inputs.is_empty() {
        s.push_str("None.\n");
    }
    for (i, inp) in spec.inputs.iter().enumerate() {
        let _ = writeln!(
            s,
            "{}. {} ({}{})",
            i + 1,
            inp.name,
            inp.ty,
            if inp.required {
                ", required"
            } else {
                ", optional"
            }
        );
    }
    if spec.variadic {
        s.push_str("\nAny number of further inputs of the last kind may follow.\n");
    }
    let _ = writeln!(s, "\n## Output\n\n{}\n", spec.output);
    if !spec.writes.is_empty() {
        let names: Vec<String> = spec
            .writes
            .iter()
            .map(|w| format!("`{}`", w.name))
            .collect();
        let _ = writeln!(
            s,
            "Writes the file named by {} every time it cooks (an output: never served from the cache).\n",
            names.join(", ")
        );
    }
    s.push_str("## Parameters\n\n");
    if spec.params.is_empty() {
        s.push_str("None.\n");
        return s;
    }
    param_rows(&mut s, spec.params);
    for p in spec.params {
        if let crate::ParamType::List(l) = p.ty {
            let _ = writeln!(
                s,
                "\n### Rows of `{}`\n\nA list parameter: an array of objects with these fields (missing fields take their defaults).\n",
                p.name
            );
            param_rows(&mut s, l.fields);
        }
        if let Some(l) = p.ty.ramp_rows() {
            let _ = writeln!(
                s,
                "\n### Keys of `{}`\n\nA ramp: an array of keys with these fields, sorted by position when loaded; each key's interpolation draws the segment after it (see `docs/ramps.md`).\n",
                p.name
            );
            param_rows(&mut s, l.fields);
        }
    }
    s
}
