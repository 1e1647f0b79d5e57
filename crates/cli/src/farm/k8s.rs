//! The Kubernetes scheduler: an Indexed Job manifest (JSON, which kubectl applies) whose pod i runs line i of `tasks.txt` from the farm's folder on a shared volume.
//!
//! The farm only writes the manifest; it never submits it, so an
//! interrupted `geode farm --scheduler k8s` has no job to delete (whoever
//! ran `kubectl create` deletes it: `kubectl delete job NAME`). Kubernetes
//! watches the pods itself: `--task-timeout` becomes each pod's
//! `activeDeadlineSeconds` (a pod past it fails and its index is retried up
//! to `--retry` times), and a pod on a lost node is failed and replaced by
//! the Job controller, so no heartbeat is watched here.

use anyhow::{Context, Result};
use serde_json::json;

use super::Farm;

/// The manifest: `completions` = the tasks, `parallelism` = `--jobs`, each
/// index retried by Kubernetes up to `--retry` times; the network's folder
/// (which holds the farm's folder, and should hold the outputs and the disk
/// cache) mounted at its own path from the claim `geode-farm`, which the
/// user provides; tasks run the image's `geode` (`tasks.k8s.txt`).
pub fn manifest(farm: &Farm, image: &str) -> serde_json::Value {
    let mut job = job(farm, image);
    if let Some(limit) = farm.task_timeout {
        job["spec"]["template"]["spec"]["activeDeadlineSeconds"] =
            json!(limit.as_secs_f64().ceil() as u64);
    }
    job
}

/// The Job before the optional per-pod deadline.
fn job(farm: &Farm, image: &str) -> serde_json::Value {
    let dir = farm.dir.display().to_string();
    let cache = farm.cache_dir.display().to_string();
    let run =
        format!("sh -c \"$(sed -n \"$((JOB_COMPLETION_INDEX + 1))p\" '{dir}/tasks.k8s.txt')\"");
    json!({
        "apiVersion": "batch/v1",
        "kind": "Job",
        "metadata": {"generateName": "geode-farm-", "labels": {"app": "geode-farm"}},
        "spec": {
            "completionMode": "Indexed",
            "completions": farm.tasks.len(),
            "parallelism": farm.jobs,
            "backoffLimitPerIndex": farm.retry,
            // A cook that exits saying the command, the network or the
            // cook is wrong fails the same way again: its index is not
            // retried (README: Exit status).
            "podFailurePolicy": {"rules": [{
                "action": "FailIndex",
                "onExitCodes": {"containerName": "cook", "operator": "In", "values": crate::exit::Exit::final_codes().collect::<Vec<_>>()},
            }]},
            "template": {
                "metadata": {"labels": {"app": "geode-farm"}},
                "spec": {
                    "restartPolicy": "Never",
                    "containers": [{
                        "name": "cook",
                        "image": image,
                        "command": ["sh", "-c", run],
                        "env": [{"name": "GEODE_CACHE_DIR", "value": cache}],
                        "resources": {"requests": {"cpu": "1"}},
                        "volumeMounts": [{"name": "farm", "mountPath": farm.root.display().to_string()}],
                    }],
                    "volumes": [{"name": "farm", "persistentVolumeClaim": {"claimName": "geode-farm"}}],
                },
            },
        },
    })
}

pub fn write(farm: &Farm, image: &str) -> Result<()> {
    let lines: String = farm
        .tasks
        .iter()
        .map(|t| {
            format!(
                "geode{}\n",
                t.command
                    .strip_prefix(farm.exe.as_str())
                    .unwrap_or(&t.command)
            )
        })
        .collect();
    let tasks = farm.dir.join("tasks.k8s.txt");
    std::fs::write(&tasks, lines)
        .with_context(|| format!("{}: cannot write the task list", tasks.display()))?;
    let path = farm.dir.join("job.json");
    let text =
        serde_json::to_string_pretty(&manifest(farm, image)).expect("a JSON value serialises");
    std::fs::write(&path, text + "\n")
        .with_context(|| format!("{}: cannot write the manifest", path.display()))?;
    println!("{}", path.display());
    eprintln!(
        "farm: wrote an Indexed Job of {} tasks; run it with `kubectl create -f {}` (the claim `geode-farm` must hold {} and {})",
        farm.tasks.len(),
        path.display(),
        farm.dir.display(),
        farm.cache_dir.display()
    );
    Ok(())
}
