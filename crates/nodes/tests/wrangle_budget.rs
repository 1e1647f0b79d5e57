//! A wrangle within the memory budget, through the engine: the requests
//! that once exhausted the machine (a two-billion-element array, a string
//! doubled forever, a large array on every point) are refused as resource
//! errors naming the node, the snippet's line and the size, promptly and
//! without the process's memory ever nearing them. One test, so the
//! process's peak memory (VmHWM) reflects these cooks alone.

use std::time::{Duration, Instant};

use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookEnv, ErrorKind};

/// 512 MiB, fixed so the messages are exact on any machine.
const BUDGET: u64 = 512 << 20;

fn refused(snippet: &str, class: &str) -> (String, Duration) {
    let nodes = serde_json::json!({
        "g": {"type": "grid", "params": {"rows": 10, "columns": 10}},
        "n": {"type": "wrangle", "params": {"run_over": class, "snippet": snippet}, "inputs": ["g"]},
    });
    let text = serde_json::json!({"geode": "network", "version": 1, "output": "n", "nodes": nodes})
        .to_string();
    let net = load_str(&text, &geode_nodes::registry()).unwrap_or_else(|e| panic!("{e:?}"));
    let cache = Cache::new(1 << 30);
    let engine = Engine::new(net, &cache);
    let mut opts = CookOptions::at_frame(1.0);
    opts.env = CookEnv {
        hip: ".".into(),
        fps: 24.0,
        memory_budget: BUDGET,
        files: geode_op::FileAccess::anywhere(),
    };
    engine.cook("/g", &opts).unwrap_or_else(|e| panic!("{e:?}"));
    let t = Instant::now();
    let Err(e) = engine.cook("/n", &opts) else {
        panic!("{snippet}: not refused")
    };
    let dt = t.elapsed();
    assert_eq!(e.len(), 1);
    assert_eq!(e[0].kind, ErrorKind::Resource, "{}", e[0]);
    (e[0].to_string(), dt)
}

fn peak_rss_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let kb: u64 = s
        .lines()
        .find(|l| l.starts_with("VmHWM:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()?;
    Some(kb * 1024)
}

#[test]
fn wrangles_that_ask_for_too_much_memory_are_refused() {
    let (msg, dt) = refused("int a[];\nresize(a, 2000000000);\ni[]@a = a;", "detail");
    assert_eq!(
        msg,
        "/n (parameter `snippet`): element 0 (line 2, column 1): resize to 2000000000 elements would need 8.0 GB, more than the 537 MB left of the memory budget of 537 MB (GEODE_MEMORY_MB)"
    );
    assert!(dt < Duration::from_millis(500), "{dt:?}");

    let (msg, dt) = refused(
        "string s = \"ab\";\nwhile (1) {\n    s = s + s;\n}\ns@s = s;",
        "detail",
    );
    assert!(
        msg.starts_with("/n (parameter `snippet`): element 0 (line 3, column 11): ")
            && msg.contains(" would need ")
            && msg.ends_with("of the memory budget of 537 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(dt < Duration::from_secs(5), "{dt:?}");

    let (msg, dt) = refused("int a[];\nresize(a, 100000000);\ni[]@a = a;", "points");
    assert!(
        msg.contains(
            "(line 2, column 1): resize to 100000000 elements would need 400 MB, more than the "
        ) && msg.ends_with("left of the memory budget of 537 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(dt < Duration::from_secs(5), "{dt:?}");

    if let Some(peak) = peak_rss_bytes() {
        eprintln!("peak resident memory: {} MB", peak >> 20);
        assert!(peak < 1 << 30, "peak {} MB", peak >> 20);
    }
}
