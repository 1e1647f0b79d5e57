//! The Slurm scheduler: job arrays through `sbatch` (task i runs line i of `tasks.txt`; arrays of at most the cluster's `MaxArraySize`, offset per chunk), watched through their status and heartbeat files and `squeue`; a task past its timeout or stalled is cancelled with `scancel`, failed tasks are resubmitted up to `--retry` times, and an interrupted farm cancels its jobs.

use std::collections::HashMap;
use std::process::Command;
use std::time::{Duration, Instant, SystemTime};

use anyhow::{anyhow, bail, Context, Result};

use super::{heartbeat, human, interrupted, shell_quote, Failure, Farm, Interrupted};

/// How long a task that left the queue may take to show its exit status
/// (the status file is written as the job ends, maybe on a shared disk).
const STATUS_GRACE: Duration = Duration::from_secs(3);
/// How often the wait says where the farm stands when nothing changes.
const QUIET_PROGRESS_EVERY: Duration = Duration::from_secs(30);
/// How long an interrupted farm waits for its cancelled jobs to leave.
const DRAIN_LIMIT: Duration = Duration::from_secs(30);

/// The array job's script: task `SLURM_ARRAY_TASK_ID + GEODE_FARM_OFFSET`
/// runs its line of `tasks.txt` through `sh`, its output to its attempt's
/// log and its heartbeat to the attempt's heartbeat file, then writes its
/// exit status atomically.
fn script(farm: &Farm, attempt: u32) -> String {
    let dir = shell_quote(&farm.dir.display().to_string());
    let cache = shell_quote(&farm.cache_dir.display().to_string());
    let beat_ms = farm.heartbeat_every().as_millis();
    let (beat, beat_every) = (heartbeat::PATH_VAR, heartbeat::EVERY_MS_VAR);
    format!(
        "#!/bin/sh\n\
         #SBATCH --job-name=geode-farm\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --output=/dev/null\n\
         export GEODE_CACHE_DIR={cache}\n\
         t=$((SLURM_ARRAY_TASK_ID + ${{GEODE_FARM_OFFSET:-0}}))\n\
         export {beat}={dir}/task-$t.attempt-{attempt}.heartbeat {beat_every}={beat_ms}\n\
         line=$(sed -n \"$((t + 1))p\" {dir}/tasks.txt)\n\
         sh -c \"$line\" > {dir}/task-$t.attempt-{attempt}.log 2>&1\n\
         code=$?\n\
         echo $code > {dir}/task-$t.attempt-{attempt}.status.tmp && mv {dir}/task-$t.attempt-{attempt}.status.tmp {dir}/task-$t.attempt-{attempt}.status\n\
         exit $code\n"
    )
}

/// The cluster's largest array index + 1 (`MaxArraySize`, 1001 by
/// default); `GEODE_SLURM_MAX_ARRAY` overrides it (the tests' small chunks).
fn max_array_size() -> usize {
    if let Some(n) = std::env::var("GEODE_SLURM_MAX_ARRAY")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        return n;
    }
    let out = Command::new("scontrol").args(["show", "config"]).output();
    let text = out
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    text.lines()
        .find_map(|l| {
            let (k, v) = l.split_once('=')?;
            (k.trim() == "MaxArraySize").then(|| v.trim().parse().ok())?
        })
        .unwrap_or(1001)
}

/// One submitted job array: its job id and what its indices are offset by.
struct Array {
    id: String,
    offset: usize,
}

/// Submits `tasks` (at most `jobs` at once) as job arrays of at most the
/// cluster's array size, each offset to its chunk.
fn submit(farm: &Farm, tasks: &[usize], attempt: u32) -> Result<Vec<Array>> {
    let path = farm.dir.join(format!("farm.attempt-{attempt}.sbatch"));
    std::fs::write(&path, script(farm, attempt))
        .with_context(|| format!("{}: cannot write the job script", path.display()))?;
    let chunk = max_array_size().max(1);
    let mut arrays = Vec::new();
    for group in tasks.chunk_by(|a, b| a / chunk == b / chunk) {
        let offset = group[0] / chunk * chunk;
        let indices: Vec<usize> = group.iter().map(|t| t - offset).collect();
        let id = submit_array(farm, &path, &indices, offset)?;
        arrays.push(Array { id, offset });
    }
    Ok(arrays)
}

fn submit_array(
    farm: &Farm,
    script: &std::path::Path,
    indices: &[usize],
    offset: usize,
) -> Result<String> {
    let out = Command::new("sbatch")
        .arg("--parsable")
        .arg(format!("--array={}%{}", array_spec(indices), farm.jobs))
        .arg(format!("--export=ALL,GEODE_FARM_OFFSET={offset}"))
        .arg(script)
        .current_dir(&farm.dir)
        .output()
        .map_err(|e| anyhow!("cannot run sbatch ({e}): is Slurm installed and SLURM_CONF set?"))?;
    if !out.status.success() {
        bail!(
            "sbatch refused the farm: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let id = String::from_utf8_lossy(&out.stdout)
        .trim()
        .split(';')
        .next()
        .unwrap_or("")
        .to_owned();
    if id.is_empty() {
        bail!("sbatch gave no job id");
    }
    Ok(id)
}

/// Task indices as Slurm's array syntax, runs collapsed: `0-23`, `3,7-9`.
fn array_spec(tasks: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < tasks.len() {
        let mut j = i;
        while j + 1 < tasks.len() && tasks[j + 1] == tasks[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            tasks[i].to_string()
        } else {
            format!("{}-{}", tasks[i], tasks[j])
        });
        i = j + 1;
    }
    parts.join(",")
}

/// What Slurm says of one array task.
#[derive(Clone)]
struct Seen {
    /// `%T`: PENDING, RUNNING, COMPLETING, CANCELLED, NODE_FAIL, ...
    state: String,
    /// `JOB_INDEX`, the name `scancel` takes.
    name: String,
}

/// Every task of the arrays Slurm still knows, finished ones included
/// (`-t all`, kept for `MinJobAge`), by array job id and task number;
/// `None` when `squeue` cannot answer (the controller is down). Each array
/// is asked on its own: one Slurm has forgotten fails only its own query.
fn queue(arrays: &[&Array]) -> Option<HashMap<(String, usize), Seen>> {
    let mut seen = HashMap::new();
    let mut answered = arrays.is_empty();
    for array in arrays {
        let Ok(out) = Command::new("squeue")
            .args(["-h", "-r", "-t", "all", "-j", &array.id, "-o", "%F %K %T"])
            .output()
        else {
            continue;
        };
        if !out.status.success() {
            // A job past MinJobAge is unknown: answered, with nothing listed.
            answered |= String::from_utf8_lossy(&out.stderr).contains("Invalid job id");
            continue;
        }
        answered = true;
        for line in String::from_utf8_lossy(&out.stdout).lines() {
            let mut words = line.split_whitespace();
            let (Some(job), Some(index), Some(state)) = (words.next(), words.next(), words.next())
            else {
                continue;
            };
            let Ok(i) = index.parse::<usize>() else {
                continue;
            };
            seen.insert(
                (job.to_owned(), array.offset + i),
                Seen {
                    state: state.to_owned(),
                    name: format!("{job}_{index}"),
                },
            );
        }
    }
    answered.then_some(seen)
}

/// Whether a state means the task is still in Slurm's hands.
fn active(state: &str) -> bool {
    matches!(
        state,
        "PENDING"
            | "RUNNING"
            | "CONFIGURING"
            | "COMPLETING"
            | "REQUEUED"
            | "REQUEUE_FED"
            | "REQUEUE_HOLD"
            | "RESIZING"
            | "SUSPENDED"
            | "STOPPED"
            | "SIGNALING"
            | "STAGE_OUT"
    )
}

/// The accounting state of a task Slurm no longer lists (`sacct`, when the
/// cluster keeps accounting).
fn accounted_state(name: &str) -> Option<String> {
    let out = Command::new("sacct")
        .args(["-n", "-X", "-P", "-j", name, "-o", "State"])
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .map(str::to_owned)
}

/// Cancels array tasks or whole jobs by name; says so if `scancel` fails.
fn scancel(names: &[&str]) {
    match Command::new("scancel").args(names).output() {
        Ok(o) if o.status.success() => {}
        Ok(o) => eprintln!(
            "farm: scancel {} failed: {}",
            names.join(" "),
            String::from_utf8_lossy(&o.stderr).trim()
        ),
        Err(e) => eprintln!("farm: cannot run scancel {}: {e}", names.join(" ")),
    }
}

/// The exit status an attempt's job wrote, once it has.
fn exit_status(farm: &Farm, t: usize, attempt: u32) -> Option<i32> {
    std::fs::read_to_string(farm.status(t, attempt))
        .ok()
        .and_then(|c| c.trim().parse().ok())
}

/// What the farm knows of one task of the attempt it waits for.
#[derive(Default)]
struct Watch {
    /// When the farm first saw it RUNNING (since a requeue, if any).
    started: Option<SystemTime>,
    /// When the farm first saw it out of Slurm's hands without a status.
    gone: Option<Instant>,
    /// What Slurm said of it last.
    last: Option<Seen>,
    /// How it ended: `Some(None)` succeeded, `Some(Some(f))` failed.
    outcome: Option<Option<Failure>>,
}

/// The attempt's outcome for a task that wrote its exit status.
fn from_status(code: i32, last: Option<&Seen>) -> Option<Failure> {
    match last {
        _ if code == 0 => None,
        Some(seen) if seen.state.starts_with("CANCELLED") => Some(Failure::Cancelled(format!(
            "Slurm says {} (job {})",
            seen.state, seen.name
        ))),
        _ => Some(Failure::from_exit(code)),
    }
}

/// The attempt's outcome for a task that left Slurm's hands without an
/// exit status: cancelled from outside, or lost with Slurm's reason.
fn from_departure(last: Option<&Seen>) -> Failure {
    let state = last.map(|s| {
        let accounted = (!active(&s.state))
            .then(|| s.state.clone())
            .or_else(|| accounted_state(&s.name));
        (
            accounted.unwrap_or_else(|| "gone from the queue".into()),
            s.name.clone(),
        )
    });
    match state {
        Some((state, name)) if state.starts_with("CANCELLED") => {
            Failure::Cancelled(format!("Slurm says {state} (job {name})"))
        }
        Some((state, name)) => Failure::Lost(format!(
            "Slurm says {state} (job {name}) and the task wrote no exit status"
        )),
        None => Failure::Lost("Slurm never listed it and it wrote no exit status".into()),
    }
}

/// Moves one unfinished task on from what Slurm says now: its exit
/// status, a timeout or stall (cancelled here), or its departure.
fn watch_task(
    farm: &Farm,
    t: usize,
    attempt: u32,
    watch: &mut Watch,
    seen: Option<&Seen>,
    queue_answered: bool,
) {
    if let Some(s) = seen {
        watch.last = Some(s.clone());
    }
    if let Some(code) = exit_status(farm, t, attempt) {
        watch.outcome = Some(from_status(code, watch.last.as_ref()));
        return;
    }
    match seen.map(|s| s.state.as_str()) {
        Some("PENDING" | "REQUEUED") => (watch.started, watch.gone) = (None, None),
        Some("RUNNING") => {
            watch.started.get_or_insert_with(SystemTime::now);
            watch.gone = None;
        }
        Some(state) if active(state) => watch.gone = None,
        // Finished in Slurm's eyes or not listed: wait a moment for the status.
        _ if queue_answered => {
            let gone = *watch.gone.get_or_insert_with(Instant::now);
            if gone.elapsed() > STATUS_GRACE {
                watch.outcome = Some(Some(from_departure(watch.last.as_ref())));
            }
            return;
        }
        _ => {}
    }
    if let (Some(started), Some(last)) = (watch.started, &watch.last) {
        if let Some(failure) = farm.overdue(t, attempt, started) {
            eprintln!(
                "farm: {} {failure} while Slurm says RUNNING; cancelling job {} (scancel)",
                farm.describe(t),
                last.name
            );
            scancel(&[&last.name]);
            watch.outcome = Some(Some(failure));
        }
    }
}

/// Cancels the arrays and waits (a while) until Slurm has let them go, so
/// an interrupted farm leaves nothing queued or running.
fn cancel_all(arrays: &[&Array]) {
    let ids: Vec<&str> = arrays.iter().map(|a| a.id.as_str()).collect();
    eprintln!(
        "farm: interrupted; cancelling job {} (scancel)",
        ids.join(", ")
    );
    scancel(&ids);
    let since = Instant::now();
    while since.elapsed() < DRAIN_LIMIT {
        let listed = Command::new("squeue")
            .args(["-h", "-j", &ids.join(","), "-o", "%i"])
            .output()
            .map(|o| o.status.success() && !String::from_utf8_lossy(&o.stdout).trim().is_empty())
            .unwrap_or(false);
        if !listed {
            eprintln!(
                "farm: job {} cancelled; nothing left in the queue",
                ids.join(", ")
            );
            return;
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    eprintln!(
        "farm: job {} is still in the queue {} after scancel; Slurm is finishing it",
        ids.join(", "),
        human(DRAIN_LIMIT)
    );
}

/// A task the farm waits for: its attempt, the array running it, and
/// what is known of that attempt.
struct Live {
    attempt: u32,
    array: String,
    watch: Watch,
}

/// Tasks as a list for a message: `0, 1, 7`.
fn list(tasks: &[usize]) -> String {
    tasks
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Submits `tasks` as attempt `attempt`, to be waited for in `live`.
fn launch(
    farm: &Farm,
    tasks: &[usize],
    attempt: u32,
    arrays: &mut Vec<Array>,
    live: &mut HashMap<usize, Live>,
) -> Result<Vec<String>> {
    let submitted = submit(farm, tasks, attempt)?;
    let ids: Vec<String> = submitted.iter().map(|a| a.id.clone()).collect();
    let chunk = max_array_size().max(1);
    for &t in tasks {
        // The array holding task t: the one at its chunk's offset.
        let array = submitted
            .iter()
            .find(|a| a.offset == t / chunk * chunk)
            .map_or_else(|| ids[0].clone(), |a| a.id.clone());
        live.insert(
            t,
            Live {
                attempt,
                array,
                watch: Watch::default(),
            },
        );
    }
    arrays.extend(submitted);
    Ok(ids)
}

/// Runs the farm: every task submitted, each failure resubmitted at once
/// (a new array of just the failed tasks) while `--retry` allows, where the
/// farm stands said whenever that changes (and every half minute
/// regardless), failures reported at the end. Interrupted, cancels every
/// array it submitted.
pub fn run(farm: &Farm) -> Result<()> {
    let (mut arrays, mut live) = (Vec::new(), HashMap::new());
    let all: Vec<usize> = (0..farm.tasks.len()).collect();
    let ids = launch(farm, &all, 0, &mut arrays, &mut live)?;
    eprintln!(
        "farm: submitted job array {} ({} tasks, attempt 1)",
        ids.join(", "),
        all.len()
    );
    let (mut succeeded, mut failed) = (0, Vec::new());
    let begun = Instant::now();
    let (mut last_line, mut last_said) = (String::new(), Instant::now());
    loop {
        let watched: Vec<&Array> = arrays
            .iter()
            .filter(|a| live.values().any(|l| l.array == a.id))
            .collect();
        if interrupted() {
            cancel_all(&watched);
            return Err(Interrupted.into());
        }
        let now_seen = queue(&watched);
        let mut retry: HashMap<u32, Vec<usize>> = HashMap::new();
        let mut ended = Vec::new();
        for (&t, task) in live.iter_mut() {
            let seen = now_seen
                .as_ref()
                .and_then(|q| q.get(&(task.array.clone(), t)));
            watch_task(
                farm,
                t,
                task.attempt,
                &mut task.watch,
                seen,
                now_seen.is_some(),
            );
            match task.watch.outcome.take() {
                None => continue,
                Some(None) => succeeded += 1,
                Some(Some(failure)) => {
                    if let Failure::Cancelled(why) = &failure {
                        eprintln!(
                            "farm: {} cancelled (by the scheduler): {why}",
                            farm.describe(t)
                        );
                    }
                    if task.attempt < farm.retry && failure.is_transient() {
                        retry.entry(task.attempt + 1).or_default().push(t);
                    } else {
                        failed.push((t, task.attempt, failure));
                    }
                }
            }
            ended.push(t);
        }
        for t in ended {
            live.remove(&t);
        }
        for (attempt, mut tasks) in retry {
            tasks.sort_unstable();
            let ids = match launch(farm, &tasks, attempt, &mut arrays, &mut live) {
                Ok(ids) => ids,
                Err(e) => {
                    // The farm gives up: nothing it submitted may run on.
                    let running: Vec<&str> = arrays
                        .iter()
                        .filter(|a| live.values().any(|l| l.array == a.id))
                        .map(|a| a.id.as_str())
                        .collect();
                    if !running.is_empty() {
                        eprintln!(
                            "farm: cannot resubmit tasks {}; cancelling job {} (scancel)",
                            list(&tasks),
                            running.join(", ")
                        );
                        scancel(&running);
                    }
                    return Err(e);
                }
            };
            eprintln!(
                "farm: resubmitted task{} {} as job array {}: retry {attempt} of {}",
                if tasks.len() == 1 { "" } else { "s" },
                list(&tasks),
                ids.join(", "),
                farm.retry
            );
        }
        let running = live.values().filter(|l| l.watch.started.is_some()).count();
        let line = format!(
            "farm: {}/{} tasks finished, {running} running, {} waiting{}",
            succeeded + failed.len(),
            farm.tasks.len(),
            live.len() - running,
            if now_seen.is_none() {
                " (squeue does not answer)"
            } else {
                ""
            }
        );
        if line != last_line || last_said.elapsed() > QUIET_PROGRESS_EVERY {
            eprintln!("{line} ({:.0} s)", begun.elapsed().as_secs_f64());
            (last_line, last_said) = (line, Instant::now());
        }
        if live.is_empty() {
            failed.sort_unstable_by_key(|f| f.0);
            return farm.report(&failed);
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn array_specs_collapse_runs() {
        assert_eq!(super::array_spec(&(0..24).collect::<Vec<_>>()), "0-23");
        assert_eq!(super::array_spec(&[3, 7, 8, 9, 12]), "3,7-9,12");
        assert_eq!(super::array_spec(&[5]), "5");
    }
}
