//! `geode farm` never hangs and cleans up: a task past `--task-timeout` is killed and reported, tasks Slurm keeps RUNNING after slurmd dies are cancelled and resubmitted once their heartbeat stalls, Ctrl-C cancels the farm's jobs and exits 130, and a task cancelled with `scancel` is reported as cancelled (Slurm tests on the cluster of `tools/slurm.sh`, one at a time).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use common::{geode_in, slurm_cluster, stderr};

/// A network whose cook spins for `iterations` turns of a wrangle loop
/// (about 4 µs each: sixty inner turns, since a detail loop runs one lane
/// at about 70 ns a turn) and depends on the frame, so no two frames share
/// a cached result and every task really runs that long.
fn slow_network(dir: &Path, iterations: u64) -> PathBuf {
    let net = format!(
        r#"{{"geode": "network", "version": 1, "output": "w", "nodes": {{
        "b": {{"type": "box"}},
        "w": {{"type": "wrangle", "inputs": ["b"], "params": {{"run_over": "detail",
            "snippet": "float s = 0; for (int i = 0; i < {iterations}; i++) {{ for (int j = 0; j < 60; j++) {{ s += sin(float(i + j)); }} }} f@s = s + @Frame;"}}}}}}}}"#
    );
    let path = dir.join("slow.json");
    std::fs::write(&path, net).unwrap();
    path
}

/// `geode farm NETWORK ARGS` started in `dir` with its farm folder `f`,
/// its cache `cache` and outputs `out/$F4.bgeo`, its standard error going
/// to a file the test reads while it runs.
fn start_farm(dir: &Path, network: &Path, args: &[&str]) -> (Child, PathBuf) {
    let log = dir.join("farm.stderr");
    let child = Command::new(env!("CARGO_BIN_EXE_geode"))
        .arg("farm")
        .arg(network)
        .args(args)
        .args([
            "--farm-dir",
            "f",
            "--cache-dir",
            "cache",
            "-o",
            "out/$F4.bgeo",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    (child, log)
}

/// Polls `what` every 20 ms until it gives a value; panics after `limit`.
fn poll<T>(limit: Duration, what: &str, mut f: impl FnMut() -> Option<T>) -> T {
    let since = Instant::now();
    loop {
        if let Some(v) = f() {
            return v;
        }
        assert!(since.elapsed() < limit, "no {what} after {limit:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The farm's exit status, killing it (and failing) past `limit`: a farm
/// that hangs fails the test instead of hanging it.
fn finish(child: &mut Child, limit: Duration, log: &Path) -> ExitStatus {
    let since = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if since.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "the farm ran past {limit:?}:\n{}",
                std::fs::read_to_string(log).unwrap_or_default()
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The first job array the farm submitted, from its standard error.
fn submitted_job(log: &Path) -> String {
    poll(Duration::from_secs(30), "submitted job", || {
        let text = std::fs::read_to_string(log).ok()?;
        let line = text
            .lines()
            .find(|l| l.starts_with("farm: submitted job array "))?;
        Some(
            line["farm: submitted job array ".len()..]
                .split(' ')
                .next()?
                .to_owned(),
        )
    })
}

/// `squeue ARGS` standard output (empty if it fails).
fn squeue(args: &[&str]) -> String {
    Command::new("squeue")
        .args(args)
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default()
}

/// The first task of `job` Slurm says is RUNNING, as `JOB_INDEX`; polled
/// every 20 ms so the test acts as tasks start.
fn first_running(job: &str) -> String {
    poll(Duration::from_secs(60), "running task", || {
        squeue(&["-h", "-r", "-t", "RUNNING", "-j", job, "-o", "%i"])
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty())
            .map(str::to_owned)
    })
}

/// slurmd of the test cluster, stopped with SIGKILL (as a crash would) and
/// started again as `tools/slurm.sh` starts it; dropped, it makes sure
/// slurmd runs and the node takes jobs, so a failing test leaves the
/// cluster as it found it.
struct Slurmd {
    conf: String,
}

impl Slurmd {
    fn new() -> Slurmd {
        Slurmd {
            conf: std::env::var("SLURM_CONF").expect("SLURM_CONF names the test cluster"),
        }
    }

    /// `SlurmdPidFile` of the cluster's configuration.
    fn pid_file(&self) -> PathBuf {
        let conf = std::fs::read_to_string(&self.conf).unwrap();
        let line = conf
            .lines()
            .find_map(|l| l.trim().strip_prefix("SlurmdPidFile="))
            .expect("the configuration names SlurmdPidFile");
        PathBuf::from(line.trim())
    }

    fn pid(&self) -> Option<String> {
        let pid = std::fs::read_to_string(self.pid_file()).ok()?;
        let pid = pid.trim().to_owned();
        Path::new("/proc").join(&pid).exists().then_some(pid)
    }

    fn kill(&self) {
        let pid = self.pid().expect("slurmd runs");
        let status = Command::new("kill").args(["-KILL", &pid]).status().unwrap();
        assert!(status.success(), "kill -KILL {pid}");
    }

    /// Starts slurmd and waits until the node takes jobs again.
    fn start(&self) {
        if self.pid().is_none() {
            let status = Command::new("slurmd")
                .args(["-f", &self.conf])
                .status()
                .unwrap();
            assert!(status.success(), "slurmd -f {}", self.conf);
        }
        poll(Duration::from_secs(60), "node taking jobs", || {
            let states = Command::new("sinfo")
                .args(["-h", "-o", "%t"])
                .output()
                .ok()?;
            String::from_utf8_lossy(&states.stdout)
                .lines()
                .any(|l| ["idle", "mix", "alloc", "plnd"].contains(&l.trim()))
                .then_some(())
        });
    }
}

impl Drop for Slurmd {
    fn drop(&mut self) {
        self.start();
    }
}

/// The lines of `text` that start with `prefix`.
fn lines_starting<'a>(text: &'a str, prefix: &str) -> Vec<&'a str> {
    text.lines().filter(|l| l.starts_with(prefix)).collect()
}

#[test]
fn a_local_task_past_its_timeout_is_killed_and_reported() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // About 20 s of cooking, killed after 1 s: twice, as --retry 1 allows.
    let net = slow_network(d, 5_000_000);
    let since = Instant::now();
    let o = geode_in(
        d,
        &[
            "farm",
            net.to_str().unwrap(),
            "--task-timeout",
            "1s",
            "--retry",
            "1",
            "--farm-dir",
            "f",
            "--cache-dir",
            "cache",
            "-o",
            "out/$F4.bgeo",
        ],
        &[],
    );
    let took = since.elapsed();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let out = d.join("out/0001.bgeo");
    assert!(
        err.contains(&format!(
            "farm: task 0 (frame 1, to {}) timed out after 1 s; killed it",
            out.display()
        )),
        "{err}"
    );
    assert!(
        err.contains("farm: task 0 timed out after 1 s; retry 1 of 1"),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "farm: task 0 (frame 1, to {}) failed after 2 attempts: timed out after 1 s; log {}:",
            out.display(),
            d.join("f/task-0.attempt-1.log").display()
        )),
        "{err}"
    );
    assert!(
        took < Duration::from_secs(15),
        "both attempts were killed, not cooked to the end: {took:?}"
    );
    assert!(!out.exists(), "a killed cook writes nothing");
}

/// `geode cook` processes of the network at `net` (its temporary folder
/// makes the path this test's own), from /proc.
fn cook_pids(net: &Path) -> Vec<String> {
    let net = net.to_str().unwrap();
    std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(|e| {
            let e = e.ok()?;
            let pid = e.file_name().to_str()?.to_owned();
            let cmdline = std::fs::read(e.path().join("cmdline")).ok()?;
            let args: Vec<&[u8]> = cmdline.split(|&b| b == 0).collect();
            let is_cook =
                args.get(1) == Some(&&b"cook"[..]) && args.get(2) == Some(&net.as_bytes());
            is_cook.then_some(pid)
        })
        .collect()
}

/// `kill -SIGNAL PID`.
fn signal(name: &str, pid: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), pid])
        .status()
        .unwrap();
    assert!(status.success(), "kill -{name} {pid}");
}

#[test]
fn interrupting_a_local_farm_kills_its_tasks_and_exits_130() {
    local_farm_stopped_by("INT");
}

#[test]
fn terminating_a_local_farm_kills_its_tasks_and_exits_130() {
    local_farm_stopped_by("TERM");
}

/// A local farm sent `signal_name` while its cooks run: it kills them all
/// and exits 130.
fn local_farm_stopped_by(signal_name: &str) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 5_000_000);
    let (mut farm, log) = start_farm(
        d,
        &net,
        &["--frames", "1-2", "--jobs", "2", "--stall-limit", "5s"],
    );
    // The cooks run once they beat (every second under a 5 s stall limit).
    let heartbeat = d.join("f/task-0.attempt-0.heartbeat");
    poll(Duration::from_secs(30), "heartbeat", || {
        heartbeat.exists().then_some(())
    });
    signal(signal_name, &farm.id().to_string());
    let status = finish(&mut farm, Duration::from_secs(10), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        err.contains("farm: interrupted; killed the running tasks"),
        "{err}"
    );
    // No cook outlives the farm: the heartbeat stops.
    let beat = || std::fs::metadata(&heartbeat).unwrap().modified().unwrap();
    let before = beat();
    std::thread::sleep(Duration::from_secs(3));
    assert_eq!(beat(), before, "a killed cook's heartbeat stopped");
    assert!(!d.join("out/0001.bgeo").exists());
    assert_eq!(
        cook_pids(&net),
        Vec::<String>::new(),
        "no cook outlives the farm"
    );
}

#[test]
fn a_local_task_killed_from_outside_names_the_signal() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 5_000_000);
    let (mut farm, log) = start_farm(d, &net, &[]);
    let cooks = poll(Duration::from_secs(30), "cook process", || {
        Some(cook_pids(&net)).filter(|p| !p.is_empty())
    });
    for pid in &cooks {
        signal("KILL", pid);
    }
    let status = finish(&mut farm, Duration::from_secs(20), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(
        err.contains("failed after 1 attempt: killed by signal 9 (SIGKILL, perhaps for memory)"),
        "{err}"
    );
}

#[test]
fn cooks_of_a_local_farm_killed_with_sigkill_stop_too() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 5_000_000);
    let (mut farm, log) = start_farm(d, &net, &["--stall-limit", "2s"]);
    poll(Duration::from_secs(30), "cook process", || {
        Some(cook_pids(&net)).filter(|p| !p.is_empty())
    });
    // SIGKILL cannot be caught: the farm kills nothing on its way out.
    signal("KILL", &farm.id().to_string());
    let _ = finish(&mut farm, Duration::from_secs(5), &log);
    poll(Duration::from_secs(10), "orphaned cooks gone", || {
        cook_pids(&net).is_empty().then_some(())
    });
    assert!(!d.join("out/0001.bgeo").exists());
}

#[test]
fn a_local_task_whose_heartbeat_stops_is_killed_as_stalled() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 5_000_000);
    let (mut farm, log) = start_farm(d, &net, &["--stall-limit", "2s"]);
    // A stopped process is one that no longer beats (as a hung machine's).
    let cooks = poll(Duration::from_secs(30), "cook process", || {
        Some(cook_pids(&net)).filter(|p| !p.is_empty())
    });
    for pid in &cooks {
        signal("STOP", pid);
    }
    let status = finish(&mut farm, Duration::from_secs(20), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    let describe = format!("task 0 (frame 1, to {})", d.join("out/0001.bgeo").display());
    assert!(
        err.contains(&format!("farm: {describe} stalled: no heartbeat for ")),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "farm: {describe} failed after 1 attempt: stalled: no heartbeat for "
        )),
        "{err}"
    );
    assert_eq!(
        cook_pids(&net),
        Vec::<String>::new(),
        "the stalled cook was killed"
    );
}

#[test]
fn a_slurm_farm_recovers_when_slurmd_dies_as_tasks_start() {
    let Some(_cluster) = slurm_cluster() else {
        return;
    };
    let slurmd = Slurmd::new();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 250_000);
    let since = Instant::now();
    let (mut farm, log) = start_farm(
        d,
        &net,
        &[
            "--scheduler",
            "slurm",
            "--frames",
            "1-6",
            "--jobs",
            "2",
            "--retry",
            "3",
            "--stall-limit",
            "5s",
        ],
    );
    let job = submitted_job(&log);
    // As the first task starts, slurmd dies: the tasks it was launching
    // stay RUNNING in Slurm's eyes with no process behind them.
    first_running(&job);
    slurmd.kill();
    // Down for longer than the stall limit, so the farm must act alone.
    std::thread::sleep(Duration::from_secs(8));
    slurmd.start();
    let status = finish(&mut farm, Duration::from_secs(90), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert!(status.success(), "{err}");
    assert!(
        since.elapsed() < Duration::from_secs(100),
        "{:?}",
        since.elapsed()
    );
    let stalled: Vec<usize> = lines_starting(&err, "farm: task ")
        .into_iter()
        .filter(|l| l.contains(") stalled: no heartbeat for "))
        .map(|l| {
            assert!(
                l.ends_with(&format!(
                    " while Slurm says RUNNING; cancelling job {job}_{} (scancel)",
                    l.split(' ').nth(2).unwrap()
                )),
                "{l}"
            );
            l.split(' ').nth(2).unwrap().parse().unwrap()
        })
        .collect();
    assert!(
        !stalled.is_empty(),
        "a task launched into the dead slurmd stalled:\n{err}"
    );
    let resubmitted: Vec<usize> = lines_starting(&err, "farm: resubmitted task")
        .iter()
        .flat_map(|l| {
            let tasks = l
                .trim_start_matches("farm: resubmitted tasks ")
                .trim_start_matches("farm: resubmitted task ");
            let tasks = tasks.split(" as job array ").next().unwrap();
            tasks
                .split(", ")
                .map(|t| t.parse::<usize>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect();
    for t in &stalled {
        assert!(resubmitted.contains(t), "task {t} resubmitted:\n{err}");
    }
    assert!(err.contains("farm: 6 tasks done"), "{err}");
    // Every output is what a plain cook of its frame writes.
    std::fs::create_dir_all(d.join("local")).unwrap();
    let o = geode_in(
        d,
        &[
            "cook",
            net.to_str().unwrap(),
            "--frames",
            "1-6",
            "-o",
            "local/$F4.bgeo",
        ],
        &[],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for f in 1..=6 {
        let name = format!("{f:04}.bgeo");
        assert!(
            std::fs::read(d.join("out").join(&name)).unwrap()
                == std::fs::read(d.join("local").join(&name)).unwrap(),
            "frame {f} differs from a local cook"
        );
    }
}

#[test]
fn interrupting_a_slurm_farm_cancels_its_jobs_and_exits_130() {
    let Some(_cluster) = slurm_cluster() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 1_000_000);
    let (mut farm, log) = start_farm(d, &net, &["--scheduler", "slurm", "--frames", "1-6"]);
    let job = submitted_job(&log);
    first_running(&job);
    let pid = farm.id().to_string();
    assert!(Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
    let status = finish(&mut farm, Duration::from_secs(45), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        err.contains(&format!(
            "farm: interrupted; cancelling job {job} (scancel)"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "farm: job {job} cancelled; nothing left in the queue"
        )),
        "{err}"
    );
    let queue = squeue(&["-h", "-u", "root", "-o", "%F %i %T"]);
    assert!(
        !queue
            .lines()
            .any(|l| l.split(' ').next() == Some(job.as_str())),
        "job {job} is still queued:\n{queue}"
    );
}

#[test]
fn a_slurm_task_cancelled_with_scancel_is_reported_as_cancelled() {
    let Some(_cluster) = slurm_cluster() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let net = slow_network(d, 1_000_000);
    let (mut farm, log) = start_farm(d, &net, &["--scheduler", "slurm", "--frames", "1-2"]);
    let job = submitted_job(&log);
    let task = first_running(&job);
    assert!(Command::new("scancel")
        .arg(&task)
        .status()
        .unwrap()
        .success());
    let status = finish(&mut farm, Duration::from_secs(60), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    let t: usize = task.split('_').nth(1).unwrap().parse().unwrap();
    let describe = format!(
        "task {t} (frame {}, to {})",
        t + 1,
        d.join(format!("out/{:04}.bgeo", t + 1)).display()
    );
    assert!(
        err.contains(&format!(
            "farm: {describe} cancelled (by the scheduler): Slurm says CANCELLED (job {task})"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "farm: {describe} failed after 1 attempt: cancelled (by the scheduler): Slurm says CANCELLED (job {task}); log {}:",
            d.join(format!("f/task-{t}.attempt-0.log")).display()
        )),
        "{err}"
    );
    assert!(err.contains("error: 1 of 2 farm tasks failed"), "{err}");
}

#[test]
fn a_slurm_task_past_its_timeout_is_cancelled_and_reported() {
    let Some(_cluster) = slurm_cluster() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // About 20 s of cooking, cancelled after 2 s.
    let net = slow_network(d, 5_000_000);
    let (mut farm, log) = start_farm(d, &net, &["--scheduler", "slurm", "--task-timeout", "2s"]);
    let job = submitted_job(&log);
    let status = finish(&mut farm, Duration::from_secs(30), &log);
    let err = std::fs::read_to_string(&log).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    let describe = format!("task 0 (frame 1, to {})", d.join("out/0001.bgeo").display());
    assert!(
        err.contains(&format!(
            "farm: {describe} timed out after 2 s while Slurm says RUNNING; cancelling job {job}_0 (scancel)"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "farm: {describe} failed after 1 attempt: timed out after 2 s; log {}:",
            d.join("f/task-0.attempt-0.log").display()
        )),
        "{err}"
    );
    // The cancel reached Slurm: the task leaves the queue.
    poll(
        Duration::from_secs(30),
        "cancelled task leaving the queue",
        || {
            squeue(&["-h", "-j", &job, "-o", "%i"])
                .trim()
                .is_empty()
                .then_some(())
        },
    );
}
