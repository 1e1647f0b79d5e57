//! Atomic file writes: a temporary file in the target's folder, renamed into place.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::IoError;

/// Writes `path` through `body`; the target is replaced only when `body`
/// succeeds and the data is flushed to disk, so a failed or interrupted write
/// never leaves a partial file there.
pub fn write_atomic<F>(path: &Path, body: F) -> Result<(), IoError>
where
    F: FnOnce(&mut dyn Write) -> Result<(), IoError>,
{
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let tmp = tempfile::Builder::new()
        .prefix(".geode-tmp-")
        .tempfile_in(dir)
        .map_err(|e| IoError::os(path, e))?;
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
