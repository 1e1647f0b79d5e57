//! The Slurm scheduler: job arrays through `sbatch` (task i runs line i of `tasks.txt`; arrays of at most the cluster's `MaxArraySize`, offset per chunk), waited for by their status files, failed tasks resubmitted up to `--retry` times.

use std::process::Command;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context, Result};

use super::{shell_quote, Farm};

/// The array job's script: task `SLURM_ARRAY_TASK_ID + GEODE_FARM_OFFSET`
/// runs its line of `tasks.txt` through `sh`, its output to its attempt's
/// log, then writes its exit status atomically.
fn script(farm: &Farm, attempt: u32) -> String {
    let dir = shell_quote(&farm.dir.display().to_string());
    let cache = shell_quote(&farm.cache_dir.display().to_string());
    format!(
        "#!/bin/sh\n\
         #SBATCH --job-name=geode-farm\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --output=/dev/null\n\
         export GEODE_CACHE_DIR={cache}\n\
         t=$((SLURM_ARRAY_TASK_ID + ${{GEODE_FARM_OFFSET:-0}}))\n\
         line=$(sed -n \"$((t + 1))p\" {dir}/tasks.txt)\n\
         sh -c \"$line\" > {dir}/task-$t.attempt-{attempt}.log 2>&1\n\
         code=$?\n\
         echo $code > {dir}/task-$t.status.tmp && mv {dir}/task-$t.status.tmp {dir}/task-$t.status\n\
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

/// Submits `tasks` (at most `jobs` at once) as job arrays of at most the
/// cluster's array size, each offset to its chunk; the job ids.
fn submit(farm: &Farm, tasks: &[usize], attempt: u32) -> Result<Vec<String>> {
    let path = farm.dir.join(format!("farm.attempt-{attempt}.sbatch"));
    std::fs::write(&path, script(farm, attempt))
        .with_context(|| format!("{}: cannot write the job script", path.display()))?;
    for &t in tasks {
        let _ = std::fs::remove_file(farm.status(t));
    }
    let chunk = max_array_size().max(1);
    let mut ids = Vec::new();
    for group in tasks.chunk_by(|a, b| a / chunk == b / chunk) {
        let offset = group[0] / chunk * chunk;
        let indices: Vec<usize> = group.iter().map(|t| t - offset).collect();
        ids.push(submit_array(farm, &path, &indices, offset)?);
    }
    Ok(ids)
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

/// Whether any of the jobs still has tasks queued or running.
fn queued(ids: &[String]) -> bool {
    Command::new("squeue")
        .args(["-h", "-j", &ids.join(","), "-o", "%i"])
        .output()
        .map(|o| o.status.success() && !String::from_utf8_lossy(&o.stdout).trim().is_empty())
        .unwrap_or(false)
}

/// Waits until every task has a status or the job has left the queue;
/// returns the tasks that did not succeed.
fn wait(farm: &Farm, ids: &[String], tasks: &[usize]) -> Vec<usize> {
    let id = ids.join(",");
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
        if finished == tasks.len() || !queued(ids) {
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
        let ids = submit(farm, &pending, attempt)?;
        eprintln!(
            "farm: submitted job array {} ({} tasks, attempt {})",
            ids.join(", "),
            pending.len(),
            attempt + 1
        );
        let failed = wait(farm, &ids, &pending);
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
