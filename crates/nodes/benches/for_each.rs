//! The for-each block's cost per piece (issue 36): 10,000 boxes (one per
//! point of a 100 x 100 grid) cooked through a for-each over connected
//! pieces whose network is a `null` (the overhead alone) or a transform
//! (a light real pass), beside the same boxes without the loop. The cache
//! is off, so every pass cooks. Per-piece overhead = (for-each - boxes) /
//! 10,000.
//! Run: cargo bench -p geode-nodes --bench for_each

use divan::Bencher;
use geode_graph::{load_str, Cache, CookOptions, Engine};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn network(inner: &str, output: &str) -> String {
    format!(
        r#"{{"geode": "network", "version": 1, "output": "{output}", "nodes": {{
            "g": {{"type": "grid", "params": {{"size": [300, 300], "rows": 99, "columns": 99}}}},
            "b": {{"type": "box", "params": {{"size": [1, 1, 1]}}}},
            "c": {{"type": "copy_to_points", "inputs": ["b", "g"], "params": {{"pack": false}}}},
            "f": {{"type": "for_each", "inputs": ["c"],
                   "network": {{"output": "step", "nodes": {{"step": {inner}}}}}}}}}}}"#
    )
}

fn cook(text: &str, pieces: usize) {
    let net = load_str(text, &geode_nodes::registry()).unwrap();
    let cache = Cache::disabled();
    let r = Engine::new(net, &cache)
        .cook_output(&CookOptions::at_frame(1.0))
        .unwrap();
    assert_eq!(r.value.as_geometry().unwrap().num_prims(), pieces * 6);
}

const NULL: &str = r#"{"type": "null", "inputs": ["@0"]}"#;
const MOVE: &str = r#"{"type": "transform", "inputs": ["@0"], "params": {"translate": [0, 1, 0]}}"#;

#[divan::bench(sample_count = 5, sample_size = 1)]
fn boxes_10k_without_the_loop(bencher: Bencher) {
    let text = network(NULL, "c");
    bencher.bench(|| cook(&text, 10_000));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn for_each_10k_pieces_null(bencher: Bencher) {
    let text = network(NULL, "f");
    bencher.bench(|| cook(&text, 10_000));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn for_each_10k_pieces_transform(bencher: Bencher) {
    let text = network(MOVE, "f");
    bencher.bench(|| cook(&text, 10_000));
}
