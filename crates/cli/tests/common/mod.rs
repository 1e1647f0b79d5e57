//! Running the built `geode` in the CLI's end-to-end tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `geode ARGS` in `dir` with extra environment variables.
pub fn geode_in(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_geode"));
    c.args(args).current_dir(dir);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

/// `geode ARGS` at the repository root.
pub fn geode(args: &[&str], env: &[(&str, &str)]) -> Output {
    geode_in(&root(), args, env)
}

pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Standard output then standard error.
pub fn text(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned() + &stderr(o)
}

/// Whether Slurm can take jobs here; a test without it fails, unless the
/// run skips oracles or Slurm (GEODE_SKIP_ORACLES=1, GEODE_SKIP_SLURM=1:
/// tools/test.sh sets the latter where it cannot start Slurm, not root):
/// then the caller skips, saying so.
pub fn slurm_ready() -> bool {
    let ok = Command::new("sinfo")
        .args(["-h", "-o", "%t"])
        .output()
        .is_ok_and(|o| {
            o.status.success()
                && String::from_utf8_lossy(&o.stdout)
                    .lines()
                    .any(|l| ["idle", "mix", "alloc", "plnd"].contains(&l.trim()))
        });
    if !ok {
        let skip = |var: &str| std::env::var_os(var).is_some_and(|v| v == "1");
        assert!(
            skip("GEODE_SKIP_ORACLES") || skip("GEODE_SKIP_SLURM"),
            "no Slurm node takes jobs: run bash tools/test.sh (it starts one), or tools/slurm.sh start and export SLURM_CONF; GEODE_SKIP_SLURM=1 skips these tests"
        );
        eprintln!("skipping: no Slurm cluster (tools/slurm.sh start; export SLURM_CONF)");
    }
    ok
}

/// The one-machine cluster, held by one test at a time: `flock(1)` on a
/// file every Slurm test locks (in any test binary, any checkout), since
/// one test stops slurmd and another counts the queue. The lock lives as
/// long as the returned `flock`, which waits on its standard input: dropping
/// it (or the test process dying) closes that and releases the lock.
/// (`File::lock` needs Rust 1.89, above the workspace's MSRV.)
pub struct SlurmLock(std::process::Child);

pub fn slurm_lock() -> SlurmLock {
    use std::io::BufRead;
    use std::process::Stdio;
    let path = std::env::temp_dir().join("geode-slurm-tests.lock");
    let mut child = Command::new("flock")
        .arg(&path)
        .args(["-c", "echo locked; exec cat >/dev/null"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("flock (util-linux) serialises the Slurm tests");
    let mut line = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    assert_eq!(line.trim(), "locked", "flock {}", path.display());
    SlurmLock(child)
}

/// The cluster for one test: its lock taken first (a test holding it may
/// have stopped slurmd), then `None` if no node takes jobs (the test skips).
pub fn slurm_cluster() -> Option<SlurmLock> {
    let lock = slurm_lock();
    slurm_ready().then_some(lock)
}

impl Drop for SlurmLock {
    fn drop(&mut self) {
        drop(self.0.stdin.take());
        let _ = self.0.wait();
    }
}
