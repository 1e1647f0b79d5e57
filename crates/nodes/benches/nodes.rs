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
    /// The peer's time or the issue's goal; none where neither exists.
    goal_ms: Option<f64>,
}

enum Network {
    Example(&'static str),
    /// An example with more nodes (a JSON object of node entries).
    Extended(&'static str, &'static str),
}

fn example(file: &str) -> String {
    let path = format!("{}/../../examples/{file}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

impl Network {
    fn text(&self) -> String {
        match self {
            Network::Example(file) => example(file),
            Network::Extended(file, extra) => {
                let mut doc: serde_json::Value = serde_json::from_str(&example(file)).unwrap();
                let extra: serde_json::Map<String, serde_json::Value> =
                    serde_json::from_str(extra).unwrap();
                doc["nodes"].as_object_mut().unwrap().extend(extra);
                doc.to_string()
            }
        }
    }
}

fn rows() -> Vec<Row> {
    vec![
        Row {
            name: "coral smooth join (frep_sweep + polygonise), frame 61, depth 7",
            network: Network::Example("coral.json"),
            pull: "/smooth",
            frame: 61.0,
            timed: &["/skeleton", "/smooth"],
            goal_ms: Some(300.0),
        },
        Row {
            name: "gyroid part (distance offset, polygonise), depth 7",
            network: Network::Example("frep_gyroid_part.json"),
            pull: "/mesh",
            frame: 1.0,
            timed: &["/inner", "/mesh"],
            goal_ms: None,
        },
        Row {
            name: "wall_thickness of the gyroid part (310k triangles)",
            network: Network::Extended(
                "frep_gyroid_part.json",
                r#"{"measured": {"type": "wall_thickness", "inputs": ["mesh"]}}"#,
            ),
            pull: "/measured",
            frame: 1.0,
            timed: &["/measured"],
            goal_ms: None,
        },
    ]
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
        let (mark, goal) = match row.goal_ms {
            Some(goal) if median > goal => (" (over)", format!("≤ {goal} ms")),
            Some(goal) => ("", format!("≤ {goal} ms")),
            None => ("", "—".to_string()),
        };
        println!("| {} | {median:.1} ms{mark} | {goal} |", row.name);
    }
}
