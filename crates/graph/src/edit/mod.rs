//! Edits of a network document (add, remove, rename, wire, parameters, keys, flags, positions, paste): each a pure function from one document to the next.

mod annotations;
mod keys;
#[cfg(test)]
mod tests;
mod wires;

use wires::connect;

use std::collections::BTreeMap;

use crate::document::{Document, NetworkDoc, NodeDoc};
use geode_op::Registry;
use serde::Deserialize;
use serde_json::{json, Value as Json};

/// One edit, as the studio sends it. Node paths are absolute (`/grow`,
/// `/rig/raise`); `parent` names a network (`/` or a subnet's path).
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Edit {
    AddNode {
        parent: String,
        #[serde(rename = "type")]
        ty: String,
        #[serde(default)]
        name: Option<String>,
        #[serde(default)]
        pos: Option<[f64; 2]>,
        /// A node of the same network to wire into the new node's first
        /// input, in the same step (Houdini's Tab menu after a selection).
        #[serde(default)]
        after: Option<String>,
    },
    RemoveNodes {
        paths: Vec<String>,
    },
    Rename {
        path: String,
        name: String,
    },
    Connect {
        from: String,
        to: String,
        input: usize,
    },
    Disconnect {
        to: String,
        input: usize,
    },
    /// Sets a parameter's value as the document writes it (a constant, text,
    /// list rows, or channels per component); `null` reverts to the default.
    SetParam {
        path: String,
        param: String,
        value: Json,
    },
    /// Declares a spare parameter of `ty` on a node that takes them, or with
    /// `ty` null removes it and its value.
    SetSpare {
        path: String,
        name: String,
        #[serde(rename = "type")]
        ty: Option<String>,
    },
    /// Sets a key of component `component` at `frame` (a constant becomes a channel).
    SetKey {
        path: String,
        param: String,
        component: usize,
        frame: f64,
        value: f64,
    },
    /// Deletes the key at `frame`; a channel left with one key becomes its constant.
    DeleteKey {
        path: String,
        param: String,
        component: usize,
        frame: f64,
    },
    SetFlag {
        path: String,
        flag: Flag,
        on: bool,
    },
    /// Names the node whose output is the network's (`parent`'s) result,
    /// or with `node` null leaves it to the display flag.
    SetOutput {
        parent: String,
        node: Option<String>,
    },
    /// Node positions in the editor (UI data kept in the file).
    Move {
        positions: BTreeMap<String, [f64; 2]>,
    },
    /// The network's frame range and frames per second (Houdini keeps them
    /// in the .hip file): the studio's timeline and playback follow them.
    SetTimeline {
        frames: [f64; 2],
        fps: f64,
    },
    /// Nodes copied from a network (as the document writes them): names that
    /// collide are renamed, wires to nodes outside the copy are dropped.
    Paste {
        parent: String,
        nodes: BTreeMap<String, NodeDoc>,
        #[serde(default)]
        offset: [f64; 2],
    },
    /// Colours nodes (`#rrggbb`; null clears).
    SetColor {
        paths: Vec<String>,
        color: Option<String>,
    },
    /// Sets sticky note `id` of network `parent`; null removes it.
    SetNote {
        parent: String,
        id: String,
        note: Option<crate::document::StickyNote>,
    },
    /// Sets network box `id` of network `parent`; null removes it.
    SetBox {
        parent: String,
        id: String,
        #[serde(rename = "box")]
        network_box: Option<crate::document::NetworkBox>,
    },
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum Flag {
    Bypass,
    Display,
    /// Drawn as a ghost beside the viewed node (any number of nodes).
    Template,
}

/// An edit that names something that is not there, or would make a network
/// no file could describe (a cycle, a wire between different port types).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct EditError {
    pub path: String,
    pub message: String,
}

pub(crate) fn refuse(path: &str, message: impl Into<String>) -> EditError {
    EditError {
        path: path.to_owned(),
        message: message.into(),
    }
}

/// The key under which a node keeps its editor position.
pub const UI_KEY: &str = "ui";

/// Splits `/a/b/c` into the parent network path `/a/b` and the name `c`.
pub fn split_path(path: &str) -> Option<(&str, &str)> {
    let i = path.rfind('/')?;
    let name = &path[i + 1..];
    (!name.is_empty()).then(|| (if i == 0 { "/" } else { &path[..i] }, name))
}

fn join(parent: &str, name: &str) -> String {
    if parent == "/" {
        format!("/{name}")
    } else {
        format!("{parent}/{name}")
    }
}

/// The network at `parent` (`/` or a subnet path).
pub(crate) fn network_mut<'d>(
    doc: &'d mut Document,
    parent: &str,
) -> Result<&'d mut NetworkDoc, EditError> {
    let mut net = &mut doc.network;
    for name in parent.split('/').filter(|s| !s.is_empty()) {
        net = net
            .nodes
            .get_mut(name)
            .and_then(|n| n.network.as_deref_mut())
            .ok_or_else(|| refuse(parent, "no such subnetwork"))?;
    }
    Ok(net)
}

fn node_mut<'d>(doc: &'d mut Document, path: &str) -> Result<&'d mut NodeDoc, EditError> {
    let (parent, name) = split_path(path).ok_or_else(|| refuse(path, "not a node path"))?;
    network_mut(doc, parent)?
        .nodes
        .get_mut(name)
        .ok_or_else(|| refuse(path, "no such node"))
}

/// Whether `name` can name a node: letters, digits and `_`, not starting with a digit.
fn check_name(path: &str, name: &str) -> Result<(), EditError> {
    let ok = !name.is_empty()
        && name.len() <= 64
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.starts_with(|c: char| c.is_ascii_digit());
    if ok {
        Ok(())
    } else {
        Err(refuse(
            path,
            format!(
                "`{name}` is not a node name (letters, digits and _, not starting with a digit)"
            ),
        ))
    }
}

/// `base` if free in `net`, else `base1`, `base2`... (Houdini's `box1`).
fn unique_name(net: &NetworkDoc, base: &str) -> String {
    let stem = base.trim_end_matches(|c: char| c.is_ascii_digit());
    let stem = if stem.is_empty() { "node" } else { stem };
    if !net.nodes.contains_key(base) && base != stem {
        return base.to_owned();
    }
    (1..)
        .map(|i| format!("{stem}{i}"))
        .find(|n| !net.nodes.contains_key(n))
        .expect("some name is free")
}

/// Applies one edit to a copy of `doc`.
pub fn apply(doc: &Document, edit: &Edit, registry: &Registry) -> Result<Document, EditError> {
    let mut d = doc.clone();
    apply_in_place(&mut d, edit, registry)?;
    Ok(d)
}

/// Applies one edit to `d` itself, for hosts that build a network edit by
/// edit (Python) and must not copy the document each time. Every edit
/// checks before it writes, so one that changes a single thing leaves `d`
/// as it was when refused; one that changes several (removing or moving
/// several nodes, a paste, adding a node wired `after` another) may have
/// made its first changes: use [`apply`] for those.
pub fn apply_in_place(d: &mut Document, edit: &Edit, registry: &Registry) -> Result<(), EditError> {
    match edit {
        Edit::AddNode {
            parent,
            ty,
            name,
            pos,
            after,
        } => {
            let path = add_node(d, parent, ty, name.as_deref(), *pos, registry)?;
            if let Some(from) = after {
                connect(d, from, &path, 0, registry)?;
            }
        }
        Edit::RemoveNodes { paths } => {
            for p in paths {
                remove_node(d, p)?;
            }
        }
        Edit::Rename { path, name } => rename(d, path, name)?,
        Edit::Connect { from, to, input } => connect(d, from, to, *input, registry)?,
        Edit::Disconnect { to, input } => {
            let n = node_mut(d, to)?;
            if let Some(slot) = n.inputs.get_mut(*input) {
                *slot = None;
            }
            while n.inputs.last() == Some(&None) {
                n.inputs.pop();
            }
        }
        Edit::SetParam { path, param, value } => set_param(d, path, param, value, registry)?,
        Edit::SetSpare { path, name, ty } => set_spare(d, path, name, ty.as_deref(), registry)?,
        Edit::SetKey {
            path,
            param,
            component,
            frame,
            value,
        } => keys::set_key(
            node_mut(d, path)?,
            path,
            param,
            *component,
            *frame,
            *value,
            registry,
        )?,
        Edit::DeleteKey {
            path,
            param,
            component,
            frame,
        } => keys::delete_key(node_mut(d, path)?, path, param, *component, *frame)?,
        Edit::SetFlag { path, flag, on } => set_flag(d, path, *flag, *on)?,
        Edit::SetOutput { parent, node } => set_output(d, parent, node.as_deref())?,
        Edit::Move { positions } => {
            for (path, p) in positions {
                set_position(node_mut(d, path)?, *p);
            }
        }
        Edit::Paste {
            parent,
            nodes,
            offset,
        } => paste(d, parent, nodes, *offset, registry)?,
        Edit::SetTimeline { frames, fps } => set_timeline(d, *frames, *fps)?,
        Edit::SetColor { paths, color } => {
            for p in paths {
                annotations::set_node_color(node_mut(d, p)?, p, color.as_deref())?;
            }
        }
        Edit::SetNote { parent, id, note } => annotations::set_note(d, parent, id, note.as_ref())?,
        Edit::SetBox {
            parent,
            id,
            network_box,
        } => annotations::set_box(d, parent, id, network_box.as_ref())?,
    }
    Ok(())
}

fn set_output(d: &mut Document, parent: &str, node: Option<&str>) -> Result<(), EditError> {
    let net = network_mut(d, parent)?;
    if let Some(name) = node {
        if !net.nodes.contains_key(name) {
            return Err(refuse(&join(parent, name), "no such node"));
        }
    }
    net.output = node.map(str::to_owned);
    Ok(())
}

/// Stores the frame range and rate as the document's `frames` and `fps`.
fn set_timeline(d: &mut Document, [start, end]: [f64; 2], fps: f64) -> Result<(), EditError> {
    if !(start.is_finite() && end.is_finite() && start <= end) {
        return Err(refuse(
            "/",
            "the frame range must run from a first frame to a later one",
        ));
    }
    if !(fps.is_finite() && fps > 0.0 && fps <= 1000.0) {
        return Err(refuse(
            "/",
            "frames per second must be above 0 and at most 1000",
        ));
    }
    d.extra.insert("frames".into(), json!([start, end]));
    d.extra.insert("fps".into(), json!(fps));
    Ok(())
}

fn set_position(n: &mut NodeDoc, p: [f64; 2]) {
    let round = |v: f64| (v * 10.0).round() / 10.0;
    let ui = n
        .extra
        .entry(UI_KEY.to_owned())
        .or_insert_with(|| json!({}));
    if !ui.is_object() {
        *ui = json!({});
    }
    ui["pos"] = json!([round(p[0]), round(p[1])]);
}

fn check_type(path: &str, ty: &str, registry: &Registry) -> Result<(), EditError> {
    if crate::node_spec(registry, ty).is_some() {
        return Ok(());
    }
    let hint = crate::container::closest_types(registry, ty);
    Err(refuse(
        path,
        match hint.first() {
            Some(h) => format!("unknown node type `{ty}` (did you mean `{h}`?)"),
            None => format!("unknown node type `{ty}`"),
        },
    ))
}

fn add_node(
    d: &mut Document,
    parent: &str,
    ty: &str,
    name: Option<&str>,
    pos: Option<[f64; 2]>,
    registry: &Registry,
) -> Result<String, EditError> {
    check_type(parent, ty, registry)?;
    let net = network_mut(d, parent)?;
    let name = match name {
        Some(n) => {
            check_name(&join(parent, n), n)?;
            if net.nodes.contains_key(n) {
                return Err(refuse(&join(parent, n), "a node of that name exists"));
            }
            n.to_owned()
        }
        None => unique_name(net, ty),
    };
    let mut node = NodeDoc {
        ty: ty.to_owned(),
        params: BTreeMap::new(),
        inputs: Vec::new(),
        bypass: false,
        display: false,
        template: false,
        network: crate::holds_network(ty).then(|| Box::new(passing_through())),
        spare: BTreeMap::new(),
        promote: BTreeMap::new(),
        extra: BTreeMap::new(),
    };
    if let Some(p) = pos {
        set_position(&mut node, p);
    }
    let path = join(parent, &name);
    net.nodes.insert(name, node);
    Ok(path)
}

/// A new subnet's or block's network: a null named `output` passing its
/// first input through (Houdini's new For-Each passes its piece through),
/// so a new block cooks before anything is put in it.
fn passing_through() -> NetworkDoc {
    let output = NodeDoc {
        ty: "null".into(),
        params: BTreeMap::new(),
        inputs: vec![Some("@0".into())],
        bypass: false,
        display: false,
        template: false,
        network: None,
        spare: BTreeMap::new(),
        promote: BTreeMap::new(),
        extra: BTreeMap::new(),
    };
    NetworkDoc {
        nodes: BTreeMap::from([("output".to_owned(), output)]),
        output: Some("output".into()),
        ..NetworkDoc::default()
    }
}

fn remove_node(d: &mut Document, path: &str) -> Result<(), EditError> {
    let (parent, name) = split_path(path).ok_or_else(|| refuse(path, "not a node path"))?;
    let net = network_mut(d, parent)?;
    if net.nodes.remove(name).is_none() {
        return Err(refuse(path, "no such node"));
    }
    for n in net.nodes.values_mut() {
        for slot in n.inputs.iter_mut() {
            if slot.as_deref() == Some(name) {
                *slot = None;
            }
        }
        while n.inputs.last() == Some(&None) {
            n.inputs.pop();
        }
    }
    if net.output.as_deref() == Some(name) {
        net.output = None;
    }
    annotations::node_renamed(net, name, None);
    // A subnet's promotions that targeted the removed node go with it.
    if parent != "/" {
        let subnet = node_mut(d, parent)?;
        subnet
            .promote
            .retain(|_, target| target.split('/').next() != Some(name));
    }
    Ok(())
}

fn rename(d: &mut Document, path: &str, new: &str) -> Result<(), EditError> {
    let (parent, old) = split_path(path).ok_or_else(|| refuse(path, "not a node path"))?;
    check_name(path, new)?;
    if old == new {
        return Ok(());
    }
    let net = network_mut(d, parent)?;
    if net.nodes.contains_key(new) {
        return Err(refuse(path, format!("a node named `{new}` exists")));
    }
    let node = net
        .nodes
        .remove(old)
        .ok_or_else(|| refuse(path, "no such node"))?;
    net.nodes.insert(new.to_owned(), node);
    for n in net.nodes.values_mut() {
        for slot in n.inputs.iter_mut().flatten() {
            if slot == old {
                *slot = new.to_owned();
            }
        }
    }
    if net.output.as_deref() == Some(old) {
        net.output = Some(new.to_owned());
    }
    annotations::node_renamed(net, old, Some(new));
    if parent != "/" {
        let subnet = node_mut(d, parent)?;
        for target in subnet.promote.values_mut() {
            if let Some(rest) = target.strip_prefix(&format!("{old}/")) {
                *target = format!("{new}/{rest}");
            }
        }
    }
    Ok(())
}

fn set_param(
    d: &mut Document,
    path: &str,
    param: &str,
    value: &Json,
    registry: &Registry,
) -> Result<(), EditError> {
    let node = node_mut(d, path)?;
    let known = node.promote.contains_key(param) || param_spec(node, param, registry).is_some();
    if !known {
        let names = crate::node_spec(registry, &node.ty)
            .into_iter()
            .flat_map(|spec| spec.params.iter().map(|p| p.name))
            .chain(node.spare.keys().map(String::as_str))
            .chain(node.promote.keys().map(String::as_str));
        let hint = crate::load::closest(param, names);
        return Err(refuse(path, format!("has no parameter `{param}`{hint}")));
    }
    if value.is_null() {
        node.params.remove(param);
    } else {
        node.params.insert(param.to_owned(), value.clone());
    }
    Ok(())
}

/// The declaration of a node's parameter: the node type's own (the
/// registry's or the engine's: a loop's or solver's), or a spare parameter
/// the node declares.
pub(crate) fn param_spec(
    node: &NodeDoc,
    param: &str,
    registry: &Registry,
) -> Option<&'static geode_op::ParamSpec> {
    crate::node_spec(registry, &node.ty)
        .and_then(|spec| spec.param(param))
        .or_else(|| {
            node.spare
                .get(param)
                .and_then(|ty| geode_op::ParamSpec::spare(ty))
        })
}

fn set_spare(
    d: &mut Document,
    path: &str,
    name: &str,
    ty: Option<&str>,
    registry: &Registry,
) -> Result<(), EditError> {
    let node = node_mut(d, path)?;
    // As declared: subnets, loops and solvers take them for their inner
    // nodes (`../name`).
    let spec = crate::node_spec(registry, &node.ty);
    if !spec.is_some_and(|s| s.spare) {
        return Err(refuse(
            path,
            format!("a {} takes no spare parameters", node.ty),
        ));
    }
    let own = spec.is_some_and(|s| s.param(name).is_some()) || node.promote.contains_key(name);
    match ty {
        None => {
            // Only a spare parameter goes: removing a node's own parameter
            // this way would drop its value.
            if node.spare.remove(name).is_none() {
                return Err(refuse(path, format!("has no spare parameter `{name}`")));
            }
            node.params.remove(name);
        }
        Some(ty) => {
            if geode_op::ParamSpec::spare(ty).is_none() {
                return Err(refuse(
                    path,
                    format!(
                        "unknown spare parameter type `{ty}`: expected one of {}",
                        geode_op::SPARE_TYPES.join(", ")
                    ),
                ));
            }
            let valid = !name.is_empty()
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                && !name.starts_with(|c: char| c.is_ascii_digit());
            if !valid {
                return Err(refuse(
                    path,
                    format!("`{name}` is not a parameter name (letters, digits and _)"),
                ));
            }
            if own {
                return Err(refuse(
                    path,
                    format!("`{name}` is one of the node's own parameters"),
                ));
            }
            if node.spare.get(name).is_some_and(|t| t != ty) {
                node.params.remove(name);
            }
            node.spare.insert(name.to_owned(), ty.to_owned());
        }
    }
    Ok(())
}

fn set_flag(d: &mut Document, path: &str, flag: Flag, on: bool) -> Result<(), EditError> {
    let (parent, name) = split_path(path).ok_or_else(|| refuse(path, "not a node path"))?;
    let net = network_mut(d, parent)?;
    if !net.nodes.contains_key(name) {
        return Err(refuse(path, "no such node"));
    }
    match flag {
        Flag::Bypass => net.nodes.get_mut(name).expect("checked").bypass = on,
        Flag::Template => net.nodes.get_mut(name).expect("checked").template = on,
        Flag::Display => {
            // One display node per network, as in Houdini; it is the output.
            for (n, node) in net.nodes.iter_mut() {
                node.display = on && n == name;
            }
            if on && net.output.is_some() {
                net.output = Some(name.to_owned());
            }
        }
    }
    Ok(())
}

fn paste(
    d: &mut Document,
    parent: &str,
    nodes: &BTreeMap<String, NodeDoc>,
    offset: [f64; 2],
    registry: &Registry,
) -> Result<(), EditError> {
    for (name, n) in nodes {
        check_name(&join(parent, name), name)?;
        check_type(&join(parent, name), &n.ty, registry)?;
    }
    let net = network_mut(d, parent)?;
    let mut renamed: BTreeMap<&str, String> = BTreeMap::new();
    for name in nodes.keys() {
        let fresh = unique_name(net, name);
        net.nodes.insert(
            fresh.clone(),
            NodeDoc {
                ..nodes[name].clone()
            },
        );
        renamed.insert(name, fresh);
    }
    for fresh in renamed.values() {
        let n = net.nodes.get_mut(fresh).expect("just inserted");
        n.display = false;
        for slot in n.inputs.iter_mut() {
            *slot = slot.as_deref().and_then(|s| {
                if s.starts_with('@') {
                    Some(s.to_owned())
                } else {
                    renamed.get(s).cloned()
                }
            });
        }
        while n.inputs.last() == Some(&None) {
            n.inputs.pop();
        }
        if let Some(pos) = n.extra.get(UI_KEY).and_then(|u| u.get("pos")).cloned() {
            if let Some([x, y]) = serde_json::from_value::<[f64; 2]>(pos)
                .ok()
                .map(|p| [p[0], p[1]])
            {
                set_position(n, [x + offset[0], y + offset[1]]);
            }
        }
    }
    Ok(())
}
