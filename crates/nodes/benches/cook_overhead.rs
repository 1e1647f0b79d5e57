//! What a node's cook costs beyond its kernel (issue 34), on a 3162 x 3162
//! grid with point normals (10.0M points, 10.0M quads): the `wrangle`
//! (`@P += @N * 0.1;`) and `transform` nodes cooked through the engine,
//! their input held ready (an operator handing out the same shared
//! geometry, as a cache hit does), beside their kernels alone on a copy
//! they own. Goal: each node at most 60 ms (6 ns a point), the wrangle
//! within 1.5x of the transform. Asked for itself, a node's output is
//! not hashed (nothing reads it); `_read` rows add a `null` reading it, so
//! the node hashes its output for the null's key (the null costs nothing).
//! The same in a trace: `geode --trace t.json cook examples/grid_wrangle.json
//! --set grid/rows=3162 --set grid/columns=3162` (the wrangle's output is
//! read, the transform's not).
//! Run: cargo bench -p geode-nodes --bench cook_overhead

use std::sync::{Arc, OnceLock};

use divan::Bencher;
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry};
use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookContext, CookError, NodeSpec, Operator, Params, Value};
use geode_vex::{BindSpec, Channel, RunOptions};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

const SNIPPET: &str = "@P += @N * 0.1;";
const DIVISIONS: u32 = 3162;

/// grid(3162 x 3162) -> normals, cooked once by the engine.
fn input() -> &'static Arc<Geometry> {
    static G: OnceLock<Arc<Geometry>> = OnceLock::new();
    G.get_or_init(|| {
        let net = format!(
            r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{
                "g": {{"type": "grid", "params": {{"size": [100, 100], "rows": {DIVISIONS}, "columns": {DIVISIONS}}}}},
                "n": {{"type": "normals", "inputs": ["g"], "params": {{"class": "point"}}}}}}}}"#
        );
        let net = load_str(&net, &geode_nodes::registry()).unwrap();
        let cache = Cache::disabled();
        let r = Engine::new(net, &cache)
            .cook_output(&CookOptions::at_frame(1.0))
            .unwrap();
        let g = Arc::clone(r.value.as_geometry().unwrap());
        assert!(g.attrib(AttribClass::Point, "N").is_some());
        g
    })
}

static HELD: NodeSpec = NodeSpec::new("held", "Held", "bench", "The bench's input", &[], &[]);

/// Hands out the input geometry, shared, as a cache hit upstream would.
struct Held;

impl Operator for Held {
    fn spec(&self) -> &'static NodeSpec {
        &HELD
    }
    fn cook(&self, _: &CookContext, _: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
        Ok(Value::Geometry(Arc::clone(input())))
    }
}

/// `held -> node` (`-> null` when `read`), cooked without a cache so every
/// cook runs the node.
fn node(bencher: Bencher, node: &str, read: bool) {
    input().content_hash();
    let mut reg = geode_nodes::registry();
    reg.add(Held);
    let net = format!(
        r#"{{"geode": "network", "version": 1, "output": "{}", "nodes": {{
            "in": {{"type": "held"}}, "x": {node},
            "y": {{"type": "null", "inputs": ["x"]}}}}}}"#,
        if read { "y" } else { "x" }
    );
    let net = load_str(&net, &reg).unwrap();
    let cache = Cache::disabled();
    let engine = Engine::new(net, &cache);
    let opts = CookOptions::at_frame(1.0);
    bencher.bench_local(|| {
        let r = engine.cook_output(&opts).unwrap();
        assert!(r.events.iter().all(|e| !e.hit));
        r
    });
}

fn wrangle() -> String {
    format!(r#"{{"type": "wrangle", "inputs": ["in"], "params": {{"snippet": "{SNIPPET}"}}}}"#)
}

const TRANSFORM: &str = r#"{"type": "transform", "inputs": ["in"], "params": {"translate": [1, 2, 3], "rotate": [10, 20, 30]}}"#;

#[divan::bench(sample_count = 10, sample_size = 1)]
fn wrangle_node(bencher: Bencher) {
    node(bencher, &wrangle(), false);
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn wrangle_node_read(bencher: Bencher) {
    node(bencher, &wrangle(), true);
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn transform_node(bencher: Bencher) {
    node(bencher, TRANSFORM, false);
}

#[divan::bench(sample_count = 10, sample_size = 1)]
fn transform_node_read(bencher: Bencher) {
    node(bencher, TRANSFORM, true);
}

/// A copy of the input whose P the kernel owns (made outside the timing).
fn owned() -> Geometry {
    let mut g = Geometry::clone(input());
    g.positions_mut();
    g
}

/// The wrangle kernel alone: `geode_vex::run` on a geometry it owns.
#[divan::bench(sample_count = 10, sample_size = 1)]
fn wrangle_kernel(bencher: Bencher) {
    let g = input();
    let none = |_: &str| -> Option<Channel> { None };
    let names = Vec::new;
    let spec = BindSpec {
        run_over: AttribClass::Point,
        inputs: vec![Some(g.as_ref())],
        channels: &none,
        channel_names: &names,
        frame: 1.0,
        time: 0.0,
    };
    let program = geode_vex::compile(SNIPPET, &spec).unwrap();
    let cancel = || false;
    bencher.with_inputs(owned).bench_local_values(|mut out| {
        geode_vex::run(
            &program,
            &mut out,
            &[Some(g.as_ref())],
            &RunOptions {
                group: None,
                cancel: &cancel,
                memory_budget: u64::MAX,
            },
        )
        .unwrap();
        out
    });
}

/// The transform kernel alone: in place on a geometry it owns (P and N).
#[divan::bench(sample_count = 10, sample_size = 1)]
fn transform_kernel(bencher: Bencher) {
    let m = geode_geo::ops::trs(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(0.2, 0.3, 0.5),
        Vec3::ONE,
    );
    bencher
        .with_inputs(|| {
            let mut g = owned();
            g.attribs_mut(AttribClass::Point)
                .get_mut("N")
                .and_then(|a| a.as_vec3_mut());
            g
        })
        .bench_local_values(|mut g| {
            geode_geo::ops::transform(&mut g, m);
            g
        });
}
