//! Parameters read from a document: each JSON value checked against its
//! declaration and compiled (constants, keys, expressions, templates, list
//! rows, spare parameters, promotions), every problem reported.

use std::collections::BTreeMap;

use geode_op::{ListSpec, ParamSpec, ParamType, ParamValue, SPARE_TYPES};
use serde_json::Value as Json;

use crate::channel::{Channel, Key};
use crate::compiled_param::{CompiledParam, Component, ParamSource};
use crate::document::NodeDoc;
use crate::expr::Piece;
use crate::network::{NodeKind, Promotion};

use super::{Builder, LoadError};

fn describe(j: &Json) -> String {
    match j {
        Json::Null => "null".into(),
        Json::Bool(b) => format!("boolean {b}"),
        Json::Number(n) => format!("number {n}"),
        Json::String(s) => format!("string {s:?}"),
        Json::Array(a) => format!("an array of {}", a.len()),
        Json::Object(_) => "an object".into(),
    }
}

impl Builder<'_> {
    fn parse_param(
        &mut self,
        path: &str,
        spec: &'static ParamSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        self.parse_named(path, spec.name, spec, j)
    }

    /// The rows of a list parameter: an array of objects keyed by field
    /// (missing fields take their defaults), or, where the parameter had
    /// one, its old text form, converted with a note.
    fn parse_list(
        &mut self,
        path: &str,
        name: &str,
        rows: &'static ListSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        let err = |m: String| LoadError::param(path, name, m);
        let noun = if std::ptr::eq(rows, &geode_op::FLOAT_RAMP_ROWS)
            || std::ptr::eq(rows, &geode_op::COLOR_RAMP_ROWS)
        {
            "a ramp's keys"
        } else {
            "a list of rows"
        };
        let items = match j {
            Json::Array(items) => items,
            Json::String(text) => {
                let Some(legacy) = rows.legacy else {
                    self.errors.push(err(format!(
                        "expected {noun} (an array of objects with fields {}), found {}",
                        field_names(rows),
                        describe(j)
                    )));
                    return None;
                };
                return match legacy(text) {
                    Ok(values) => {
                        self.notes.push(err(format!(
                            "read from the old text form as {} row{}; write it as a list of objects with fields {}",
                            values.len(),
                            if values.len() == 1 { "" } else { "s" },
                            field_names(rows)
                        )));
                        Some(ParamSource::List(
                            values
                                .into_iter()
                                .map(|row| {
                                    rows.fields
                                        .iter()
                                        .zip(row)
                                        .map(|(f, v)| CompiledParam {
                                            spec: f,
                                            source: constant_source(v),
                                        })
                                        .collect()
                                })
                                .collect(),
                        ))
                    }
                    Err(why) => {
                        self.errors.push(err(why));
                        None
                    }
                };
            }
            other => {
                self.errors.push(err(format!(
                    "expected {noun} (an array of objects with fields {}), found {}",
                    field_names(rows),
                    describe(other)
                )));
                return None;
            }
        };
        let mut out = Vec::with_capacity(items.len());
        let mut ok = true;
        for (k, item) in items.iter().enumerate() {
            let row_name = format!("{name}[{k}]");
            let Json::Object(obj) = item else {
                self.errors.push(LoadError::param(
                    path,
                    &row_name,
                    format!(
                        "expected an object with fields {}, found {}",
                        field_names(rows),
                        describe(item)
                    ),
                ));
                ok = false;
                continue;
            };
            for key in obj.keys() {
                if rows.field(key).is_none() {
                    let hint = closest(key, rows.fields.iter().map(|f| f.name));
                    self.errors.push(LoadError::param(
                        path,
                        &row_name,
                        format!(
                            "unknown field `{key}`{hint} (fields: {})",
                            field_names(rows)
                        ),
                    ));
                    ok = false;
                }
            }
            let mut row = Vec::with_capacity(rows.fields.len());
            for f in rows.fields {
                let source = match obj.get(f.name) {
                    Some(j) => {
                        match self.parse_named(path, &format!("{row_name}.{}", f.name), f, j) {
                            Some(s) => s,
                            None => {
                                ok = false;
                                continue;
                            }
                        }
                    }
                    None => default_source(f),
                };
                row.push(CompiledParam { spec: f, source });
            }
            out.push(row);
        }
        ok.then_some(ParamSource::List(out))
    }

    fn parse_named(
        &mut self,
        path: &str,
        name: &str,
        spec: &'static ParamSpec,
        j: &Json,
    ) -> Option<ParamSource> {
        let err = |m: String| LoadError::param(path, name, m);
        if let ParamType::List(rows) = spec.ty {
            return self.parse_list(path, name, rows, j);
        }
        if let Some(rows) = spec.ty.ramp_rows() {
            // A ramp is written as list rows, one per key.
            return self.parse_list(path, name, rows, j);
        }
        if spec.ty.is_textual() {
            let Json::String(s) = j else {
                self.errors.push(err(format!(
                    "expected a {} (a string), found {}",
                    spec.ty,
                    describe(j)
                )));
                return None;
            };
            if let ParamType::Menu(items) = spec.ty {
                if !items.contains(&s.as_str()) {
                    self.errors
                        .push(err(format!("`{s}` is not one of {}", items.join(", "))));
                    return None;
                }
            }
            if !crate::expr::expands(spec) {
                return Some(ParamSource::Text(s.clone()));
            }
            return match crate::expr::parse_template(s, self.registry.expressions()) {
                Ok(pieces) => Some(text_source(pieces)),
                Err(e) => {
                    self.errors.push(err(e.message).at(e.position));
                    None
                }
            };
        }
        let n = spec.ty.components();
        let parts: Vec<&Json> = match (n, j) {
            (1, Json::Array(_)) | (2.., Json::Number(_)) => {
                self.errors.push(err(format!(
                    "expected {}, found {}",
                    expectation(spec.ty),
                    describe(j)
                )));
                return None;
            }
            (1, j) => vec![j],
            (_, Json::Array(a)) if a.len() == n => a.iter().collect(),
            _ => {
                self.errors.push(err(format!(
                    "expected {}, found {}",
                    expectation(spec.ty),
                    describe(j)
                )));
                return None;
            }
        };
        let mut comps = Vec::new();
        for p in parts {
            let c = match p {
                Json::Number(x) => Component::Const(x.as_f64().unwrap_or(f64::NAN)),
                Json::Bool(b) if spec.ty == ParamType::Toggle => {
                    Component::Const(if *b { 1.0 } else { 0.0 })
                }
                Json::Object(o) if o.contains_key("keys") => {
                    if !spec.animatable {
                        self.errors
                            .push(err("this parameter cannot be animated".into()));
                        return None;
                    }
                    let keys: Result<Vec<Key>, _> = serde_json::from_value(o["keys"].clone());
                    match keys.map_err(|e| e.to_string()).and_then(Channel::new) {
                        Ok(ch) => Component::Channel(ch),
                        Err(e) => {
                            self.errors.push(err(format!("bad channel: {e}")));
                            return None;
                        }
                    }
                }
                Json::Object(o) if o.contains_key("expr") => {
                    let Some(text) = o["expr"].as_str() else {
                        self.errors
                            .push(err("an expression (\"expr\") must be a string".into()));
                        return None;
                    };
                    if !spec.animatable {
                        self.errors
                            .push(err("this parameter takes no expression".into()));
                        return None;
                    }
                    match crate::expr::parse(text, self.registry.expressions()) {
                        Ok(e) => Component::Expr(e),
                        Err(e) => {
                            self.errors.push(err(e.message).at(e.position));
                            return None;
                        }
                    }
                }
                other => {
                    self.errors.push(err(format!(
                        "expected {}, found {}",
                        expectation(spec.ty),
                        describe(other)
                    )));
                    return None;
                }
            };
            let values: Vec<f64> = match &c {
                Component::Const(x) => vec![*x],
                Component::Channel(ch) => ch.keys().iter().map(|k| k.value).collect(),
                // Checked when evaluated, at each frame.
                Component::Expr(_) => Vec::new(),
            };
            for v in values {
                if !v.is_finite() {
                    self.errors
                        .push(err("values must be finite numbers".into()));
                    return None;
                }
                if spec.ty == ParamType::Int && v.fract() != 0.0 {
                    self.errors
                        .push(err(format!("expected an integer, found {v}")));
                    return None;
                }
                if let Some(min) = spec.min.filter(|m| v < *m) {
                    self.errors
                        .push(err(format!("value {v} is below the minimum {min}")));
                    return None;
                }
                if let Some(max) = spec.max.filter(|m| v > *m) {
                    self.errors
                        .push(err(format!("value {v} is above the maximum {max}")));
                    return None;
                }
            }
            comps.push(c);
        }
        Some(ParamSource::Components(comps))
    }

    /// The spare parameters `doc` declares on a node of type `spec`, with
    /// their values from `params` (each type's default when absent).
    fn spare_params(
        &mut self,
        path: &str,
        accepts: Option<&str>,
        own: &dyn Fn(&str) -> bool,
        doc: &NodeDoc,
    ) -> Vec<(String, CompiledParam)> {
        let mut out = Vec::new();
        if let (false, Some(ty)) = (doc.spare.is_empty(), accepts) {
            self.errors.push(LoadError::node(
                path,
                format!("a {ty} node takes no spare parameters"),
            ));
            return out;
        }
        for (name, ty) in &doc.spare {
            if own(name) {
                self.errors.push(LoadError::param(
                    path,
                    name,
                    "a spare parameter cannot reuse the name of one of the node's own parameters",
                ));
                continue;
            }
            let Some(pspec) = ParamSpec::spare(ty) else {
                self.errors.push(LoadError::param(
                    path,
                    name,
                    format!(
                        "unknown spare parameter type `{ty}`: expected one of {}",
                        SPARE_TYPES.join(", ")
                    ),
                ));
                continue;
            };
            let source = match doc.params.get(name) {
                Some(j) => self.parse_named(path, name, pspec, j),
                None => None,
            };
            let source = source.unwrap_or_else(|| default_source(pspec));
            out.push((
                name.clone(),
                CompiledParam {
                    spec: pspec,
                    source,
                },
            ));
        }
        out
    }

    pub(super) fn compile_params(&mut self) {
        // Promoted values, applied to their target after the target's own parameters.
        let mut overrides: BTreeMap<(usize, String), (String, Json)> = BTreeMap::new();
        for i in 0..self.nodes.len() {
            let path = self.nodes[i].path.clone();
            let doc = self.docs[i].clone();
            match self.nodes[i].kind.clone() {
                NodeKind::Op { op, .. } => {
                    let spec = op.spec();
                    let mut given: BTreeMap<&str, &Json> = BTreeMap::new();
                    let refuses = (!spec.spare).then_some(spec.name);
                    let spare =
                        self.spare_params(&path, refuses, &|n| spec.param(n).is_some(), &doc);
                    for (name, j) in &doc.params {
                        match spec.param(name) {
                            Some(_) => {
                                given.insert(name.as_str(), j);
                            }
                            None if spare.iter().any(|(n, _)| n == name) => {}
                            None => {
                                let hint = closest(name, spec.params.iter().map(|p| p.name));
                                self.errors.push(LoadError::node(
                                    &path,
                                    format!("unknown parameter `{name}`{hint}"),
                                ));
                            }
                        }
                    }
                    let mut params = Vec::new();
                    for spec in spec.params {
                        let source = match given.get(spec.name) {
                            Some(j) => self.parse_param(&path, spec, j),
                            None => None,
                        };
                        let source = source.unwrap_or_else(|| default_source(spec));
                        params.push(CompiledParam { spec, source });
                    }
                    self.nodes[i].kind = NodeKind::Op { op, params, spare };
                }
                NodeKind::Invalid | NodeKind::Feed { .. } => {}
                NodeKind::Subnet { block, .. } => {
                    let own: Vec<&'static ParamSpec> = block
                        .as_ref()
                        .map_or(Vec::new(), |b| b.kind.params().iter().collect());
                    let mut compiled = Vec::new();
                    for spec in &own {
                        let source = doc
                            .params
                            .get(spec.name)
                            .and_then(|j| self.parse_param(&path, spec, j));
                        compiled.push(CompiledParam {
                            spec,
                            source: source.unwrap_or_else(|| default_source(spec)),
                        });
                    }
                    let taken: Vec<String> = own
                        .iter()
                        .map(|p| p.name.to_owned())
                        .chain(doc.promote.keys().cloned())
                        .collect();
                    let spare =
                        self.spare_params(&path, None, &|n| taken.iter().any(|t| t == n), &doc);
                    if let NodeKind::Subnet {
                        block: b, spare: s, ..
                    } = &mut self.nodes[i].kind
                    {
                        if let Some(b) = b {
                            b.params = compiled;
                        }
                        *s = spare.clone();
                    }
                    for (name, target) in &doc.promote {
                        let Some((inner, param)) = target.rsplit_once('/') else {
                            self.errors.push(LoadError::node(&path, format!("promoted parameter `{name}` must name `node/parameter`, found `{target}`")));
                            continue;
                        };
                        let inner_path = format!("{path}/{inner}");
                        let Some(&t) = self.by_path.get(&inner_path) else {
                            self.errors.push(LoadError::node(&path, format!("promoted parameter `{name}` targets `{inner}`, which is not a node of the subnet")));
                            continue;
                        };
                        self.promotions.push(Promotion {
                            subnet: path.clone(),
                            name: name.clone(),
                            target: inner_path,
                            target_param: param.to_owned(),
                        });
                        if let Some(j) = doc.params.get(name) {
                            overrides.insert((t, param.to_owned()), (name.clone(), j.clone()));
                        }
                    }
                    for name in doc.params.keys() {
                        if !doc.promote.contains_key(name)
                            && !own.iter().any(|s| s.name == name)
                            && !spare.iter().any(|(n, _)| n == name)
                        {
                            self.errors.push(LoadError::node(&path, format!("unknown parameter `{name}` (a subnet has only its promoted parameters)")));
                        }
                    }
                }
            }
        }
        for ((t, param), (promoted, j)) in overrides {
            let NodeKind::Op { op, .. } = &self.nodes[t].kind else {
                let p = self.nodes[t].path.clone();
                self.errors.push(LoadError::node(&p, format!("promoted parameter `{promoted}` targets a subnet, not a node with parameters")));
                continue;
            };
            let path = self.nodes[t].path.clone();
            let Some(spec) = op.spec().param(&param) else {
                let sub = self.nodes[self.nodes[t].parent.unwrap_or(t)].path.clone();
                self.errors.push(LoadError::node(
                    &sub,
                    format!(
                        "promoted parameter `{promoted}` targets `{param}`, which {} does not have",
                        path
                    ),
                ));
                continue;
            };
            if let Some(source) = self.parse_param(&path, spec, &j) {
                if let NodeKind::Op { params, .. } = &mut self.nodes[t].kind {
                    if let Some(p) = params.iter_mut().find(|p| p.spec.name == param) {
                        p.source = source;
                    }
                }
            }
        }
    }
}

fn expectation(ty: ParamType) -> String {
    match ty.components() {
        1 if ty == ParamType::Toggle => {
            "a toggle (true/false, a number, a channel or {\"expr\": ...})".into()
        }
        1 => format!("{ty} (a number, a channel or {{\"expr\": ...}})"),
        n => format!("{ty} (an array of {n} numbers, channels or expressions)"),
    }
}

/// `a`, `b` and `c`: a list's field names for messages.
fn field_names(rows: &ListSpec) -> String {
    let names: Vec<String> = rows
        .fields
        .iter()
        .map(|f| format!("`{}`", f.name))
        .collect();
    names.join(", ")
}

/// ` (did you mean `x`?)` for the known name nearest to `name`, if near.
/// ` (did you mean `k`?)` for the known name nearest `name`, if any is near.
pub(crate) fn closest<'k>(name: &str, known: impl Iterator<Item = &'k str>) -> String {
    let mut near: Vec<(usize, &str)> = known
        .map(|k| (geode_op::edit_distance(name, k), k))
        .filter(|(d, _)| *d <= 3)
        .collect();
    near.sort();
    near.first()
        .map(|(_, k)| format!(" (did you mean `{k}`?)"))
        .unwrap_or_default()
}

fn default_source(spec: &'static ParamSpec) -> ParamSource {
    match spec.default_value() {
        ParamValue::String(s) if crate::expr::expands(spec) => {
            crate::expr::parse_template(&s, None).map_or(ParamSource::Text(s), text_source)
        }
        v => constant_source(v),
    }
}

/// A string's pieces as a source: plain text when nothing expands.
fn text_source(pieces: Vec<Piece>) -> ParamSource {
    match pieces.as_slice() {
        [] => ParamSource::Text(String::new()),
        [Piece::Text(t)] => ParamSource::Text(t.clone()),
        _ => ParamSource::Template(pieces),
    }
}

/// A fixed value as a parameter source.
fn constant_source(v: ParamValue) -> ParamSource {
    match v {
        ParamValue::Float(x) => ParamSource::Components(vec![Component::Const(x)]),
        ParamValue::Int(x) => ParamSource::Components(vec![Component::Const(x as f64)]),
        ParamValue::Toggle(x) => {
            ParamSource::Components(vec![Component::Const(if x { 1.0 } else { 0.0 })])
        }
        ParamValue::Vector(v) => {
            ParamSource::Components(v.into_iter().map(Component::Const).collect())
        }
        ParamValue::String(s) => ParamSource::Text(s),
        // A list's default has no rows (legacy rows are built field by
        // field in `parse_list`, where the field declarations are known).
        ParamValue::List(_) => ParamSource::List(Vec::new()),
        // A ramp's keys as the rows it is written as.
        ParamValue::Ramp(r) => {
            let fields = ParamType::Ramp(r.kind())
                .ramp_rows()
                .map_or(&[][..], |l| l.fields);
            ParamSource::List(
                geode_op::ramp_to_rows(&r)
                    .into_iter()
                    .map(|row| {
                        fields
                            .iter()
                            .zip(row)
                            .map(|(spec, v)| CompiledParam {
                                spec,
                                source: constant_source(v),
                            })
                            .collect()
                    })
                    .collect(),
            )
        }
    }
}
