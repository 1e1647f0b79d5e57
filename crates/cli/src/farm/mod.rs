//! `geode farm`: frames and wedges as independent `geode cook` tasks on a scheduler (a local process pool, Slurm, or a Kubernetes Indexed Job), all sharing the disk cache.
//!
//! Every task is one `geode cook NETWORK --frame F [--set NODE/PARAM=V] -o
//! OUT` with `GEODE_CACHE_DIR` set, so a farm writes exactly the bytes a
//! local cook of the same frame writes, and nodes two tasks share (every
//! frame's static inputs) are cooked once. The task list is a file of
//! shell-quoted command lines the schedulers index (`tasks.txt`, one line
//! per task), kept with each task's log and exit status in the farm's
//! folder (`.geode-farm/<id>/` beside the network unless `--farm-dir`).

mod k8s;
mod local;
mod slurm;

use std::path::{Path, PathBuf};

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
}

impl Farm {
    pub fn log(&self, task: usize, attempt: u32) -> PathBuf {
        self.dir.join(format!("task-{task}.attempt-{attempt}.log"))
    }
    pub fn status(&self, task: usize) -> PathBuf {
        self.dir.join(format!("task-{task}.status"))
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

    /// Reports tasks still failed after every retry, with their logs; an error if any.
    pub fn report(&self, failed: &[(usize, u32)]) -> Result<()> {
        if failed.is_empty() {
            eprintln!(
                "farm: {} tasks done; outputs as `-o` names them",
                self.tasks.len()
            );
            return Ok(());
        }
        for &(t, attempt) in failed {
            let task = &self.tasks[t];
            eprintln!(
                "farm: task {t} (frame {}{}, to {}) failed after {} attempt{}; log {}:\n{}",
                task.frame,
                task.set
                    .as_deref()
                    .map(|s| format!(", {s}"))
                    .unwrap_or_default(),
                task.output.display(),
                attempt + 1,
                if attempt == 0 { "" } else { "s" },
                self.log(t, attempt).display(),
                self.tail(t, attempt)
            );
        }
        bail!("{} of {} farm tasks failed", failed.len(), self.tasks.len())
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
    eprintln!(
        "farm: {} tasks ({} frames{}), folder {}, disk cache {}",
        farm.tasks.len(),
        frames.len(),
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
