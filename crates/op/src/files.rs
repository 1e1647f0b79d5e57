//! Which files cooks may touch, and how they read them: anywhere (`geode
//! cook`) or only under some folders (the studio), symlinks resolved before
//! the check; only regular files are read, their size reserved against the
//! memory budget before a byte is read, and reads stop when cancelled.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::env::human_bytes;

/// Bytes read between two looks at cancellation.
const CHUNK: usize = 8 << 20;

/// Where cooks may read and write files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FileAccess {
    /// Canonical folders (symlinks resolved); `None` for anywhere.
    roots: Option<Arc<[PathBuf]>>,
}

/// Why a file was not read or may not be written.
#[derive(Debug, thiserror::Error)]
pub enum FileRefusal {
    #[error("{}{}: outside the folders this studio may {verb} ({}); start `geode serve` with `--allow DIR` to add one", path.display(), resolved(path, real), list(roots))]
    Outside {
        path: PathBuf,
        /// Where `path` leads once its symlinks are resolved.
        real: PathBuf,
        verb: &'static str,
        roots: Arc<[PathBuf]>,
    },
    #[error("{}: not a regular file ({what}); only regular files are read", path.display())]
    NotRegular { path: PathBuf, what: &'static str },
    #[error("{}: the file's {} would exceed the memory budget of {} (GEODE_MEMORY_MB)", path.display(), human_bytes(*size as f64), human_bytes(*budget as f64))]
    TooLarge {
        path: PathBuf,
        size: u64,
        budget: u64,
    },
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cancelled")]
    Cancelled,
}

/// ` (which leads to REAL)` where the asked path is not the real one.
fn resolved(path: &Path, real: &Path) -> String {
    if path == real {
        String::new()
    } else {
        format!(" (which leads to {})", real.display())
    }
}

fn list(roots: &[PathBuf]) -> String {
    roots
        .iter()
        .map(|r| r.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> FileRefusal + '_ {
    move |source| FileRefusal::Io {
        path: path.to_owned(),
        source,
    }
}

/// What a non-regular file is, for the message.
fn kind_of(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a pipe";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "not a plain file"
    }
}

impl FileAccess {
    /// Any file the process can reach (`geode cook`, the farm).
    pub fn anywhere() -> FileAccess {
        FileAccess::default()
    }

    /// Only files under `roots` (each resolved to its canonical form now:
    /// a root that does not exist is an error).
    pub fn confined(roots: impl IntoIterator<Item = PathBuf>) -> std::io::Result<FileAccess> {
        let roots = roots
            .into_iter()
            .map(|r| r.canonicalize())
            .collect::<std::io::Result<Vec<_>>>()?;
        Ok(FileAccess {
            roots: Some(roots.into()),
        })
    }

    /// The folders files must be under, or `None` for anywhere.
    pub fn roots(&self) -> Option<&[PathBuf]> {
        self.roots.as_deref()
    }

    fn inside(
        &self,
        real: PathBuf,
        asked: &Path,
        verb: &'static str,
    ) -> Result<PathBuf, FileRefusal> {
        match &self.roots {
            Some(roots) if !roots.iter().any(|r| real.starts_with(r)) => {
                Err(FileRefusal::Outside {
                    path: asked.to_owned(),
                    real,
                    verb,
                    roots: roots.clone(),
                })
            }
            _ => Ok(real),
        }
    }

    /// The real path of a file that may be read: inside the roots once
    /// every symlink is resolved, and a regular file.
    pub fn readable(&self, path: &Path) -> Result<PathBuf, FileRefusal> {
        let real = match path.canonicalize() {
            Ok(real) => real,
            Err(e) => {
                // Outside the roots, a missing file is refused like any
                // other: the studio never tells what exists out there.
                if let Some(ancestor) = path.ancestors().skip(1).find_map(|a| {
                    let a = if a.as_os_str().is_empty() {
                        Path::new(".")
                    } else {
                        a
                    };
                    a.canonicalize().ok()
                }) {
                    self.inside(ancestor, path, "read")?;
                }
                return Err(io(path)(e));
            }
        };
        let real = self.inside(real, path, "read")?;
        let t = std::fs::metadata(&real).map_err(io(path))?.file_type();
        if !t.is_file() {
            return Err(FileRefusal::NotRegular {
                path: path.to_owned(),
                what: kind_of(t),
            });
        }
        Ok(real)
    }

    /// The real path a file may be written at: its folder inside the roots
    /// once resolved, and the file itself, if it exists, a regular file.
    /// Missing folders on the way are made (as Houdini's output nodes make
    /// them), once the path is known to be inside the roots.
    pub fn writable(&self, path: &Path) -> Result<PathBuf, FileRefusal> {
        let real = match path.canonicalize() {
            Ok(real) => real,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                if path.file_name().is_none() {
                    return Err(FileRefusal::NotRegular {
                        path: path.to_owned(),
                        what: "a folder",
                    });
                }
                // The nearest folder that exists, resolved, and the rest as
                // written (plain names only: no `..` past what was resolved).
                let mut existing = path;
                let mut rest = Vec::new();
                loop {
                    match existing.parent() {
                        Some(p) => {
                            rest.push(existing.file_name().unwrap_or_default());
                            existing = if p.as_os_str().is_empty() {
                                Path::new(".")
                            } else {
                                p
                            };
                            if existing.exists() {
                                break;
                            }
                        }
                        None => return Err(io(path)(e)),
                    }
                }
                let tail_ok = rest.iter().all(|c| {
                    let c = Path::new(c);
                    c.components().count() == 1
                        && matches!(c.components().next(), Some(std::path::Component::Normal(_)))
                });
                if !tail_ok {
                    return Err(io(path)(e));
                }
                let mut real = existing.canonicalize().map_err(io(path))?;
                for c in rest.iter().rev() {
                    real.push(c);
                }
                real
            }
            Err(e) => return Err(io(path)(e)),
        };
        let real = self.inside(real, path, "write")?;
        match std::fs::metadata(&real) {
            Ok(m) if !m.file_type().is_file() => Err(FileRefusal::NotRegular {
                path: path.to_owned(),
                what: kind_of(m.file_type()),
            }),
            _ => {
                if let Some(folder) = real.parent() {
                    std::fs::create_dir_all(folder).map_err(io(path))?;
                }
                Ok(real)
            }
        }
    }

    /// Reads a whole file: refused outside the roots, when it is no regular
    /// file, or when its size exceeds `budget` (before reading); stops when
    /// `cancelled` says so.
    pub fn read(
        &self,
        path: &Path,
        budget: u64,
        cancelled: &dyn Fn() -> bool,
    ) -> Result<Vec<u8>, FileRefusal> {
        let real = self.readable(path)?;
        let file = std::fs::File::open(&real).map_err(io(path))?;
        let meta = file.metadata().map_err(io(path))?;
        if !meta.file_type().is_file() {
            return Err(FileRefusal::NotRegular {
                path: path.to_owned(),
                what: kind_of(meta.file_type()),
            });
        }
        let size = meta.len();
        if size > budget {
            return Err(FileRefusal::TooLarge {
                path: path.to_owned(),
                size,
                budget,
            });
        }
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(size as usize)
            .map_err(|_| FileRefusal::TooLarge {
                path: path.to_owned(),
                size,
                budget,
            })?;
        // A file that grows while read stops at the budget.
        let mut limited = file.take(budget.saturating_add(1));
        loop {
            if cancelled() {
                return Err(FileRefusal::Cancelled);
            }
            let start = bytes.len();
            let n = (&mut limited)
                .take(CHUNK as u64)
                .read_to_end(&mut bytes)
                .map_err(io(path))?;
            if bytes.len() as u64 > budget {
                return Err(FileRefusal::TooLarge {
                    path: path.to_owned(),
                    size: bytes.len() as u64,
                    budget,
                });
            }
            if n == 0 || bytes.len() == start {
                return Ok(bytes);
            }
        }
    }

    /// Reads a whole text file (a network, a script) as `read` does; bytes
    /// that are not UTF-8 are an I/O error naming the file.
    pub fn read_text(
        &self,
        path: &Path,
        budget: u64,
        cancelled: &dyn Fn() -> bool,
    ) -> Result<String, FileRefusal> {
        let bytes = self.read(path, budget, cancelled)?;
        String::from_utf8(bytes).map_err(|e| FileRefusal::Io {
            path: path.to_owned(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidData, e),
        })
    }

    /// The content hash of a file a node reads, for its cache key, read in
    /// chunks (nothing held); `None` when it may not or cannot be read (the
    /// cook then reports why) or when cancelled.
    pub fn content_hash(&self, path: &Path, cancelled: &dyn Fn() -> bool) -> Option<u128> {
        let real = self.readable(path).ok()?;
        let mut file = std::fs::File::open(real).ok()?;
        let mut hasher = xxhash_rust::xxh3::Xxh3::new();
        let mut buf = vec![0u8; CHUNK];
        loop {
            if cancelled() {
                return None;
            }
            match file.read(&mut buf) {
                Ok(0) => return Some(hasher.digest128()),
                Ok(n) => hasher.update(&buf[..n]),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(_) => return None,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn never() -> bool {
        false
    }

    #[test]
    fn confined_reads_and_writes_stay_under_the_roots_through_symlinks() {
        let inside = tempfile::tempdir().unwrap();
        let outside = tempfile::tempdir().unwrap();
        let secret = outside.path().join("secret.obj");
        std::fs::write(&secret, "v 0 0 0\n").unwrap();
        let own = inside.path().join("own.obj");
        std::fs::write(&own, "v 1 1 1\n").unwrap();
        let access = FileAccess::confined([inside.path().to_owned()]).unwrap();
        assert_eq!(access.read(&own, 1 << 20, &never).unwrap(), b"v 1 1 1\n");
        let e = access.read(&secret, 1 << 20, &never).unwrap_err();
        assert!(
            matches!(e, FileRefusal::Outside { verb: "read", .. }),
            "{e}"
        );
        assert!(e.to_string().contains("--allow DIR"), "{e}");
        #[cfg(unix)]
        {
            let link = inside.path().join("link.obj");
            std::os::unix::fs::symlink(&secret, &link).unwrap();
            assert!(matches!(
                access.read(&link, 1 << 20, &never),
                Err(FileRefusal::Outside { .. })
            ));
            let dir_link = inside.path().join("out");
            std::os::unix::fs::symlink(outside.path(), &dir_link).unwrap();
            assert!(matches!(
                access.writable(&dir_link.join("new.obj")),
                Err(FileRefusal::Outside { verb: "write", .. })
            ));
        }
        assert!(access.writable(&inside.path().join("new.obj")).is_ok());
        assert!(matches!(
            access.writable(&outside.path().join("new.obj")),
            Err(FileRefusal::Outside { .. })
        ));
        assert!(FileAccess::anywhere()
            .read(&secret, 1 << 20, &never)
            .is_ok());
        // A missing file outside is refused as outside (its absence not told).
        assert!(matches!(
            access.readable(&outside.path().join("nope.obj")),
            Err(FileRefusal::Outside { .. })
        ));
        assert!(matches!(
            access.readable(&inside.path().join("nope.obj")),
            Err(FileRefusal::Io { .. })
        ));
    }

    #[cfg(unix)]
    #[test]
    fn missing_folders_are_made_inside_the_roots_only() {
        let inside = tempfile::tempdir().unwrap();
        let outside = tempfile::tempdir().unwrap();
        let access = FileAccess::confined([inside.path().to_owned()]).unwrap();
        let deep = inside.path().join("out/frames/f.0001.obj");
        let real = access.writable(&deep).unwrap();
        assert!(real.parent().unwrap().is_dir(), "out/frames made");
        // Outside the roots nothing is made.
        let far = outside.path().join("made/here.obj");
        assert!(access.writable(&far).is_err());
        assert!(!outside.path().join("made").exists());
        // `..` after a missing folder is not followed.
        let sneaky = inside.path().join("nothere/../../escape.obj");
        assert!(access.writable(&sneaky).is_err());
    }

    #[test]
    fn devices_are_refused_before_reading_even_behind_a_link() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("zero.obj");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        for access in [
            FileAccess::anywhere(),
            FileAccess::confined([PathBuf::from("/")]).unwrap(),
        ] {
            let e = access.read(&link, 1 << 20, &never).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!(
                    "{}: not a regular file (a character device); only regular files are read",
                    link.display()
                )
            );
            assert_eq!(access.content_hash(&link, &never), None);
        }
    }

    #[test]
    fn a_file_over_the_budget_is_refused_before_reading_and_reads_stop_when_cancelled() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("big.obj");
        std::fs::write(&f, vec![b'x'; 4096]).unwrap();
        let access = FileAccess::anywhere();
        assert!(matches!(
            access.read(&f, 4095, &never),
            Err(FileRefusal::TooLarge {
                size: 4096,
                budget: 4095,
                ..
            })
        ));
        assert_eq!(access.read(&f, 4096, &never).unwrap().len(), 4096);
        assert!(matches!(
            access.read(&f, 4096, &|| true),
            Err(FileRefusal::Cancelled)
        ));
        assert_eq!(access.content_hash(&f, &|| true), None);
        let same = dir.path().join("same.obj");
        std::fs::write(&same, vec![b'x'; 4096]).unwrap();
        assert_eq!(
            access.content_hash(&f, &never),
            access.content_hash(&same, &never)
        );
    }
}
