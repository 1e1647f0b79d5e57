//! The shared estimate of a disk cache directory's bytes: an append-only log every process adds its writes and removals to, so the bound holds across many short processes without locks.
//!
//! `usage.log` at the cache's root is a header (magic, generation, creation
//! time, the counted bytes it starts from) followed by 16-byte records, each
//! a change in bytes and its complement as a check. A process appends one
//! record per save (a single `O_APPEND` write, which processes on a local
//! file system never interleave), then reads the records every process
//! appended since its last look: a few small system calls per save.
//!
//! Whoever lists the directory (a collection, a recount) replaces the log by
//! a new generation starting from the bytes it counted; the replacement is
//! written atomically, and readers notice the new generation and start over.
//! The estimate can drift: a process killed between writing a file and
//! appending its record, two processes writing one key, a record appended
//! to a log being replaced, appends on a network file system that are not
//! atomic. So it is never trusted for long: the log asks for a recount once
//! it holds [`Recount::records`] records or is older than [`Recount::age`],
//! and at once when it is missing or damaged.

use std::fs::File;
use std::hash::{BuildHasher, Hasher};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// The log's name in the cache directory.
pub const USAGE_LOG: &str = "usage.log";

const MAGIC: &[u8; 8] = b"GEODEUSE";
const HEADER: u64 = 32;
const RECORD: usize = 16;

/// How stale the shared estimate may grow before the directory is listed again.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Recount {
    /// Records (saves and removals, by all processes) since the last count.
    pub records: u64,
    /// Time since the last count.
    pub age: Duration,
}

impl Default for Recount {
    /// A recount every 4096 saves (a 64 KiB log) or 10 minutes.
    fn default() -> Recount {
        Recount {
            records: 4096,
            age: Duration::from_secs(600),
        }
    }
}

/// What the log says after a change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Usage {
    /// The directory's estimated bytes.
    Estimate(u64),
    /// The estimate is missing, damaged or stale: list the directory and
    /// [`UsageLog::restart`] from what it holds.
    Recount,
}

/// One process's view of the shared log.
pub struct UsageLog {
    path: PathBuf,
    recount: Recount,
    seen: Mutex<Seen>,
}

/// How far this process has read the log, and what it summed.
#[derive(Default)]
struct Seen {
    generation: u64,
    offset: u64,
    bytes: i64,
    records: u64,
}

struct Header {
    generation: u64,
    created: SystemTime,
    counted: i64,
}

impl UsageLog {
    /// The log of the cache directory `dir` (created on the first restart).
    pub fn new(dir: &Path, recount: Recount) -> UsageLog {
        UsageLog {
            path: dir.join(USAGE_LOG),
            recount,
            seen: Mutex::new(Seen::default()),
        }
    }

    /// Adds `change` bytes (negative for a removal) to the shared estimate and
    /// reads it back with every other process's changes.
    pub fn record(&self, change: i64) -> Usage {
        match self.append_and_read(change) {
            Ok(usage) => usage,
            Err(e) => {
                if e.kind() != std::io::ErrorKind::NotFound {
                    tracing::warn!(path = %self.path.display(), "disk cache usage log: {e}");
                }
                Usage::Recount
            }
        }
    }

    /// Starts a new generation of the log from `counted` bytes, just found by
    /// listing the directory.
    pub fn restart(&self, counted: u64) -> Result<(), geode_io::IoError> {
        let mut header = Vec::with_capacity(HEADER as usize);
        header.extend_from_slice(MAGIC);
        header.extend_from_slice(&new_generation().to_le_bytes());
        let now = SystemTime::now().duration_since(UNIX_EPOCH);
        header.extend_from_slice(&now.map_or(0, |d| d.as_secs()).to_le_bytes());
        header.extend_from_slice(&(counted.min(i64::MAX as u64) as i64).to_le_bytes());
        geode_io::write_atomic_shared(&self.path, |w| {
            w.write_all(&header)
                .map_err(|e| geode_io::IoError::os(&self.path, e))
        })
    }

    fn append_and_read(&self, change: i64) -> std::io::Result<Usage> {
        let mut file = File::options().read(true).append(true).open(&self.path)?;
        let Some(header) = read_header(&mut file)? else {
            return Ok(Usage::Recount);
        };
        if change != 0 {
            file.write_all(&encode_record(change))?;
        }
        let mut seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        if seen.generation != header.generation {
            *seen = Seen {
                generation: header.generation,
                offset: HEADER,
                bytes: header.counted,
                records: 0,
            };
        }
        if !read_new_records(&mut file, &mut seen)? {
            return Ok(Usage::Recount);
        }
        let age = SystemTime::now()
            .duration_since(header.created)
            .unwrap_or_default();
        if seen.records >= self.recount.records || age >= self.recount.age || seen.bytes < 0 {
            return Ok(Usage::Recount);
        }
        Ok(Usage::Estimate(seen.bytes as u64))
    }
}

/// The log's header, `None` when it is not one.
fn read_header(file: &mut File) -> std::io::Result<Option<Header>> {
    let mut b = [0u8; HEADER as usize];
    match file.read_exact(&mut b) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => return Ok(None),
        Err(e) => return Err(e),
    }
    if &b[..8] != MAGIC {
        return Ok(None);
    }
    let word = |i: usize| u64::from_le_bytes(b[i..i + 8].try_into().expect("8 bytes"));
    Ok(Some(Header {
        generation: word(8),
        created: UNIX_EPOCH + Duration::from_secs(word(16)),
        counted: word(24) as i64,
    }))
}

/// Sums the whole records appended since `seen` last read; `false` when one
/// fails its check (the log is damaged).
fn read_new_records(file: &mut File, seen: &mut Seen) -> std::io::Result<bool> {
    file.seek(SeekFrom::Start(seen.offset))?;
    let mut tail = Vec::new();
    file.read_to_end(&mut tail)?;
    // A record being appended right now is read next time.
    for record in tail.chunks_exact(RECORD) {
        let Some(change) = decode_record(record) else {
            return Ok(false);
        };
        seen.bytes = seen.bytes.saturating_add(change);
        seen.records += 1;
        seen.offset += RECORD as u64;
    }
    Ok(true)
}

fn encode_record(change: i64) -> [u8; RECORD] {
    let mut r = [0u8; RECORD];
    r[..8].copy_from_slice(&change.to_le_bytes());
    r[8..].copy_from_slice(&(!change).to_le_bytes());
    r
}

fn decode_record(r: &[u8]) -> Option<i64> {
    let change = i64::from_le_bytes(r[..8].try_into().ok()?);
    let check = i64::from_le_bytes(r[8..].try_into().ok()?);
    (check == !change).then_some(change)
}

/// A generation nobody else picks: the standard library's per-process random
/// hasher keys, mixed with the time.
fn new_generation() -> u64 {
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u128(
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos()),
    );
    h.write_u32(std::process::id());
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_processes_see_each_others_changes() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (
            UsageLog::new(dir.path(), Recount::default()),
            UsageLog::new(dir.path(), Recount::default()),
        );
        assert_eq!(a.record(10), Usage::Recount, "no log yet");
        a.restart(100).unwrap();
        assert_eq!(a.record(10), Usage::Estimate(110));
        assert_eq!(b.record(5), Usage::Estimate(115));
        assert_eq!(a.record(-20), Usage::Estimate(95));
        b.restart(7).unwrap();
        assert_eq!(a.record(1), Usage::Estimate(8), "a new generation");
        assert_eq!(b.record(0), Usage::Estimate(8));
    }

    #[test]
    fn a_damaged_or_old_log_asks_for_a_recount() {
        let dir = tempfile::tempdir().unwrap();
        let log = UsageLog::new(dir.path(), Recount::default());
        log.restart(0).unwrap();
        assert_eq!(log.record(3), Usage::Estimate(3));
        let path = dir.path().join(USAGE_LOG);
        let mut f = File::options().append(true).open(&path).unwrap();
        f.write_all(&[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16])
            .unwrap();
        assert_eq!(log.record(3), Usage::Recount, "a record failing its check");
        std::fs::write(&path, b"not a log").unwrap();
        assert_eq!(log.record(3), Usage::Recount, "a bad header");

        let few = UsageLog::new(
            dir.path(),
            Recount {
                records: 2,
                age: Duration::from_secs(600),
            },
        );
        few.restart(0).unwrap();
        assert_eq!(few.record(1), Usage::Estimate(1));
        assert_eq!(few.record(1), Usage::Recount, "two records: recount");
        let young = UsageLog::new(
            dir.path(),
            Recount {
                records: 100,
                age: Duration::ZERO,
            },
        );
        assert_eq!(young.record(1), Usage::Recount, "older than allowed");
    }
}
