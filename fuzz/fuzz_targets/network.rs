//! Fuzz target: the network loader (JSON document, node types, parameters, expressions, subnets) must load or return errors on any text, never panic or overflow the stack.
#![no_main]

use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;

/// Built once: the registry is the same for every input.
static REGISTRY: OnceLock<geode_op::Registry> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let registry = REGISTRY.get_or_init(geode_nodes::registry);
    let _ = geode_graph::load_str(text, registry);
});
