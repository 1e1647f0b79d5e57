//! Wiring edits: a wire between sibling nodes of matching port types that makes no cycle, and the enclosing node's inputs (`@N`, `@meta`) inside a subnet or block.

use std::collections::BTreeSet;

use crate::document::{Document, NetworkDoc, NodeDoc};
use geode_op::{PortType, Registry};

use super::{join, network_mut, node_mut, refuse, split_path, EditError};

/// The port type a node produces, and the type of its input `k` (None when it has no such input).
fn port_types(node: &NodeDoc, registry: &Registry, k: usize) -> (PortType, Option<PortType>) {
    let Some(spec) = crate::node_spec(registry, &node.ty) else {
        return (PortType::Geometry, None);
    };
    let input = spec
        .inputs
        .get(k)
        .or_else(|| spec.variadic.then(|| spec.inputs.last()).flatten())
        .map(|i| i.ty);
    (spec.output, input)
}

pub(super) fn connect(
    d: &mut Document,
    from: &str,
    to: &str,
    input: usize,
    registry: &Registry,
) -> Result<(), EditError> {
    let (pf, from_name) = split_path(from).ok_or_else(|| refuse(from, "not a node path"))?;
    let (pt, to_name) = split_path(to).ok_or_else(|| refuse(to, "not a node path"))?;
    if pf != pt {
        return Err(refuse(to, "wires join nodes of the same network"));
    }
    if from_name.starts_with('@') {
        return connect_inner_input(d, pt, from_name, to_name, input, registry);
    }
    let net = network_mut(d, pt)?;
    let source = net
        .nodes
        .get(from_name)
        .ok_or_else(|| refuse(from, "no such node"))?;
    let target = net
        .nodes
        .get(to_name)
        .ok_or_else(|| refuse(to, "no such node"))?;
    let (out_ty, _) = port_types(source, registry, 0);
    let (_, in_ty) = port_types(target, registry, input);
    let in_ty = in_ty.ok_or_else(|| refuse(to, format!("has no input {}", input + 1)))?;
    if in_ty != out_ty {
        return Err(refuse(
            to,
            format!(
                "input {} takes {in_ty}, but `{from_name}` produces {out_ty}",
                input + 1
            ),
        ));
    }
    if from_name == to_name || upstream(net, from_name).contains(to_name) {
        return Err(refuse(
            to,
            format!("wiring `{from_name}` into it would make a cycle"),
        ));
    }
    let target = net.nodes.get_mut(to_name).expect("checked above");
    if target.inputs.len() <= input {
        target.inputs.resize(input + 1, None);
    }
    target.inputs[input] = Some(from_name.to_owned());
    Ok(())
}

/// Wires one of the enclosing node's inputs inside its network: `@N` (its
/// N-th input, in a block the feedback or piece for `@0`) or `@meta` (a
/// block's pass).
fn connect_inner_input(
    d: &mut Document,
    parent: &str,
    from_name: &str,
    to_name: &str,
    input: usize,
    registry: &Registry,
) -> Result<(), EditError> {
    let to = join(parent, to_name);
    let holder = (parent != "/")
        .then(|| node_mut(d, parent).ok().map(|n| n.ty.clone()))
        .flatten();
    let Some(holder) = holder.filter(|t| crate::holds_network(t)) else {
        return Err(refuse(
            &to,
            format!(
                "`{from_name}` names an input of the enclosing node: only inside a subnet or block"
            ),
        ));
    };
    let valid = match &from_name[1..] {
        "meta" => crate::has_meta(&holder),
        n => n.parse::<usize>().is_ok(),
    };
    if !valid {
        return Err(refuse(
            &to,
            format!(
                "`{from_name}` is no input of a {holder} (`@0`, `@1`..{})",
                if crate::has_meta(&holder) {
                    " or `@meta`"
                } else {
                    ""
                }
            ),
        ));
    }
    let net = network_mut(d, parent)?;
    let target = net
        .nodes
        .get_mut(to_name)
        .ok_or_else(|| refuse(&to, "no such node"))?;
    let (_, in_ty) = port_types(target, registry, input);
    if in_ty.is_none() {
        return Err(refuse(&to, format!("has no input {}", input + 1)));
    }
    if target.inputs.len() <= input {
        target.inputs.resize(input + 1, None);
    }
    target.inputs[input] = Some(from_name.to_owned());
    Ok(())
}

/// Every node `name` depends on, directly or not.
fn upstream<'n>(net: &'n NetworkDoc, name: &'n str) -> BTreeSet<&'n str> {
    let mut seen = BTreeSet::new();
    let mut stack = vec![name];
    while let Some(n) = stack.pop() {
        for i in net
            .nodes
            .get(n)
            .into_iter()
            .flat_map(|n| n.inputs.iter().flatten())
        {
            if seen.insert(i.as_str()) {
                stack.push(i.as_str());
            }
        }
    }
    seen
}
