//! The Slurm scheduler: one job array through `sbatch` (task i runs line i of `tasks.txt`), waited for by its status files, failed tasks resubmitted as a smaller array up to `--retry` times.

use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context, Result};

use super::{shell_quote, Farm};

/// The array job's script: the task's line of `tasks.txt`, run by `sh`,
/// then its exit status written atomically beside its log.
fn script(farm: &Farm, attempt: u32) -> String {
    let dir = shell_quote(&farm.dir.display().to_string());
    let cache = shell_quote(&farm.cache_dir.display().to_string());
    format!(
        "#!/bin/sh\n\
         #SBATCH --job-name=geode-farm\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --output={dir}/task-%a.attempt-{attempt}.log\n\
         export GEODE_CACHE_DIR={cache}\n\
         line=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" {dir}/tasks.txt)\n\
         sh -c \"$line\"\n\
         code=$?\n\
         echo $code > {dir}/task-$SLURM_ARRAY_TASK_ID.status.tmp && mv {dir}/task-$SLURM_ARRAY_TASK_ID.status.tmp {dir}/task-$SLURM_ARRAY_TASK_ID.status\n\
         exit $code\n"
    )
}

/// Submits an array of `tasks` (at most `jobs` at once); the job id.
fn submit(farm: &Farm, tasks: &[usize], attempt: u32) -> Result<String> {
    let path = farm.dir.join(format!("farm.attempt-{attempt}.sbatch"));
    std::fs::write(&path, script(farm, attempt))
        .with_context(|| format!("{}: cannot write the job script", path.display()))?;
    for &t in tasks {
        let _ = std::fs::remove_file(farm.status(t));
    }
    let out = Command::new("sbatch")
        .arg("--parsable")
        .arg(format!("--array={}%{}", array_spec(tasks), farm.jobs))
        .arg(&path)
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

/// Whether the job still has tasks queued or running.
fn queued(id: &str) -> bool {
    Command::new("squeue")
        .args(["-h", "-j", id, "-o", "%i"])
        .output()
        .map(|o| o.status.success() && !String::from_utf8_lossy(&o.stdout).trim().is_empty())
        .unwrap_or(false)
}

/// Waits until every task has a status or the job has left the queue;
/// returns the tasks that did not succeed.
fn wait(farm: &Farm, id: &str, tasks: &[usize]) -> Vec<usize> {
    let status = |t: usize| {
        std::fs::read_to_string(farm.status(t))
            .ok()
            .map(|c| c.trim() == "0")
    };
    let started = Instant::now();
    let mut last = usize::MAX;
    loop {
        let finished = tasks.iter().filter(|&&t| status(t).is_some()).count();
        if finished != last {
            eprintln!(
                "farm: job {id}: {finished}/{} tasks finished ({:.0} s)",
                tasks.len(),
                started.elapsed().as_secs_f64()
            );
            last = finished;
        }
        // A task the job no longer holds and that left no status (cancelled,
        // its node lost) failed too: poll the queue once everything is quiet.
        if finished == tasks.len() || !queued(id) {
            std::thread::sleep(Duration::from_millis(200));
            return tasks
                .iter()
                .copied()
                .filter(|&t| status(t) != Some(true))
                .collect();
        }
        std::thread::sleep(Duration::from_millis(500));
    }
}

pub fn run(farm: &Farm) -> Result<()> {
    let mut pending: Vec<usize> = (0..farm.tasks.len()).collect();
    let mut attempt = 0;
    loop {
        let id = submit(farm, &pending, attempt)?;
        eprintln!(
            "farm: submitted job array {id} ({} tasks, attempt {})",
            pending.len(),
            attempt + 1
        );
        let failed = wait(farm, &id, &pending);
        if failed.is_empty() || attempt == farm.retry {
            let report: Vec<(usize, u32)> = failed.iter().map(|&t| (t, attempt)).collect();
            return farm.report(&report);
        }
        eprintln!(
            "farm: {} tasks failed; resubmitting (retry {} of {})",
            failed.len(),
            attempt + 1,
            farm.retry
        );
        pending = failed;
        attempt += 1;
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
