//! A cache hit on a node whose output holds 8 million points (seed 004 reports 5 ms).
//! Run: cargo bench -p geode-graph --bench cache

use geode_geo::glam::Vec3;
use geode_geo::Geometry;
use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookContext, CookError, NodeSpec, Operator, Params, Registry, Value};

fn main() {
    divan::main();
}

struct Big;

static BIG: NodeSpec = NodeSpec::new("big", "Big", "bench", "8 million points", &[], &[]);

impl Operator for Big {
    fn spec(&self) -> &'static NodeSpec {
        &BIG
    }
    fn cook(&self, _: &CookContext, _: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
        let mut g = Geometry::new();
        let pts: Vec<Vec3> = (0..8_000_000)
            .map(|i| Vec3::new(i as f32, 0.0, 0.0))
            .collect();
        g.add_points(&pts);
        Ok(Value::geometry(g))
    }
}

#[divan::bench(sample_count = 200)]
fn hit_on_8m_points(bencher: divan::Bencher) {
    let mut reg = Registry::new();
    reg.add(Big);
    let net = load_str(
        r#"{"geode": "network", "version": 1, "output": "b", "nodes": {"b": {"type": "big"}}}"#,
        &reg,
    )
    .unwrap();
    let cache = Cache::new(1 << 30);
    let engine = Engine::new(net, &cache);
    let opts = CookOptions::at_frame(1.0);
    engine.cook_output(&opts).unwrap();
    bencher.bench_local(|| {
        let r = engine.cook_output(&opts).unwrap();
        assert!(r.events[0].hit);
        r
    });
}
