//! `geode farm`: frames and wedges as independent `geode cook` tasks on a scheduler (a local process pool, Slurm, or a Kubernetes Indexed Job), all sharing the disk cache.
//!
//! Every task is one `geode cook NETWORK --frame F [--set NODE/PARAM=V] -o
//! OUT` with `GEODE_CACHE_DIR` set, so a farm writes exactly the bytes a
//! local cook of the same frame writes, and nodes two tasks share (every
//! frame's static inputs) are cooked once. The task list is a file of
//! shell-quoted command lines the schedulers index (`tasks.txt`, one line
//! per task), kept with each task's log and exit status in the farm's
//! folder (`.geode-farm/<id>/` beside the network unless `--farm-dir`).
//!
//! No farm hangs or leaves work behind: a task past `--task-timeout` is
//! cancelled, a started task whose heartbeat (a file its `geode cook`
//! touches, see [`heartbeat`]) is older than `--stall-limit` is cancelled
//! (its process is gone though the scheduler still says it runs), both
//! retried as `--retry` allows; Ctrl-C or SIGTERM cancels what the farm
//! submitted before it exits with status 130.

pub mod heartbeat;

mod k8s;
mod local;
mod slurm;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, SystemTime};

use anyhow::{anyhow, bail, Context, Result};

/// Where tasks run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Scheduler {
    /// A pool of processes on this machine.
    Local,
    /// A Slurm job array submitted with sbatch.
    Slurm,
    /// A Kubernetes Indexed Job manifest to apply (written, not run).
    K8s,
}

#[derive(clap::Args)]
pub struct FarmArgs {
    /// Network file (.json).
    pub network: PathBuf,
    /// The frames, e.g. 1-24 (default 1).
    #[arg(long, value_name = "A-B")]
    pub frames: Option<String>,
    /// One parameter's values, one task per value and frame: NODE/PARAM=v1,v2,...
    #[arg(long, value_name = "NODE/PARAM=V1,V2,...")]
    pub wedge: Option<String>,
    /// Output path per task: $F, $F4, $FF the frame; $WEDGE the wedge value.
    #[arg(short, long, value_name = "OUT")]
    pub output: String,
    /// Cook this node instead of the network's output.
    #[arg(long, value_name = "PATH")]
    pub node: Option<String>,
    /// Where tasks run.
    #[arg(long, value_enum, default_value = "local")]
    pub scheduler: Scheduler,
    /// Tasks at once (default: this machine's cores).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Times a failed task runs again.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub retry: u32,
    /// The disk cache the tasks share.
    #[arg(long, value_name = "DIR")]
    pub cache_dir: Option<PathBuf>,
    /// The folder for the task list, logs and statuses.
    #[arg(long, value_name = "DIR")]
    pub farm_dir: Option<PathBuf>,
    /// The container image of the Kubernetes job (--scheduler k8s).
    #[arg(long, value_name = "IMAGE", default_value = "geode:latest")]
    pub image: String,
    /// Cancel a task running longer than this (e.g. 90s, 10m, 2h; a bare
    /// number is seconds); it counts as failed and is retried as --retry allows.
    #[arg(long, value_name = "DURATION", value_parser = parse_duration)]
    pub task_timeout: Option<Duration>,
    /// Cancel and retry a started task whose heartbeat is older than this
    /// (its process is gone though the scheduler may still say it runs).
    #[arg(long, value_name = "DURATION", value_parser = parse_duration, default_value = "60s")]
    pub stall_limit: Duration,
}

/// A duration as `90s`, `10m`, `2h` or `1.5m`; a bare number is seconds.
pub fn parse_duration(text: &str) -> Result<Duration, String> {
    let t = text.trim();
    let split = t.find(|c: char| c.is_ascii_alphabetic()).unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("`{text}`: expected a duration such as 90s, 10m or 2h"))?;
    let seconds = match unit.trim() {
        "" | "s" | "sec" | "secs" => value,
        "m" | "min" | "mins" => value * 60.0,
        "h" | "hour" | "hours" => value * 3600.0,
        other => return Err(format!("`{text}`: unknown unit `{other}` (use s, m or h)")),
    };
    if !seconds.is_finite() || seconds <= 0.0 {
        return Err(format!("`{text}`: a duration must be above zero"));
    }
    Ok(Duration::from_secs_f64(seconds))
}

/// A duration as a person reads it in a report: `5 s`, `2.5 s`, `10 min`.
pub(crate) fn human(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 120.0 {
        let minutes = s / 60.0;
        if (minutes - minutes.round()).abs() < 0.05 {
            format!("{:.0} min", minutes)
        } else {
            format!("{minutes:.1} min")
        }
    } else if s >= 10.0 || (s - s.round()).abs() < 0.05 {
        format!("{s:.0} s")
    } else {
        format!("{s:.1} s")
    }
}

/// Why an attempt of a task did not succeed.
#[derive(Clone, Debug)]
pub(crate) enum Failure {
    /// The cook exited with this status (`None`: killed by a signal).
    Exit(Option<i32>),
    /// The cook was killed by this signal (from outside the farm).
    Signal(i32),
    /// The farm cancelled it at `--task-timeout`.
    TimedOut(Duration),
    /// The farm cancelled it: no heartbeat for this long while started.
    Stalled(Duration),
    /// Cancelled from outside the farm; the scheduler's word for its state.
    Cancelled(String),
    /// Gone from the scheduler without an exit status; what is known of why.
    Lost(String),
}

impl Failure {
    /// Whether another attempt can succeed: not when the cook exited with
    /// a status that says the command, the network or the cook is wrong
    /// (README: Exit status), which fail again the same way; a crash, a
    /// signal, a timeout or a lost node may not.
    pub(crate) fn is_transient(&self) -> bool {
        match self {
            Failure::Exit(Some(code)) => crate::exit::Exit::is_transient(*code),
            _ => true,
        }
    }

    /// A task's exit status as the shell that ran it reports it: past 128,
    /// the cook was killed by signal (status - 128).
    pub(crate) fn from_exit(code: i32) -> Failure {
        match code {
            129..=159 => Failure::Signal(code - 128),
            code => Failure::Exit(Some(code)),
        }
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Failure::Exit(Some(code)) => write!(f, "exit status {code}"),
            Failure::Exit(None) => write!(f, "killed by a signal"),
            Failure::Signal(n) => write!(f, "killed by signal {n}{}", signal_name(*n)),
            Failure::TimedOut(after) => write!(f, "timed out after {}", human(*after)),
            Failure::Stalled(for_) => write!(f, "stalled: no heartbeat for {}", human(*for_)),
            Failure::Cancelled(state) => write!(f, "cancelled (by the scheduler): {state}"),
            Failure::Lost(why) => write!(f, "lost: {why}"),
        }
    }
}

/// Set by Ctrl-C or SIGTERM; every scheduler polls it and cancels its work.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

pub(crate) fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// The farm was interrupted and cancelled its tasks; `main` exits 130 on it.
#[derive(Debug)]
pub struct Interrupted;

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted; the farm's tasks were cancelled")
    }
}

impl std::error::Error for Interrupted {}

/// Ctrl-C and SIGTERM (the `ctrlc` crate's `termination` feature, which
/// cannot tell the two apart: both exit 130) only raise a flag, so the
/// scheduler that owns the tasks cancels them before the farm exits.
fn catch_interrupts() {
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
}

/// One frame of one wedge variant.
pub(crate) struct Task {
    pub frame: f64,
    /// The `--set` of its wedge variant.
    pub set: Option<String>,
    pub output: PathBuf,
    /// The task as a shell command line.
    pub command: String,
}

/// A farm laid out on disk: its tasks and where their logs and statuses go.
pub(crate) struct Farm {
    pub dir: PathBuf,
    /// The network's folder (what a Kubernetes pod mounts).
    pub root: PathBuf,
    /// This geode, as the task lines name it.
    pub exe: String,
    pub tasks: Vec<Task>,
    pub cache_dir: PathBuf,
    pub jobs: usize,
    pub retry: u32,
    pub task_timeout: Option<Duration>,
    pub stall_limit: Duration,
}

impl Farm {
    pub fn log(&self, task: usize, attempt: u32) -> PathBuf {
        self.dir.join(format!("task-{task}.attempt-{attempt}.log"))
    }
    /// The attempt's exit status (one file per attempt, so a cancelled
    /// attempt finishing late never speaks for its retry).
    pub fn status(&self, task: usize, attempt: u32) -> PathBuf {
        self.dir
            .join(format!("task-{task}.attempt-{attempt}.status"))
    }
    /// The file the attempt's `geode cook` touches while it runs.
    pub fn heartbeat(&self, task: usize, attempt: u32) -> PathBuf {
        self.dir
            .join(format!("task-{task}.attempt-{attempt}.heartbeat"))
    }
    /// How often tasks touch their heartbeat: often enough that a few
    /// beats fit in the stall limit, at most every 2 s.
    pub fn heartbeat_every(&self) -> Duration {
        (self.stall_limit / 5).clamp(Duration::from_millis(200), Duration::from_secs(2))
    }

    /// How long an attempt started at `started` has gone without a
    /// heartbeat (since it started if it never beat).
    pub fn silent_for(&self, task: usize, attempt: u32, started: SystemTime) -> Duration {
        let beat = std::fs::metadata(self.heartbeat(task, attempt))
            .and_then(|m| m.modified())
            .map_or(started, |b| b.max(started));
        SystemTime::now().duration_since(beat).unwrap_or_default()
    }

    /// The failure, if any, a running attempt has reached: past the
    /// timeout, or silent past the stall limit.
    pub fn overdue(&self, task: usize, attempt: u32, started: SystemTime) -> Option<Failure> {
        let running = SystemTime::now()
            .duration_since(started)
            .unwrap_or_default();
        if let Some(limit) = self.task_timeout.filter(|&l| running > l) {
            return Some(Failure::TimedOut(limit));
        }
        let silent = self.silent_for(task, attempt, started);
        (silent > self.stall_limit).then_some(Failure::Stalled(silent))
    }

    /// A task as the report names it: `task 2 (frame 3, to out/0003.ply)`.
    pub fn describe(&self, t: usize) -> String {
        let task = &self.tasks[t];
        format!(
            "task {t} (frame {}{}, to {})",
            task.frame,
            task.set
                .as_deref()
                .map(|s| format!(", {s}"))
                .unwrap_or_default(),
            task.output.display()
        )
    }
    pub fn tasks_file(&self) -> PathBuf {
        self.dir.join("tasks.txt")
    }

    /// The last lines of a task's latest log, for the failure report.
    pub fn tail(&self, task: usize, attempt: u32) -> String {
        let text = std::fs::read_to_string(self.log(task, attempt)).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len().saturating_sub(12)..].join("\n")
    }

    /// Reports tasks still failed after every retry, with why and their
    /// logs; an error if any.
    pub fn report(&self, failed: &[(usize, u32, Failure)]) -> Result<()> {
        if failed.is_empty() {
            eprintln!(
                "farm: {} done; outputs as `-o` names them",
                plural(self.tasks.len(), "task")
            );
            return Ok(());
        }
        for (t, attempt, why) in failed {
            let (t, attempt) = (*t, *attempt);
            // An exit status speaks through the log; anything else is said.
            let reason = match why {
                Failure::Exit(Some(_)) => String::new(),
                other => format!(": {other}"),
            };
            let tail = self.tail(t, attempt);
            eprintln!(
                "farm: {} failed after {} attempt{}{reason}; log {}:\n{}",
                self.describe(t),
                attempt + 1,
                if attempt == 0 { "" } else { "s" },
                self.log(t, attempt).display(),
                if tail.trim().is_empty() {
                    "(the log is empty)".to_owned()
                } else {
                    tail
                }
            );
        }
        // Tasks that all failed alike give the farm their status (a network
        // every frame refuses exits as the cook would); else it is 1.
        let mut statuses = failed.iter().map(|(_, _, why)| match why {
            Failure::Exit(Some(code)) => crate::exit::Exit::from_code(*code),
            _ => None,
        });
        let first = statuses.next().flatten();
        let kind = match first {
            Some(k) if statuses.all(|s| s == Some(k)) => k,
            _ => crate::exit::Exit::Internal,
        };
        Err(crate::exit::tagged(
            kind,
            anyhow!("{} of {} farm tasks failed", failed.len(), self.tasks.len()),
        ))
    }
}

/// Quotes a word for `sh`.
pub(crate) fn shell_quote(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-=+:,@%".contains(c))
    {
        return s.to_owned();
    }
    format!("'{}'", s.replace('\'', r"'\''"))
}

/// The wedge's variants: (`--set` value, `$WEDGE` label).
fn wedge_variants(wedge: &str) -> Result<Vec<(String, String)>> {
    let (target, values) = wedge
        .split_once('=')
        .ok_or_else(|| anyhow!("--wedge {wedge}: expected NODE/PARAM=v1,v2,..."))?;
    let param = target.rsplit('/').next().unwrap_or(target);
    let values = split_values(values);
    if values.is_empty() {
        bail!("--wedge {wedge}: no values");
    }
    Ok(values
        .into_iter()
        .map(|v| {
            let label: String = format!("{param}_{v}")
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || "._-".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            (format!("{target}={v}"), label)
        })
        .collect())
}

/// Values split at top-level commas (a `[1,2,3]` value keeps its commas).
fn split_values(s: &str) -> Vec<String> {
    let (mut out, mut cur, mut depth) = (Vec::new(), String::new(), 0i32);
    for c in s.chars() {
        match c {
            '[' | '{' => depth += 1,
            ']' | '}' => depth -= 1,
            ',' if depth == 0 => {
                out.push(std::mem::take(&mut cur));
                continue;
            }
            _ => {}
        }
        cur.push(c);
    }
    out.push(cur);
    out.into_iter()
        .map(|v| v.trim().to_owned())
        .filter(|v| !v.is_empty())
        .collect()
}

fn absolute(p: &Path) -> Result<PathBuf> {
    std::path::absolute(p)
        .with_context(|| format!("{}: cannot make the path absolute", p.display()))
}

/// Lays the farm out: checks the network under every wedge variant, lists
/// the tasks and writes them to `tasks.txt`.
fn plan(args: &FarmArgs, frames: &[f64]) -> Result<Farm> {
    let network = absolute(&args.network)?;
    let variants: Vec<Option<(String, String)>> = match &args.wedge {
        Some(w) => wedge_variants(w)?.into_iter().map(Some).collect(),
        None => vec![None],
    };
    // Every variant must load: a wrong node or value fails here, not in 100 tasks.
    for v in &variants {
        let sets: Vec<String> = v.iter().map(|(s, _)| s.clone()).collect();
        crate::cook::load_with(&network, &sets)?;
    }
    crate::cook::check_per_frame(&args.output, frames)?;
    if args.wedge.is_some() && !args.output.contains("$WEDGE") {
        bail!("-o {}: a wedge needs $WEDGE in the output path, or every variant writes the same files", args.output);
    }
    let stem = network
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("farm");
    let dir = match &args.farm_dir {
        Some(d) => absolute(d)?,
        None => network
            .parent()
            .unwrap_or(Path::new("."))
            .join(".geode-farm")
            .join(format!("{stem}-{}-{}", std::process::id(), unix_seconds())),
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("{}: cannot create the farm folder", dir.display()))?;
    let cache_dir = match &args.cache_dir {
        Some(d) => absolute(d)?,
        None => match std::env::var_os("GEODE_CACHE_DIR").filter(|d| !d.is_empty()) {
            Some(d) => absolute(Path::new(&d))?,
            None => network
                .parent()
                .unwrap_or(Path::new("."))
                .join(".geode-cache"),
        },
    };
    let exe = std::env::current_exe().context("cannot find the geode executable")?;
    let mut tasks = Vec::new();
    for v in &variants {
        for &frame in frames {
            let pattern = match v {
                Some((_, label)) => args.output.replace("$WEDGE", label),
                None => args.output.replace("$WEDGE", "base"),
            };
            let output = absolute(&crate::cook::frame_path(&pattern, frame))?;
            if let Some(parent) = output.parent() {
                std::fs::create_dir_all(parent).with_context(|| {
                    format!("{}: cannot create the output folder", parent.display())
                })?;
            }
            let mut words: Vec<String> = vec![
                exe.display().to_string(),
                "cook".into(),
                network.display().to_string(),
                "--frame".into(),
                frame.to_string(),
                "-o".into(),
                output.display().to_string(),
            ];
            if let Some(node) = &args.node {
                words.extend(["--node".into(), node.clone()]);
            }
            if let Some((set, _)) = v {
                words.extend(["--set".into(), set.clone()]);
            }
            let command = words
                .iter()
                .map(|w| shell_quote(w))
                .collect::<Vec<_>>()
                .join(" ");
            tasks.push(Task {
                frame,
                set: v.as_ref().map(|(s, _)| s.clone()),
                output,
                command,
            });
        }
    }
    let farm = Farm {
        dir,
        root: network.parent().unwrap_or(Path::new("/")).to_owned(),
        exe: shell_quote(&exe.display().to_string()),
        tasks,
        cache_dir,
        jobs: args
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
            .max(1),
        retry: args.retry,
        task_timeout: args.task_timeout,
        stall_limit: args.stall_limit,
    };
    let lines: String = farm
        .tasks
        .iter()
        .map(|t| format!("{}\n", t.command))
        .collect();
    geode_io::write_atomic(&farm.tasks_file(), |w| {
        w.write_all(lines.as_bytes())
            .map_err(|e| geode_io::IoError::os(farm.tasks_file(), e))
    })?;
    Ok(farm)
}

fn unix_seconds() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

pub fn farm(args: FarmArgs) -> Result<()> {
    let frames = crate::cook::frames(None, args.frames.as_deref())?;
    let farm = plan(&args, &frames)?;
    catch_interrupts();
    eprintln!(
        "farm: {} ({}{}), folder {}, disk cache {}",
        plural(farm.tasks.len(), "task"),
        plural(frames.len(), "frame"),
        args.wedge
            .as_deref()
            .map(|w| format!(" x wedge {w}"))
            .unwrap_or_default(),
        farm.dir.display(),
        farm.cache_dir.display()
    );
    match args.scheduler {
        Scheduler::Local => local::run(&farm),
        Scheduler::Slurm => slurm::run(&farm),
        Scheduler::K8s => k8s::write(&farm, &args.image),
    }
}

/// ` (SIGKILL)` for the signals a task is commonly killed by.
fn signal_name(n: i32) -> &'static str {
    match n {
        1 => " (SIGHUP)",
        2 => " (SIGINT)",
        6 => " (SIGABRT)",
        9 => " (SIGKILL, perhaps for memory)",
        11 => " (SIGSEGV)",
        15 => " (SIGTERM)",
        _ => "",
    }
}

/// `1 task`, `12 tasks`.
pub(crate) fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    #[test]
    fn durations_read_seconds_minutes_and_hours() {
        let d = |s| super::parse_duration(s);
        assert_eq!(d("90s"), Ok(Duration::from_secs(90)));
        assert_eq!(d("90"), Ok(Duration::from_secs(90)));
        assert_eq!(d("10m"), Ok(Duration::from_secs(600)));
        assert_eq!(d("1.5m"), Ok(Duration::from_secs(90)));
        assert_eq!(d("2h"), Ok(Duration::from_secs(7200)));
        assert!(d("0s").is_err() && d("ten").is_err() && d("5d").is_err());
        assert_eq!(super::human(Duration::from_secs(5)), "5 s");
        assert_eq!(super::human(Duration::from_millis(2500)), "2.5 s");
        assert_eq!(super::human(Duration::from_secs(600)), "10 min");
    }
}
