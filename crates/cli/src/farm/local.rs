//! The local scheduler: a pool of `geode cook` processes on this machine, each task retried up to `--retry` times, killed at `--task-timeout`, when its heartbeat stops, or when the farm is interrupted.

use std::os::unix::process::CommandExt;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

use anyhow::Result;

use super::{heartbeat, interrupted, Failure, Farm, Interrupted};

/// How one attempt ended.
enum Ending {
    Succeeded,
    Failed(Failure),
    /// The farm was interrupted and the attempt killed.
    Interrupted,
}

/// Starts one attempt of a task through `sh` (the task is a command line)
/// in a process group of its own, so killing the group kills its `geode
/// cook` too; its output goes to the attempt's log.
fn start(farm: &Farm, task: usize, n: u32) -> std::io::Result<Child> {
    let log = std::fs::File::create(farm.log(task, n))?;
    let err = log.try_clone()?;
    Command::new("sh")
        .arg("-c")
        .arg(&farm.tasks[task].command)
        .env("GEODE_CACHE_DIR", &farm.cache_dir)
        .env(heartbeat::PATH_VAR, farm.heartbeat(task, n))
        .env(heartbeat::FARM_PID_VAR, std::process::id().to_string())
        .env(
            heartbeat::EVERY_MS_VAR,
            farm.heartbeat_every().as_millis().to_string(),
        )
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(err)
        .process_group(0)
        .spawn()
}

/// Kills the attempt's whole process group (`sh` and its `geode cook`) and
/// reaps `sh`.
fn kill(child: &mut Child) {
    let group = format!("-{}", child.id());
    let killed = Command::new("kill")
        .args(["-s", "KILL", "--", &group])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !killed {
        let _ = child.kill();
    }
    let _ = child.wait();
}

/// Runs one attempt to its end: its exit, the timeout, a stall, or the
/// farm's interruption; writes the exit status file when it exits.
fn attempt(farm: &Farm, task: usize, n: u32) -> Ending {
    let mut child = match start(farm, task, n) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("farm: task {task}: cannot start it: {e}");
            return Ending::Failed(Failure::Lost(format!("cannot start it: {e}")));
        }
    };
    let started = SystemTime::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                let code = status.code();
                let _ = std::fs::write(farm.status(task, n), format!("{}\n", code.unwrap_or(-1)));
                return if status.success() {
                    Ending::Succeeded
                } else if let Some(signal) = std::os::unix::process::ExitStatusExt::signal(&status)
                {
                    Ending::Failed(Failure::Signal(signal))
                } else {
                    Ending::Failed(code.map_or(Failure::Exit(None), Failure::from_exit))
                };
            }
            Ok(None) => {}
            Err(e) => {
                kill(&mut child);
                return Ending::Failed(Failure::Lost(format!("cannot wait for it: {e}")));
            }
        }
        if interrupted() {
            kill(&mut child);
            return Ending::Interrupted;
        }
        if let Some(failure) = farm.overdue(task, n, started) {
            kill(&mut child);
            eprintln!("farm: {} {failure}; killed it", farm.describe(task));
            return Ending::Failed(failure);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Runs a task's attempts until one succeeds or the retries run out; the
/// last attempt's number and failure, if it failed; `None` once interrupted.
fn run_task(farm: &Farm, t: usize) -> Option<Result<(), (u32, Failure)>> {
    let mut n = 0;
    loop {
        match attempt(farm, t, n) {
            Ending::Succeeded => return Some(Ok(())),
            Ending::Interrupted => return None,
            Ending::Failed(failure) if n < farm.retry && failure.is_transient() => {
                let why = match failure {
                    Failure::Exit(_) => "failed".to_owned(),
                    other => other.to_string(),
                };
                eprintln!("farm: task {t} {why}; retry {} of {}", n + 1, farm.retry);
                n += 1;
            }
            Ending::Failed(failure) => return Some(Err((n, failure))),
        }
    }
}

pub fn run(farm: &Farm) -> Result<()> {
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let failed = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..farm.jobs.min(farm.tasks.len()) {
            s.spawn(|| loop {
                let t = next.fetch_add(1, Ordering::Relaxed);
                if t >= farm.tasks.len() || interrupted() {
                    return;
                }
                match run_task(farm, t) {
                    None => return,
                    Some(Ok(())) => {}
                    Some(Err((n, failure))) => failed
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((t, n, failure)),
                }
                let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                eprintln!("farm: {d}/{} tasks finished", farm.tasks.len());
            });
        }
    });
    if interrupted() {
        eprintln!("farm: interrupted; killed the running tasks");
        return Err(Interrupted.into());
    }
    let mut failed = failed.into_inner().unwrap_or_else(|e| e.into_inner());
    failed.sort_unstable_by_key(|f| f.0);
    farm.report(&failed)
}
