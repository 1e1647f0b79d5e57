//! `GEODE_CACHE_DIR` end to end: a second process reads every node from the disk cache and writes the same bytes; `geode cache stats` and `gc`.

mod common;

use std::process::{Command, Output};

use common::{geode, root, stderr};

/// The `--stats` lines: (node type, hit kind).
fn sources(o: &Output) -> Vec<(String, String)> {
    stderr(o)
        .lines()
        .filter(|l| l.starts_with("  /"))
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            (w[1].to_owned(), w[2].to_owned())
        })
        .collect()
}

#[test]
fn a_second_process_reads_every_node_from_disk_and_writes_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let env = [("GEODE_CACHE_DIR", cache.to_str().unwrap())];
    let mut outputs = Vec::new();
    let mut runs = Vec::new();
    for run in 0..2 {
        let out = dir.path().join(format!("coral{run}.bgeo"));
        let o = geode(
            &[
                "cook",
                "examples/coral.json",
                "--frame",
                "20",
                "--stats",
                "-o",
                out.to_str().unwrap(),
            ],
            &env,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        outputs.push(std::fs::read(&out).unwrap());
        runs.push(sources(&o));
    }
    assert!(!runs[0].is_empty());
    assert!(runs[0].iter().all(|(_, k)| k == "cook"), "{:?}", runs[0]);
    // Every node, fields (the coral's ellipsoid and sweep) included.
    assert!(runs[1].iter().all(|(_, k)| k == "disk"), "{:?}", runs[1]);
    assert!(runs[1].iter().any(|(t, _)| t == "frep_sweep"));
    assert_eq!(runs[0].len(), runs[1].len());
    assert!(
        outputs[0] == outputs[1],
        "the cached cook wrote other bytes"
    );

    let stats = geode(&["cache", "stats", "--dir", cache.to_str().unwrap()], &[]);
    let text = String::from_utf8_lossy(&stats.stdout).into_owned();
    assert!(
        text.contains(&format!("entries:     {}", runs[0].len())),
        "{text}"
    );
    let gc = geode(
        &[
            "cache",
            "gc",
            "--dir",
            cache.to_str().unwrap(),
            "--max-mb",
            "0",
        ],
        &[],
    );
    assert!(gc.status.success(), "{}", stderr(&gc));
    let after = geode(&["cache", "stats", "--dir", cache.to_str().unwrap()], &[]);
    assert!(String::from_utf8_lossy(&after.stdout).contains("entries:     0"));
    // Without the variable or --dir: a clear error, not a default folder.
    let none = geode(&["cache", "stats"], &[]);
    assert!(!none.status.success());
    assert!(
        stderr(&none).contains("no disk cache: pass --dir or set GEODE_CACHE_DIR"),
        "{}",
        stderr(&none)
    );
}

/// Two processes cooking the same network into one cache at once leave
/// whole entries: a third reads every geometry from disk, the trace marks
/// the hits as the store's, and the output equals the first two.
#[test]
fn two_processes_writing_at_once_leave_whole_entries() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let spawn = |out: &str| {
        Command::new(env!("CARGO_BIN_EXE_geode"))
            .args([
                "cook",
                "examples/chain.json",
                "-o",
                dir.path().join(out).to_str().unwrap(),
            ])
            .current_dir(root())
            .env("GEODE_CACHE_DIR", &cache)
            .spawn()
            .unwrap()
    };
    let (mut a, mut b) = (spawn("a.bgeo"), spawn("b.bgeo"));
    assert!(a.wait().unwrap().success() && b.wait().unwrap().success());
    let trace = dir.path().join("trace.json");
    let c = geode(
        &[
            "--trace",
            trace.to_str().unwrap(),
            "cook",
            "examples/chain.json",
            "--stats",
            "-o",
            dir.path().join("c.bgeo").to_str().unwrap(),
        ],
        &[("GEODE_CACHE_DIR", cache.to_str().unwrap())],
    );
    assert!(c.status.success(), "{}", stderr(&c));
    assert!(
        sources(&c).iter().all(|(_, k)| k == "disk"),
        "{:?}",
        sources(&c)
    );
    let text = std::fs::read_to_string(&trace).unwrap();
    assert!(
        text.contains(r#""store":"true""#) && !text.contains(r#""hit":"false""#),
        "{text}"
    );
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert!(read("a.bgeo") == read("c.bgeo") && read("b.bgeo") == read("c.bgeo"));
    let stray: Vec<_> = std::fs::read_dir(&cache)
        .unwrap()
        .flatten()
        .flat_map(|d| std::fs::read_dir(d.path()).unwrap().flatten())
        .filter(|f| f.file_name().to_string_lossy().starts_with(".geode-tmp"))
        .collect();
    assert!(stray.is_empty(), "temporary files left");
}
