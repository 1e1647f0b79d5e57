//! The local scheduler: a pool of `geode cook` processes on this machine, each task retried up to `--retry` times.

use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use anyhow::Result;

use super::Farm;

/// Runs one attempt of a task through `sh` (the task is a command line),
/// its output to the attempt's log, its exit status to the status file.
fn attempt(farm: &Farm, task: usize, n: u32) -> bool {
    let log = match std::fs::File::create(farm.log(task, n)) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("farm: task {task}: cannot create its log: {e}");
            return false;
        }
    };
    let err = log.try_clone().ok();
    let status = Command::new("sh")
        .arg("-c")
        .arg(&farm.tasks[task].command)
        .env("GEODE_CACHE_DIR", &farm.cache_dir)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(err.map_or(Stdio::null(), Stdio::from))
        .status();
    let code = status.as_ref().ok().and_then(|s| s.code()).unwrap_or(-1);
    let _ = std::fs::write(farm.status(task), format!("{code}\n"));
    code == 0
}

pub fn run(farm: &Farm) -> Result<()> {
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let failed = Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..farm.jobs.min(farm.tasks.len()) {
            s.spawn(|| loop {
                let t = next.fetch_add(1, Ordering::Relaxed);
                if t >= farm.tasks.len() {
                    return;
                }
                let mut n = 0;
                let mut ok = attempt(farm, t, n);
                while !ok && n < farm.retry {
                    eprintln!("farm: task {t} failed; retry {} of {}", n + 1, farm.retry);
                    n += 1;
                    ok = attempt(farm, t, n);
                }
                if !ok {
                    failed
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .push((t, n));
                }
                let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                eprintln!("farm: {d}/{} tasks done", farm.tasks.len());
            });
        }
    });
    let mut failed = failed.into_inner().unwrap_or_else(|e| e.into_inner());
    failed.sort_unstable();
    farm.report(&failed)
}
