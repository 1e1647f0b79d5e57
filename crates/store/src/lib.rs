//! geode's disk cache: cook results content-addressed on a directory that many processes and machines share, behind the memory cache, bounded across all of them.
//!
//! An entry is named by its cook key (`ab/<key>.gve`, 256 folders by the
//! key's first byte); a packed instance's source by its content hash
//! (`ab/<hash>.gvs`), written once and shared. Writes go to a temporary
//! file, are synced and renamed into place (`geode_io::write_atomic_shared`),
//! so a reader sees a whole entry or none, and two writers of one key both
//! leave a valid entry (the same bytes: keys name content). Every entry ends
//! with an xxh3-128 checksum and records in its header the key it was
//! written under and the kind of value it holds: a damaged entry, or one
//! holding another key or kind than its name asks (a copied file), is a
//! miss and is removed, never an error and never served.
//!
//! The bound holds across processes: every save adds its bytes to a shared
//! estimate of the directory's size ([`UsageLog`], `usage.log`, lock-free),
//! and the save that finds the estimate over the bound collects at once,
//! however short-lived its process. A collection removes the least
//! recently used files (reads refresh a file's modification time) down to
//! a low-water mark, 90% of the bound, so the next saves do not collect
//! again, and restarts the estimate from the bytes it counted. The estimate
//! is recounted from a listing when it grows stale, so a killed process
//! cannot leave it wrong for long. A file another process removes while
//! this one reads is a miss.

mod entry;
mod usage;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, Weak};
use std::time::SystemTime;

use entry::{Asked, EntryError};
use geode_geo::codec::DecodeError;
use geode_geo::Geometry;
use geode_graph::{Cached, Store};

pub use usage::{Recount, Usage, UsageLog, USAGE_LOG};

/// The default bound of a disk cache (`GEODE_CACHE_DISK_MB`).
pub const DEFAULT_DISK_MB: u64 = 10 * 1024;

/// A collection brings the directory down to this share of its bound (in
/// percent), leaving room for the next saves before the next collection.
pub const LOW_WATER_PERCENT: u64 = 90;

/// A disk cache on one directory, bounded by bytes.
pub struct DiskCache {
    dir: PathBuf,
    budget: u64,
    /// The directory's size as every process sharing it has changed it.
    usage: UsageLog,
    /// Sources already read, shared by every entry that places them.
    sources: Mutex<HashMap<u128, Weak<Geometry>>>,
}

/// What the directory holds.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DiskStats {
    pub entries: u64,
    pub sources: u64,
    pub bytes: u64,
    pub budget: u64,
}

/// What a collection removed.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct GcReport {
    pub removed: u64,
    pub freed: u64,
    pub bytes_after: u64,
}

/// How long a save may take: a temporary file older than this was left by
/// a process killed mid-save (on this machine or another sharing the
/// folder), and counts and goes like any file.
const ABANDONED_AFTER: std::time::Duration = std::time::Duration::from_secs(600);

/// An entry or source file found by listing the directory.
struct CacheFile {
    last_used: SystemTime,
    size: u64,
    path: PathBuf,
    is_entry: bool,
}

impl DiskCache {
    /// A cache on `dir` (created if missing) bounded by `budget` bytes.
    pub fn open(dir: impl Into<PathBuf>, budget: u64) -> std::io::Result<DiskCache> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir)?;
        Ok(DiskCache {
            usage: UsageLog::new(&dir, Recount::default()),
            dir,
            budget,
            sources: Mutex::new(HashMap::new()),
        })
    }

    /// The same cache, listing its directory again after `recount` (how
    /// stale the shared size estimate may grow).
    pub fn with_recount(mut self, recount: Recount) -> DiskCache {
        self.usage = UsageLog::new(&self.dir, recount);
        self
    }

    /// The cache `GEODE_CACHE_DIR` names, bounded by `GEODE_CACHE_DISK_MB`
    /// (default 10 GiB); `None` when the variable is unset or empty.
    pub fn from_env() -> Option<std::io::Result<DiskCache>> {
        let dir = std::env::var_os("GEODE_CACHE_DIR").filter(|d| !d.is_empty())?;
        let mb = std::env::var("GEODE_CACHE_DISK_MB")
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
            .unwrap_or(DEFAULT_DISK_MB);
        Some(DiskCache::open(
            PathBuf::from(dir),
            mb.saturating_mul(1_000_000),
        ))
    }

    /// A cook cache from the process's settings: the memory cache of
    /// `Cache::from_env()` with, when `GEODE_CACHE_DIR` names one, this disk
    /// cache behind it (what `geode cook` and Python's `geode` both use).
    pub fn cook_cache_from_env() -> std::io::Result<geode_graph::Cache> {
        Ok(match DiskCache::from_env() {
            Some(disk) => geode_graph::Cache::from_env().with_store(std::sync::Arc::new(disk?)),
            None => geode_graph::Cache::from_env(),
        })
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The bound, in bytes.
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// The bytes a collection leaves at most.
    pub fn low_water(&self) -> u64 {
        self.budget / 100 * LOW_WATER_PERCENT + self.budget % 100 * LOW_WATER_PERCENT / 100
    }

    fn path(&self, name: u128, ext: &str) -> PathBuf {
        let hex = format!("{name:032x}");
        self.dir.join(&hex[..2]).join(format!("{hex}.{ext}"))
    }

    /// The verified body of an entry file; a damaged one is removed. A file
    /// that vanished (collected by another process) is a miss.
    fn read(&self, path: &Path) -> Option<Vec<u8>> {
        let bytes = std::fs::read(path).ok()?;
        if entry::verified(&bytes).is_none() {
            tracing::warn!(path = %path.display(), "disk cache: bad checksum, entry removed");
            self.remove(path);
            return None;
        }
        touch(path);
        let n = bytes.len() - 16;
        let mut bytes = bytes;
        bytes.truncate(n);
        Some(bytes)
    }

    /// The value of the file at `path` if it holds what `asked` names. A
    /// damaged file, or one holding another key or kind, is removed; one
    /// whose packed source is missing is kept (it serves again once the
    /// source is back).
    fn read_entry(&self, path: &Path, asked: Asked) -> Option<Cached> {
        let body = self.read(path)?;
        match entry::decode(&body, asked, &|h| self.source(h)) {
            Ok(c) => Some(c),
            Err(EntryError::Decode(DecodeError::MissingSource(_))) => None,
            Err(e) => {
                tracing::warn!(path = %path.display(), "disk cache: {e}, entry removed");
                self.remove(path);
                None
            }
        }
    }

    fn source(&self, hash: u128) -> Option<Arc<Geometry>> {
        if let Some(g) = self.lock_sources().get(&hash).and_then(Weak::upgrade) {
            return Some(g);
        }
        let path = self.path(hash, "gvs");
        let cached = self.read_entry(&path, Asked::Source(hash))?;
        let geode_op::Value::Geometry(g) = cached.value else {
            return None;
        };
        if g.content_hash() != hash {
            self.remove(&path);
            return None;
        }
        self.lock_sources().insert(hash, Arc::downgrade(&g));
        Some(g)
    }

    fn lock_sources(&self) -> std::sync::MutexGuard<'_, HashMap<u128, Weak<Geometry>>> {
        self.sources.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Removes a file that cannot serve, taking its bytes off the estimate.
    fn remove(&self, path: &Path) {
        let Ok(size) = std::fs::metadata(path).map(|m| m.len()) else {
            return;
        };
        if std::fs::remove_file(path).is_ok() {
            self.account(-(size as i64));
        }
    }

    /// Writes `bytes` under `path` (callers skip entries already there);
    /// whether it was written.
    fn write(&self, path: &Path, bytes: &[u8]) -> bool {
        if let Some(parent) = path.parent() {
            let _ = std::fs::create_dir_all(parent);
        }
        let r = geode_io::write_atomic_shared(path, |w| {
            w.write_all(bytes)
                .map_err(|e| geode_io::IoError::os(path, e))
        });
        if let Err(e) = &r {
            tracing::warn!("disk cache: {e}");
        }
        r.is_ok()
    }

    /// Writes packed sources (and theirs) not yet on disk; the bytes written.
    fn write_sources(&self, mut pending: Vec<Arc<Geometry>>) -> u64 {
        let mut done = std::collections::HashSet::new();
        let mut written = 0;
        while let Some(g) = pending.pop() {
            let hash = g.content_hash();
            if !done.insert(hash) {
                continue;
            }
            let path = self.path(hash, "gvs");
            if path.exists() {
                continue;
            }
            if let Some((bytes, more)) = entry::encode_source(&g) {
                pending.extend(more);
                if self.write(&path, &bytes) {
                    written += bytes.len() as u64;
                }
            }
        }
        written
    }

    /// Adds `change` bytes to the shared estimate and collects when the
    /// directory is over its bound (or counts it again when the estimate
    /// cannot be trusted).
    fn account(&self, change: i64) {
        let result = match self.usage.record(change) {
            Usage::Estimate(bytes) if bytes <= self.budget => return,
            Usage::Estimate(_) => self.gc().map(drop),
            Usage::Recount => self.recount(),
        };
        if let Err(e) = result {
            tracing::warn!("disk cache: collecting {}: {e}", self.dir.display());
        }
    }

    /// Lists the directory to restart the shared estimate from what it
    /// holds, collecting if that is over the bound.
    fn recount(&self) -> std::io::Result<()> {
        let files = self.files()?;
        let bytes: u64 = files.iter().map(|f| f.size).sum();
        if bytes > self.budget {
            self.collect(files)?;
        } else {
            self.restart_usage(bytes);
        }
        Ok(())
    }

    fn restart_usage(&self, bytes: u64) {
        if let Err(e) = self.usage.restart(bytes) {
            tracing::warn!("disk cache: {e}");
        }
    }

    /// Every entry and source file with its size and last use.
    fn files(&self) -> std::io::Result<Vec<CacheFile>> {
        let mut out = Vec::new();
        for dir in std::fs::read_dir(&self.dir)? {
            let dir = dir?.path();
            if !dir.is_dir() {
                continue;
            }
            // A folder removed by hand since the listing holds nothing.
            let Ok(listing) = std::fs::read_dir(&dir) else {
                continue;
            };
            for f in listing.flatten() {
                let path = f.path();
                let is_entry = path.extension().is_some_and(|e| e == "gve");
                let is_source = path.extension().is_some_and(|e| e == "gvs");
                if !(is_entry || is_source || geode_io::abandoned_temporary(&f, ABANDONED_AFTER)) {
                    continue;
                }
                // A file removed since the listing is simply not counted.
                if let Ok(m) = f.metadata() {
                    out.push(CacheFile {
                        last_used: m.modified().unwrap_or(SystemTime::UNIX_EPOCH),
                        size: m.len(),
                        path,
                        is_entry,
                    });
                }
            }
        }
        Ok(out)
    }

    pub fn stats(&self) -> std::io::Result<DiskStats> {
        let files = self.files()?;
        Ok(DiskStats {
            entries: files.iter().filter(|f| f.is_entry).count() as u64,
            sources: files.iter().filter(|f| !f.is_entry).count() as u64,
            bytes: files.iter().map(|f| f.size).sum(),
            budget: self.budget,
        })
    }

    /// When the directory is over its bound, removes the least recently
    /// used files down to the low-water mark; restarts the shared estimate
    /// from what is left either way.
    pub fn gc(&self) -> std::io::Result<GcReport> {
        self.collect(self.files()?)
    }

    fn collect(&self, mut files: Vec<CacheFile>) -> std::io::Result<GcReport> {
        let mut total: u64 = files.iter().map(|f| f.size).sum();
        let mut report = GcReport::default();
        if total > self.budget {
            let low_water = self.low_water();
            files.sort_by(|a, b| {
                a.last_used
                    .cmp(&b.last_used)
                    .then_with(|| a.path.cmp(&b.path))
            });
            for f in files {
                if total <= low_water {
                    break;
                }
                match std::fs::remove_file(&f.path) {
                    Ok(()) => {
                        total -= f.size;
                        report.removed += 1;
                        report.freed += f.size;
                    }
                    // Another process collecting at once removed it first.
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => total -= f.size,
                    Err(_) => {}
                }
            }
        }
        report.bytes_after = total;
        self.restart_usage(total);
        Ok(report)
    }
}

/// Marks a file as just used (its modification time), for `gc`'s order;
/// whether the file is there.
fn touch(path: &Path) -> bool {
    match std::fs::File::options().append(true).open(path) {
        Ok(f) => {
            let _ = f.set_modified(SystemTime::now());
            true
        }
        Err(_) => false,
    }
}

impl Store for DiskCache {
    fn load(&self, key: u128) -> Option<Cached> {
        self.read_entry(&self.path(key, "gve"), Asked::CookResult(key))
    }

    fn save(&self, key: u128, cached: &Cached) {
        // A value bigger than the whole cache would only evict everything else.
        if cached.bytes as u64 > self.budget {
            return;
        }
        let path = self.path(key, "gve");
        if touch(&path) {
            return;
        }
        let Some((bytes, sources)) = entry::encode(key, cached) else {
            return;
        };
        // Sources first: an entry never appears before what it places.
        let mut written = self.write_sources(sources);
        if self.write(&path, &bytes) {
            written += bytes.len() as u64;
        }
        self.account(written as i64);
    }
}
