//! Node-level benchmarks: workloads cooked through the engine as users cook
//! them, timed by the spans of the nodes that do the work (the engine's cook
//! events; upstream nodes and file I/O excluded), median of a few runs,
//! printed as one table with each row's goal.
//! Run: cargo bench -p geode-nodes --bench nodes [-- FILTER]

use std::time::Duration;

use geode_graph::{load_str, Cache, CookOptions, Engine};

/// One workload: a network, the node pulled, the frame, and the nodes whose
/// spans make the row's figure.
struct Row {
    name: &'static str,
    network: Network,
    pull: &'static str,
    frame: f64,
    timed: &'static [&'static str],
    goal_ms: f64,
}

enum Network {
    Example(&'static str),
}

impl Network {
    fn text(&self) -> String {
        match self {
            Network::Example(file) => {
                let path = format!("{}/../../examples/{file}", env!("CARGO_MANIFEST_DIR"));
                std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
            }
        }
    }
}

fn rows() -> Vec<Row> {
    vec![Row {
        name: "coral smooth join (frep_sweep + polygonise), frame 61, depth 7",
        network: Network::Example("coral.json"),
        pull: "/smooth",
        frame: 61.0,
        timed: &["/skeleton", "/smooth"],
        goal_ms: 300.0,
    }]
}

/// The summed spans of `row.timed` in one cold cook (cache off).
fn run_once(row: &Row) -> Duration {
    let net = load_str(&row.network.text(), &geode_nodes::registry())
        .unwrap_or_else(|e| panic!("{}: {e:?}", row.name));
    let cache = Cache::disabled();
    let result = Engine::new(net, &cache)
        .cook(row.pull, &CookOptions::at_frame(row.frame))
        .unwrap_or_else(|e| panic!("{}: {e:?}", row.name));
    let seconds: f64 = row
        .timed
        .iter()
        .map(|path| {
            result
                .events
                .iter()
                .find(|e| e.path == *path)
                .unwrap_or_else(|| panic!("{}: {path} did not cook", row.name))
                .seconds
        })
        .sum();
    Duration::from_secs_f64(seconds)
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let runs = 3;
    println!("| workload | median of {runs} | goal |");
    println!("|---|---|---|");
    for row in rows() {
        if filter.as_deref().is_some_and(|f| !row.name.contains(f)) {
            continue;
        }
        let mut times: Vec<Duration> = (0..runs).map(|_| run_once(&row)).collect();
        times.sort();
        let median = times[runs / 2].as_secs_f64() * 1e3;
        let mark = if median <= row.goal_ms { "" } else { " (over)" };
        println!(
            "| {} | {median:.1} ms{mark} | ≤ {} ms |",
            row.name, row.goal_ms
        );
    }
}
