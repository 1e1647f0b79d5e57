//! Atomic file writes: a temporary file in the target's folder, renamed
//! into place; temporary files left by a killed process are removed by the
//! next write to that folder.

use std::io::{BufWriter, Write};
use std::path::Path;
use std::time::{Duration, SystemTime};

use crate::error::IoError;

/// Writes `path` through `body`; the target is replaced only when `body`
/// succeeds and the data is flushed to disk, so a failed or interrupted write
/// never leaves a partial file there.
pub fn write_atomic<F>(path: &Path, body: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> Result<(), IoError>,
{
    write_atomic_in(path, body, true)
}

/// [`write_atomic`] for a folder other machines write too (a shared disk
/// cache): a temporary file is judged stale by its age alone, since its
/// process id may be another machine's.
pub fn write_atomic_shared<F>(path: &Path, body: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> Result<(), IoError>,
{
    write_atomic_in(path, body, false)
}

fn write_atomic_in<F>(path: &Path, body: F, local: bool) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> Result<(), IoError>,
{
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    remove_stale_temporaries_by(dir, local);
    let prefix = format!("{TMP_PREFIX}{}-", std::process::id());
    if !dir.is_dir() {
        return Err(IoError::os(
            path,
            std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("its folder {} does not exist", dir.display()),
            ),
        ));
    }
    let tmp = tempfile::Builder::new()
        .prefix(&prefix)
        .tempfile_in(dir)
        // tempfile names its temporary file in the error; the user named
        // only the target.
        .map_err(|e| IoError::os(path, bare(&e, dir)))?;
    {
        let mut w = BufWriter::with_capacity(1 << 20, tmp.as_file());
        body(&mut w)?;
        w.flush().map_err(|e| IoError::os(path, e))?;
    }
    tmp.as_file().sync_all().map_err(|e| IoError::os(path, e))?;
    set_permissions(tmp.path(), path).map_err(|e| IoError::os(path, e))?;
    // Dropping `tmp` on an error path deletes the temporary file.
    tmp.persist(path).map_err(|e| IoError::os(path, e.error))?;
    Ok(())
}

/// The system's error without the temporary file's name tempfile adds,
/// saying that no file could be made in `dir`.
fn bare(e: &std::io::Error, dir: &Path) -> std::io::Error {
    let why = match e.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code).to_string(),
        None => e.kind().to_string(),
    };
    std::io::Error::new(
        e.kind(),
        format!("no file can be made in {}: {why}", dir.display()),
    )
}

/// Temporary files are `.geode-tmp-<pid>-<random>`.
const TMP_PREFIX: &str = ".geode-tmp-";

/// A temporary file nobody will finish after this long is stale whatever its
/// process id says (another machine's, on a shared folder).
const STALE_AFTER: Duration = Duration::from_secs(24 * 3600);

/// Removes temporary files in `dir` left by geode processes that no longer
/// run on this machine (killed mid-write: `kill -9`, power loss), or older
/// than a day. Best effort: a folder that cannot be listed is left alone.
/// `by_pid`: a temporary file of a process not running here is stale (only
/// right when no other machine writes the folder).
fn remove_stale_temporaries_by(dir: &Path, by_pid: bool) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(TMP_PREFIX)) else {
            continue;
        };
        let pid = rest.split('-').next().and_then(|p| p.parse::<u32>().ok());
        let dead = by_pid && pid.is_some_and(|p| !process_alive(p));
        if dead || abandoned_temporary(&e, STALE_AFTER) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// Whether `e` is an atomic write's temporary file untouched for longer
/// than `after`: one no write will finish (a killed process's).
pub fn abandoned_temporary(e: &std::fs::DirEntry, after: Duration) -> bool {
    e.file_name()
        .to_str()
        .is_some_and(|n| n.starts_with(TMP_PREFIX))
        && e.metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|t| SystemTime::now().duration_since(t).ok())
            .is_some_and(|age| age > after)
}

/// Whether a process with this id runs on this machine (Linux: /proc);
/// elsewhere every process counts as running, so only age decides.
pub fn process_alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let proc = Path::new("/proc");
    !proc.is_dir() || proc.join(pid.to_string()).exists()
}

/// A writer that fails once `cancelled` says so, polled at every write
/// reaching it (the buffered writer above it passes a megabyte at a time).
pub(crate) struct Cancelling<'a> {
    pub inner: &'a mut dyn Write,
    pub cancelled: &'a dyn Fn() -> bool,
}

impl Write for Cancelling<'_> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if (self.cancelled)() {
            return Err(std::io::Error::other("cancelled"));
        }
        self.inner.write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// Temporary files are created private (0600); the result should look like
/// any file the user writes: the old file's permissions, or 0644.
fn set_permissions(tmp: &Path, target: &Path) -> std::io::Result<()> {
    let perms = match std::fs::metadata(target) {
        Ok(m) => m.permissions(),
        Err(_) => {
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                std::fs::Permissions::from_mode(0o644)
            }
            #[cfg(not(unix))]
            {
                return Ok(());
            }
        }
    };
    std::fs::set_permissions(tmp, perms)
}

/// Maps an OS error while writing to an [`IoError`] for `path`.
pub(crate) fn os_err(path: &Path) -> impl Fn(std::io::Error) -> IoError + '_ {
    move |e| IoError::os(path, e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed_by_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        // A process that has exited: its id is free (and not reused this soon).
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let stale = dir.path().join(format!("{TMP_PREFIX}{dead}-abc123"));
        std::fs::write(&stale, b"half").unwrap();
        let live = dir
            .path()
            .join(format!("{TMP_PREFIX}{}-def456", std::process::id()));
        std::fs::write(&live, b"in progress").unwrap();
        let other = dir.path().join("keep.obj");
        std::fs::write(&other, b"user data").unwrap();
        let target = dir.path().join("out.obj");
        write_atomic(&target, |w| w.write_all(b"x").map_err(os_err(&target))).unwrap();
        assert!(
            !stale.exists(),
            "a dead process's temporary file is removed"
        );
        assert!(live.exists(), "a running process's temporary file is kept");
        assert_eq!(std::fs::read(&other).unwrap(), b"user data");
    }

    #[test]
    fn failed_write_keeps_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.obj");
        std::fs::write(&target, b"precious").unwrap();
        let err = write_atomic(&target, |w| {
            w.write_all(b"half a fi").unwrap();
            Err(IoError::Unsupported {
                path: target.clone(),
                message: "boom".into(),
            })
        });
        assert!(err.is_err());
        assert_eq!(std::fs::read(&target).unwrap(), b"precious");
        let leftovers: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(leftovers.len(), 1, "temporary file removed");
        write_atomic(&target, |w| w.write_all(b"new").map_err(os_err(&target))).unwrap();
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let fresh = dir.path().join("fresh.obj");
            write_atomic(&fresh, |w| w.write_all(b"x").map_err(os_err(&fresh))).unwrap();
            let mode = std::fs::metadata(&fresh).unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o644, "not the temporary file's private mode");
        }
    }
}
