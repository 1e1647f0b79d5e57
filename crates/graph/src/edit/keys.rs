//! Setting and deleting keyframes on a node's parameter in the document: a constant component becomes a channel, a channel with no key left becomes a constant.

use crate::document::NodeDoc;
use geode_op::{ParamDefault, Registry};
use serde_json::{json, Value as Json};

use crate::edit::{refuse, EditError};

/// The components of a numeric default as the document writes them.
fn default_components(d: ParamDefault) -> Vec<Json> {
    match d {
        ParamDefault::Float(x) => vec![json!(x)],
        ParamDefault::Int(x) => vec![json!(x)],
        ParamDefault::Toggle(b) => vec![json!(if b { 1 } else { 0 })],
        ParamDefault::Vec2(v) => v.iter().map(|x| json!(x)).collect(),
        ParamDefault::Vec3(v) => v.iter().map(|x| json!(x)).collect(),
        ParamDefault::Vec4(v) => v.iter().map(|x| json!(x)).collect(),
        ParamDefault::Str(_) | ParamDefault::EmptyList | ParamDefault::Ramp(..) => Vec::new(),
    }
}

/// The parameter's components (value or channel each) as written, or its default's.
fn components(
    node: &NodeDoc,
    path: &str,
    param: &str,
    registry: &Registry,
) -> Result<Vec<Json>, EditError> {
    let spec = crate::edit::param_spec(node, param, registry)
        .ok_or_else(|| refuse(path, format!("has no keyable parameter `{param}`")))?;
    if !spec.animatable || spec.ty.components() == 0 {
        return Err(refuse(
            path,
            format!("parameter `{param}` cannot be animated"),
        ));
    }
    let comps = match node.params.get(param) {
        None => default_components(spec.default),
        Some(Json::Array(a)) if spec.ty.components() > 1 => a.clone(),
        Some(v) if spec.ty.components() == 1 => vec![v.clone()],
        Some(_) => {
            return Err(refuse(
                path,
                format!("parameter `{param}` is not a vector of numbers"),
            ))
        }
    };
    if comps.len() != spec.ty.components() {
        return Err(refuse(
            path,
            format!(
                "parameter `{param}` has {} components",
                spec.ty.components()
            ),
        ));
    }
    Ok(comps)
}

fn store(node: &mut NodeDoc, param: &str, mut comps: Vec<Json>) {
    let v = if comps.len() == 1 {
        comps.pop().expect("one component")
    } else {
        Json::Array(comps)
    };
    node.params.insert(param.to_owned(), v);
}

fn keys_of(c: &Json) -> Option<Vec<Json>> {
    c.get("keys").and_then(Json::as_array).cloned()
}

fn same_frame(k: &Json, frame: f64) -> bool {
    k.get("frame").and_then(Json::as_f64) == Some(frame)
}

pub fn set_key(
    node: &mut NodeDoc,
    path: &str,
    param: &str,
    component: usize,
    frame: f64,
    value: f64,
    registry: &Registry,
) -> Result<(), EditError> {
    if !frame.is_finite() || !value.is_finite() {
        return Err(refuse(path, "a key needs a finite frame and value"));
    }
    let mut comps = components(node, path, param, registry)?;
    let c = comps.get_mut(component).ok_or_else(|| {
        refuse(
            path,
            format!("parameter `{param}` has no component {component}"),
        )
    })?;
    let mut keys = keys_of(c).unwrap_or_default();
    match keys.iter_mut().find(|k| same_frame(k, frame)) {
        Some(k) => k["value"] = json!(value),
        None => keys.push(json!({"frame": frame, "value": value})),
    }
    keys.sort_by(|a, b| {
        let f = |k: &Json| k.get("frame").and_then(Json::as_f64).unwrap_or(0.0);
        f(a).total_cmp(&f(b))
    });
    *c = json!({ "keys": keys });
    store(node, param, comps);
    Ok(())
}

pub fn delete_key(
    node: &mut NodeDoc,
    path: &str,
    param: &str,
    component: usize,
    frame: f64,
) -> Result<(), EditError> {
    let comps_json = node
        .params
        .get(param)
        .cloned()
        .ok_or_else(|| refuse(path, format!("parameter `{param}` has no keys")))?;
    let mut comps = match comps_json {
        Json::Array(a) => a,
        v => vec![v],
    };
    let c = comps.get_mut(component).ok_or_else(|| {
        refuse(
            path,
            format!("parameter `{param}` has no component {component}"),
        )
    })?;
    let mut keys =
        keys_of(c).ok_or_else(|| refuse(path, format!("parameter `{param}` is not animated")))?;
    let at = keys
        .iter()
        .position(|k| same_frame(k, frame))
        .ok_or_else(|| {
            refuse(
                path,
                format!("parameter `{param}` has no key at frame {frame}"),
            )
        })?;
    let removed = keys.remove(at);
    *c = if keys.is_empty() {
        removed.get("value").cloned().unwrap_or(json!(0))
    } else {
        json!({ "keys": keys })
    };
    store(node, param, comps);
    Ok(())
}
