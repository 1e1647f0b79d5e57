//! The heartbeat of a farm task: `geode cook` run by a farm touches a file while it runs, so the farm can tell a live task from one the scheduler still calls running though its process is gone.

use std::path::PathBuf;
use std::time::Duration;

/// The file to touch (set by the farm for each attempt).
pub const PATH_VAR: &str = "GEODE_FARM_HEARTBEAT";
/// How often, in milliseconds (the farm derives it from its stall limit).
pub const EVERY_MS_VAR: &str = "GEODE_FARM_HEARTBEAT_MS";
/// The process id of a local farm running this task: when it is gone
/// (killed with SIGKILL, which it cannot catch to kill its tasks), the
/// task stops rather than cook on for nobody.
pub const FARM_PID_VAR: &str = "GEODE_FARM_PID";

/// Starts touching the heartbeat file the environment names, on a thread of
/// its own so a long kernel never delays a beat; nothing if none is named.
/// The first beat is written before this returns.
pub fn start_from_env() {
    let Some(path) = std::env::var_os(PATH_VAR)
        .filter(|p| !p.is_empty())
        .map(PathBuf::from)
    else {
        return;
    };
    let every = std::env::var(EVERY_MS_VAR)
        .ok()
        .and_then(|v| v.parse().ok())
        .map_or(Duration::from_secs(2), Duration::from_millis);
    let farm = std::env::var(FARM_PID_VAR)
        .ok()
        .and_then(|v| v.parse::<u32>().ok());
    beat(&path);
    std::thread::Builder::new()
        .name("farm-heartbeat".into())
        .spawn(move || loop {
            std::thread::sleep(every);
            if farm.is_some_and(|pid| !geode_io::process_alive(pid)) {
                // Outputs are written atomically: stopping here leaves none
                // half-written.
                eprintln!("farm process {} is gone; stopping", farm.unwrap_or(0));
                std::process::exit(130);
            }
            beat(&path);
        })
        .map(drop)
        .unwrap_or_else(|e| eprintln!("warning: cannot start the farm heartbeat: {e}"));
}

/// One beat: the file's modification time is what the farm reads.
fn beat(path: &std::path::Path) {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    if let Err(e) = std::fs::write(path, format!("{now}\n")) {
        eprintln!(
            "warning: {}: cannot write the farm heartbeat: {e}",
            path.display()
        );
    }
}
