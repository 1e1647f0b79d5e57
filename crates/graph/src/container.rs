//! The node types the graph engine cooks itself (subnet, loop, solver,
//! for_each, time_shift),
//! declared once as `NodeSpec`s: the loader, the catalogue, `geode nodes`,
//! the docs and the studio's Tab menu and wiring all read these.

use geode_op::{InputSpec, NodeSpec, PortType, Registry};

use crate::block::{FOR_EACH_PARAMS, LOOP_PARAMS, SOLVER_PARAMS, TIME_SHIFT_PARAMS};

const fn input(name: &'static str, required: bool) -> InputSpec {
    InputSpec {
        name,
        ty: PortType::Geometry,
        required,
    }
}

/// A subnet's inputs: all optional (an unwired one is an empty `@N`).
static SUBNET_INPUTS: [InputSpec; 4] = [
    input("input 1", false),
    input("input 2", false),
    input("input 3", false),
    input("input 4", false),
];

/// A loop's or solver's inputs: the first starts the feedback.
static BLOCK_INPUTS: [InputSpec; 4] = [
    input("input 1", true),
    input("input 2", false),
    input("input 3", false),
    input("input 4", false),
];

pub static SUBNET: NodeSpec = NodeSpec::new(
    "subnet",
    "Subnetwork",
    "flow",
    "A network inside a node. Inner nodes read the subnet's inputs as @0, @1...; its output is the inner network's output or display node, and promoted parameters drive inner nodes.",
    &SUBNET_INPUTS,
    &[],
)
.spare_params();

pub static LOOP: NodeSpec = NodeSpec::new(
    "loop",
    "For-Loop with Feedback",
    "flow",
    "Cooks its network a number of times, each pass on the previous pass's result. Inside, @0 is that feedback, @1.. the loop's other inputs, and @meta a geometry whose detail attributes iteration and numiterations give the pass; a non-zero detail attribute named by Stop ends the loop early.",
    &BLOCK_INPUTS,
    &LOOP_PARAMS,
)
.spare_params();

pub static SOLVER: NodeSpec = NodeSpec {
    time_dependent: true,
    ..NodeSpec::new(
        "solver",
        "Solver",
        "flow",
        "Cooks its network once per frame on the previous frame's result. Inside, @0 is that result (the input at the start frame), @1.. the solver's other inputs at the frame, and @meta a geometry whose detail attributes frame and start_frame give the pass. Scrubbing forward reuses every cached frame.",
        &BLOCK_INPUTS,
        &SOLVER_PARAMS,
    )
    .spare_params()
};

pub static FOR_EACH: NodeSpec = NodeSpec::new(
    "for_each",
    "For-Each",
    "flow",
    "Cooks its network once per piece of its input (connected pieces, or the values of a primitive attribute) and merges the results in piece order; or, by count, a number of passes each on the previous pass's result. Pieces cook in parallel and the merge is the same at any thread count. Inside, @0 is the piece (or the feedback), @1.. the block's other inputs, and @meta a geometry whose detail attributes iteration, numiterations and value (the piece's number or attribute value) give the pass.",
    &BLOCK_INPUTS,
    &FOR_EACH_PARAMS,
)
.spare_params();

/// One input, required.
static SHIFT_INPUT: [InputSpec; 1] = [input("input 1", true)];

pub static TIME_SHIFT: NodeSpec = NodeSpec {
    time_dependent: true,
    ..NodeSpec::new(
        "time_shift",
        "Time Shift",
        "flow",
        "Its input as it cooks at another frame: the current one plus an offset, or a frame given (an expression of $F), optionally clamped to a range (Houdini's Time Shift). Nothing upstream cooks at the current frame.",
        &SHIFT_INPUT,
        &TIME_SHIFT_PARAMS,
    )
};

/// The engine's own node types.
pub fn containers() -> [&'static NodeSpec; 5] {
    [&SUBNET, &LOOP, &SOLVER, &FOR_EACH, &TIME_SHIFT]
}

/// Whether node type `ty` holds a network (the engine's own types but
/// time_shift, which only reads its input at another frame).
pub fn holds_network(ty: &str) -> bool {
    container_spec(ty).is_some() && ty != TIME_SHIFT.name
}

/// Whether the network inside node type `ty` reads `@meta` (the blocks:
/// loop, solver, for_each; not a subnet).
pub fn has_meta(ty: &str) -> bool {
    holds_network(ty) && ty != SUBNET.name
}

/// The declaration of one of the engine's own node types (nodes that hold
/// a network), if `ty` names one.
pub fn container_spec(ty: &str) -> Option<&'static NodeSpec> {
    containers().into_iter().find(|s| s.name == ty)
}

/// The declaration of any node type: the registry's or the engine's own.
pub fn node_spec<'r>(registry: &'r Registry, ty: &str) -> Option<&'r NodeSpec> {
    registry
        .get(ty)
        .map(|op| op.spec())
        .or_else(|| container_spec(ty))
}

/// Every node type's declaration, the engine's own included, in name order.
pub fn node_specs(registry: &Registry) -> Vec<&NodeSpec> {
    let mut all: Vec<&NodeSpec> = registry.iter().map(|op| op.spec()).collect();
    all.extend(containers());
    all.sort_by_key(|s| s.name);
    all
}

/// Up to three node type names closest to `ty`, the engine's own included.
pub fn closest_types(registry: &Registry, ty: &str) -> Vec<&'static str> {
    let mut scored: Vec<(usize, &'static str)> = registry
        .closest(ty)
        .into_iter()
        .chain(containers().iter().map(|s| s.name))
        .map(|k| (geode_op::edit_distance(ty, k), k))
        .filter(|(d, k)| *d <= (k.len().max(ty.len()) / 2).max(2))
        .collect();
    scored.sort();
    scored.dedup();
    scored.into_iter().take(3).map(|(_, k)| k).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn containers_are_found_by_name_and_typos_suggest_them() {
        let reg = Registry::new();
        assert_eq!(
            node_spec(&reg, "loop").map(|s| s.label),
            Some("For-Loop with Feedback")
        );
        assert!(node_spec(&reg, "solver").unwrap().time_dependent);
        assert_eq!(closest_types(&reg, "lop"), vec!["loop"]);
        assert_eq!(closest_types(&reg, "subnt"), vec!["subnet"]);
        assert!(BLOCK_INPUTS[0].required && !SUBNET_INPUTS[0].required);
    }
}
