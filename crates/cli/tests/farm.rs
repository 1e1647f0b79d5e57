//! `geode farm` end to end on the local scheduler and on a real one-machine Slurm cluster (`tools/slurm.sh`, started by `.ci/run`): outputs equal local cooks byte for byte, a failing task is retried and reported with its log, the Kubernetes manifest indexes the tasks.

mod common;

use std::path::Path;

use common::{geode_in, root, slurm_cluster, stderr};

/// `geode ARGS` in `dir`.
fn run(args: &[&str], dir: &Path) -> std::process::Output {
    geode_in(dir, args, &[])
}

fn example(name: &str) -> String {
    root().join("examples").join(name).display().to_string()
}

/// 24 frames of the coral and a 3-value wedge of the chain, farmed, then
/// the same cooked by `geode cook`: every file equal byte for byte.
fn farms_equal_local_cooks(scheduler: &str) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let farm = |args: &[&str]| {
        let mut all = vec![
            "farm",
            "--scheduler",
            scheduler,
            "--jobs",
            "2",
            "--cache-dir",
            "cache",
        ];
        all.extend(args);
        // Slurm arrays of 10: the 24 frames go as three arrays, offset.
        let o = geode_in(d, &all, &[("GEODE_SLURM_MAX_ARRAY", "10")]);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let coral = example("coral.json");
    let o = farm(&[
        &coral,
        "--frames",
        "1-24",
        "--farm-dir",
        "f1",
        "-o",
        "farm/coral/$F4.bgeo",
    ]);
    if scheduler == "slurm" {
        let err = stderr(&o);
        let line = err
            .lines()
            .find(|l| l.starts_with("farm: submitted job array"))
            .unwrap();
        let ids = line["farm: submitted job array ".len()..]
            .split(" (")
            .next()
            .unwrap();
        assert_eq!(
            ids.split(", ").count(),
            3,
            "three arrays of at most 10: {line}"
        );
    }
    assert!(stderr(&o).contains("farm: 24 tasks done"), "{}", stderr(&o));
    let chain = example("chain.json");
    farm(&[
        &chain,
        "--wedge",
        "/spacing/count=48,96,192",
        "--farm-dir",
        "f2",
        "-o",
        "farm/$WEDGE/$F4.bgeo",
    ]);

    std::fs::create_dir_all(d.join("local/coral")).unwrap();
    let o = run(
        &[
            "cook",
            &coral,
            "--frames",
            "1-24",
            "-o",
            "local/coral/$F4.bgeo",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in 1..=24 {
        let name = format!("coral/{f:04}.bgeo");
        let (a, b) = (
            std::fs::read(d.join("farm").join(&name)).unwrap(),
            std::fs::read(d.join("local").join(&name)).unwrap(),
        );
        assert!(a == b, "{scheduler}: {name} differs from the local cook");
    }
    for count in [48, 96, 192] {
        let out = d.join(format!("local/count_{count}.bgeo"));
        let o = run(
            &[
                "cook",
                &chain,
                "--set",
                &format!("/spacing/count={count}"),
                "-o",
                out.to_str().unwrap(),
            ],
            d,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let farmed = std::fs::read(d.join(format!("farm/count_{count}/0001.bgeo"))).unwrap();
        assert!(
            farmed == std::fs::read(&out).unwrap(),
            "{scheduler}: wedge count={count} differs"
        );
    }
    // The variants really differ: the wedge set the parameter.
    assert!(
        std::fs::read(d.join("farm/count_48/0001.bgeo")).unwrap()
            != std::fs::read(d.join("farm/count_96/0001.bgeo")).unwrap()
    );
}

/// Frame 3's input file is missing: its task fails on every attempt, is
/// retried (the disk may yet hold it), and is reported with the end of its
/// log. Frame 4's is not OBJ: its cook exits 4, which no retry changes, so
/// it runs once. The others are written.
fn a_failing_task_is_retried_and_reported(scheduler: &str) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let obj = root().join("examples/assets/creased_box.obj");
    for f in [1, 2] {
        std::fs::copy(&obj, d.join(format!("in.{f:04}.obj"))).unwrap();
    }
    std::fs::write(d.join("in.0004.obj"), "v 1 2 x\n").unwrap();
    let net = r#"{"geode": "network", "version": 1, "output": "t", "nodes": {
        "f": {"type": "file", "params": {"file": "$HIP/in.$F4.obj"}},
        "t": {"type": "transform", "inputs": ["f"], "params": {"translate": [0, 1, 0]}}}}"#;
    std::fs::write(d.join("net.json"), net).unwrap();
    let o = run(
        &[
            "farm",
            "net.json",
            "--scheduler",
            scheduler,
            "--frames",
            "1-4",
            "--retry",
            "1",
            "--farm-dir",
            "f",
            "--cache-dir",
            "cache",
            "-o",
            "out/$F4.ply",
        ],
        d,
    );
    assert!(!o.status.success());
    let err = stderr(&o);
    let log = d.join("f/task-2.attempt-1.log");
    assert!(
        err.contains(&format!(
            "farm: task 2 (frame 3, to {}) failed after 2 attempts; log {}:",
            d.join("out/0003.ply").display(),
            log.display()
        )),
        "{err}"
    );
    assert!(
        err.contains("in.0003.obj: No such file or directory"),
        "{err}"
    );
    assert!(err.contains("error: 2 of 4 farm tasks failed"), "{err}");
    assert!(
        d.join("f/task-2.attempt-0.log").exists() && log.exists(),
        "both attempts ran"
    );
    assert!(
        err.contains(&format!(
            "farm: task 3 (frame 4, to {}) failed after 1 attempt; log {}:",
            d.join("out/0004.ply").display(),
            d.join("f/task-3.attempt-0.log").display()
        )),
        "{err}"
    );
    assert!(
        !d.join("f/task-3.attempt-1.log").exists(),
        "a cook's failure is not retried"
    );
    assert!(d.join("out/0001.ply").exists() && d.join("out/0002.ply").exists());
    assert!(!d.join("out/0003.ply").exists());
}

#[test]
fn local_farm_equals_local_cooks() {
    farms_equal_local_cooks("local");
}

#[test]
fn local_farm_retries_and_reports_a_failing_task() {
    a_failing_task_is_retried_and_reported("local");
}

#[test]
fn slurm_farm_equals_local_cooks() {
    if let Some(_cluster) = slurm_cluster() {
        farms_equal_local_cooks("slurm");
    }
}

#[test]
fn slurm_farm_retries_and_reports_a_failing_task() {
    if let Some(_cluster) = slurm_cluster() {
        a_failing_task_is_retried_and_reported("slurm");
    }
}

#[test]
fn a_wedge_must_name_its_outputs_and_its_node() {
    let dir = tempfile::tempdir().unwrap();
    let chain = example("chain.json");
    let o = run(
        &[
            "farm",
            &chain,
            "--wedge",
            "/spacing/count=48,96",
            "-o",
            "out/$F4.bgeo",
            "--farm-dir",
            "f",
        ],
        dir.path(),
    );
    assert!(
        stderr(&o).contains("a wedge needs $WEDGE in the output path"),
        "{}",
        stderr(&o)
    );
    let o = run(
        &[
            "farm",
            &chain,
            "--wedge",
            "/nope/count=48,96",
            "-o",
            "out/$WEDGE.bgeo",
            "--farm-dir",
            "f",
        ],
        dir.path(),
    );
    assert!(
        stderr(&o).contains("--set /nope/count=48: no node `nope`"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_kubernetes_manifest_indexes_every_task() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = run(
        &[
            "farm",
            &example("coral.json"),
            "--scheduler",
            "k8s",
            "--frames",
            "1-5",
            "--jobs",
            "3",
            "--retry",
            "2",
            "--farm-dir",
            "f",
            "--cache-dir",
            "cache",
            "--image",
            "registry/geode:1",
            "--task-timeout",
            "10m",
            "-o",
            "out/$F4.bgeo",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let job: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("f/job.json")).unwrap()).unwrap();
    assert_eq!(job["kind"], "Job");
    assert_eq!(job["spec"]["completionMode"], "Indexed");
    assert_eq!(job["spec"]["completions"], 5);
    assert_eq!(job["spec"]["parallelism"], 3);
    assert_eq!(job["spec"]["backoffLimitPerIndex"], 2);
    // Usage, network and cook failures (exit 2, 3, 4) are not retried.
    let rule = &job["spec"]["podFailurePolicy"]["rules"][0];
    assert_eq!(rule["action"], "FailIndex");
    assert_eq!(rule["onExitCodes"]["values"], serde_json::json!([2, 3, 4]));
    // Kubernetes enforces --task-timeout itself, per pod.
    assert_eq!(
        job["spec"]["template"]["spec"]["activeDeadlineSeconds"],
        600
    );
    let container = &job["spec"]["template"]["spec"]["containers"][0];
    assert_eq!(container["image"], "registry/geode:1");
    assert!(container["command"][2]
        .as_str()
        .unwrap()
        .contains("JOB_COMPLETION_INDEX"));
    assert_eq!(
        container["env"][0]["value"],
        d.join("cache").display().to_string()
    );
    let tasks = std::fs::read_to_string(d.join("f/tasks.k8s.txt")).unwrap();
    let lines: Vec<&str> = tasks.lines().collect();
    assert_eq!(lines.len(), 5);
    assert!(
        lines[4].starts_with("geode cook ") && lines[4].contains("--frame 5"),
        "{}",
        lines[4]
    );
}
