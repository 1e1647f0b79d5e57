//! Resource guards: requests too big for memory (a wrangle's included) are
//! refused before anything is allocated, promptly, with a message naming the node, the parameter,
//! the estimate and the budget. One test, so the process's peak memory
//! (VmHWM) reflects these cooks alone.

use std::time::{Duration, Instant};

use geode_graph::{load_str, Cache, CookOptions, Engine};
use geode_op::{CookEnv, ErrorKind};

/// 8 GiB, fixed so the messages are exact on any machine.
const BUDGET: u64 = 8 << 30;

fn refused(nodes: &str, hip: &str) -> (String, Duration) {
    refused_within(nodes, hip, BUDGET)
}

fn refused_within(nodes: &str, hip: &str, budget: u64) -> (String, Duration) {
    let text =
        format!(r#"{{"geode": "network", "version": 1, "output": "n", "nodes": {{{nodes}}}}}"#);
    let net = load_str(&text, &geode_nodes::registry()).unwrap_or_else(|e| panic!("{e:?}"));
    let cache = Cache::new(1 << 30);
    let engine = Engine::new(net, &cache);
    let mut opts = CookOptions::at_frame(1.0);
    opts.env = CookEnv {
        hip: hip.into(),
        fps: 24.0,
        memory_budget: budget,
        files: geode_op::FileAccess::anywhere(),
        nesting: Vec::new(),
        held: Default::default(),
    };
    // Inputs first: the time measured is the guarded node's.
    for e in engine
        .network()
        .paths()
        .filter(|p| *p != "/n")
        .map(str::to_owned)
        .collect::<Vec<_>>()
    {
        engine.cook(&e, &opts).unwrap_or_else(|e| panic!("{e:?}"));
    }
    let t = Instant::now();
    let Err(e) = engine.cook("/n", &opts) else {
        panic!("not refused")
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

fn corpus(name: &str) -> String {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../corpus/opensubdiv")
        .join(name);
    p.canonicalize().unwrap().to_string_lossy().into_owned()
}

#[test]
fn oversized_requests_are_refused_promptly_with_exact_messages() {
    let dir = tempfile::tempdir().unwrap();
    let hip = dir.path().to_str().unwrap();
    let cases = [
        (
            "grid 65536 x 65536".to_string(),
            r#""n": {"type": "grid", "params": {"rows": 65536, "columns": 65536}}"#.to_string(),
            "/n (parameter `columns`): 4.3 billion points and 4.3 billion primitives would need about 722 GB, more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)",
        ),
        (
            "subdivide catmark_car level 8".into(),
            format!(
                r#""f": {{"type": "file", "params": {{"file": "{}"}}}},
                   "n": {{"type": "subdivide", "params": {{"levels": 8}}, "inputs": ["f"]}}"#,
                corpus("catmark_car.obj")
            ),
            "/n (parameter `levels`): 103.2 million quads at level 8 would need about 41.3 GB, more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)",
        ),
        (
            "polygonise depth 12".into(),
            r#""s": {"type": "frep_sphere", "params": {"radius": 0.9}},
               "n": {"type": "polygonise", "params": {"depth": 12, "min": [-1, -1, -1], "max": [1, 1, 1]}, "inputs": ["s"]}"#.into(),
            "",
        ),
        (
            "1M packed copies written to .ply".into(),
            r#""ball": {"type": "sphere", "params": {"radius": 0.03, "rows": 51, "columns": 100}},
               "field": {"type": "grid", "params": {"size": [100, 100], "rows": 999, "columns": 999}},
               "copies": {"type": "copy_to_points", "inputs": ["ball", "field"]},
               "n": {"type": "write", "params": {"file": "$HIP/million.ply"}, "inputs": ["copies"]}"#.into(),
            "",
        ),
        (
            "hspline tessellated 10000 x 10000".into(),
            r#""n": {"type": "hspline", "params": {"samples": [10000, 10000]}}"#.into(),
            "/n (parameter `samples`): 100.0 million points and 100.0 million primitives would need about 16.8 GB, more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)",
        ),
        (
            "scatter 100M blue-noise points".into(),
            r#""s": {"type": "sphere"}, "n": {"type": "scatter", "params": {"mode": "surface", "count": 100000000, "relax": true}, "inputs": ["s"]}"#.into(),
            "/n (parameter `count`): scattering 100000000 points would need about 122 GB, more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)",
        ),
        (
            "resample a helix every nanometre".into(),
            r#""c": {"type": "curve_helix"}, "n": {"type": "resample", "params": {"length": 1e-9}, "inputs": ["c"]}"#.into(),
            "/n (parameter `length`): 18.9 billion points and 1 primitive would need about 1.4 TB, more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)",
        ),
    ];
    for (name, nodes, want) in &cases {
        let (msg, dt) = refused(nodes, hip);
        eprintln!("{name}: refused in {:.1} ms: {msg}", dt.as_secs_f64() * 1e3);
        if !want.is_empty() {
            assert_eq!(&msg, want, "{name}");
        }
        assert!(
            dt < Duration::from_millis(500),
            "{name} took {dt:?} to refuse"
        );
    }
    let (poly, _) = refused(&cases[2].1, hip);
    assert!(
        poly.starts_with("/n (parameter `depth`): meshing at depth 12 (")
            && poly.contains(" million cells with surface) would need about ")
            && poly.ends_with("more than the memory budget of 8.6 GB (GEODE_MEMORY_MB)"),
        "{poly}"
    );
    let (ply, _) = refused(&cases[3].1, hip);
    assert!(
        ply.starts_with(&format!("/n (parameter `file`): {hip}/million.ply: unpacking 1000000 packed instances for this format would need about ")),
        "{ply}"
    );
    assert!(
        ply.ends_with("GB (GEODE_MEMORY_MB); write .glb or .usda, which keep instances"),
        "{ply}"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing written"
    );
    wrangles_within_a_small_budget(hip);
    if let Some(peak) = peak_rss_bytes() {
        eprintln!("peak resident memory: {} MB", peak >> 20);
        assert!(peak < 1 << 30, "peak {} MB", peak >> 20);
    }
}

/// The requests that once exhausted the machine from a wrangle (a
/// two-billion-element array, a string doubled forever, a large array on
/// every point) are refused within 512 MiB, the process never nearing them.
fn wrangles_within_a_small_budget(hip: &str) {
    let wrangle = |class: &str, snippet: &str| {
        let nodes = serde_json::json!({
            "g": {"type": "grid", "params": {"rows": 10, "columns": 10}},
            "n": {"type": "wrangle", "params": {"run_over": class, "snippet": snippet}, "inputs": ["g"]},
        })
        .to_string();
        refused_within(&nodes[1..nodes.len() - 1], hip, 512 << 20)
    };
    let (msg, dt) = wrangle("detail", "int a[];\nresize(a, 2000000000);\ni[]@a = a;");
    assert_eq!(
        msg,
        "/n (parameter `snippet`): element 0 (line 2, column 1): resize to 2000000000 elements would need 8.0 GB, more than the 537 MB left of the memory budget of 537 MB (GEODE_MEMORY_MB)"
    );
    assert!(dt < Duration::from_millis(500), "{dt:?}");
    let (msg, dt) = wrangle(
        "detail",
        "string s = \"ab\";\nwhile (1) {\n    s = s + s;\n}\ns@s = s;",
    );
    assert!(
        // Refused at the join (column 11) or at the copy that assigns it
        // (column 7), whichever first outgrows what is left.
        (msg.starts_with("/n (parameter `snippet`): element 0 (line 3, column 11): ")
            || msg.starts_with("/n (parameter `snippet`): element 0 (line 3, column 7): "))
            && msg.contains(" would need ")
            && msg.ends_with("of the memory budget of 537 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(dt < Duration::from_secs(5), "{dt:?}");
    // Points and primitives made without end (their lists double as they
    // grow: each doubling is asked for first).
    let (msg, dt) = wrangle(
        "detail",
        "while (1) {\n    int p = addpoint(0, {0, 0, 0});\n    addprim(0, \"polyline\", p, p);\n}",
    );
    assert!(
        (msg.contains("(line 2, column 13): ") || msg.contains("(line 3, column 5): "))
            && msg.contains("queueing")
            && msg.ends_with("of the memory budget of 537 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(dt < Duration::from_secs(20), "{dt:?}");
    let (msg, dt) = wrangle("points", "int a[];\nresize(a, 100000000);\ni[]@a = a;");
    assert!(
        msg.contains(
            "(line 2, column 1): resize to 100000000 elements would need 400 MB, more than the "
        ) && msg.ends_with("left of the memory budget of 537 MB (GEODE_MEMORY_MB)"),
        "{msg}"
    );
    assert!(dt < Duration::from_secs(5), "{dt:?}");
}
