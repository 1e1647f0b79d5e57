//! geode's disk cache: cook results content-addressed on a directory that many processes and machines share, behind the memory cache.
//!
//! An entry is named by its cook key (`ab/<key>.gve`, 256 folders by the
//! key's first byte); a packed instance's source by its content hash
//! (`ab/<hash>.gvs`), written once and shared. Writes go to a temporary
//! file, are synced and renamed into place (`geode_io::write_atomic_shared`),
//! so a reader sees a whole entry or none, and two writers of one key both
//! leave a valid entry (the same bytes: keys name content). Every entry ends
//! with an xxh3-128 checksum; a bad or unreadable entry is a miss, removed,
//! never an error. Reads refresh an entry's modification time; `gc` removes
//! the least recently used entries until the directory fits its bound.

mod entry;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, Weak};
use std::time::SystemTime;

use geode_geo::Geometry;
use geode_graph::{Cached, Store};

/// The default bound of a disk cache (`GEODE_CACHE_DISK_MB`).
pub const DEFAULT_DISK_MB: u64 = 10 * 1024;

/// A disk cache on one directory, bounded by bytes.
pub struct DiskCache {
    dir: PathBuf,
    budget: u64,
    /// Saves since the last bound check (checked every `GC_EVERY`).
    saves: AtomicU64,
    /// Sources already read, shared by every entry that places them.
    sources: Mutex<HashMap<u128, Weak<Geometry>>>,
}

/// How often (in saves) the bound is checked while cooking.
const GC_EVERY: u64 = 64;

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

impl DiskCache {
    /// A cache on `dir` (created if missing) bounded by `budget` bytes.
    pub fn open(dir: impl Into<PathBuf>, budget: u64) -> std::io::Result<DiskCache> {
        let dir = dir.into();
        std::fs::create_dir_all(&dir)?;
        Ok(DiskCache {
            dir,
            budget,
            saves: AtomicU64::new(0),
            sources: Mutex::new(HashMap::new()),
        })
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
            mb.saturating_mul(1 << 20),
        ))
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn path(&self, name: u128, ext: &str) -> PathBuf {
        let hex = format!("{name:032x}");
        self.dir.join(&hex[..2]).join(format!("{hex}.{ext}"))
    }

    /// The verified body of an entry file; a damaged one is removed.
    fn read(&self, path: &Path) -> Option<Vec<u8>> {
        let bytes = std::fs::read(path).ok()?;
        if entry::verified(&bytes).is_none() {
            tracing::warn!(path = %path.display(), "disk cache: bad checksum, entry removed");
            let _ = std::fs::remove_file(path);
            return None;
        }
        touch(path);
        let n = bytes.len() - 16;
        let mut bytes = bytes;
        bytes.truncate(n);
        Some(bytes)
    }

    fn source(&self, hash: u128) -> Option<Arc<Geometry>> {
        if let Some(g) = self.lock_sources().get(&hash).and_then(Weak::upgrade) {
            return Some(g);
        }
        let path = self.path(hash, "gvs");
        let body = self.read(&path)?;
        let cached = entry::decode(&body, true, &|h| self.source(h)).ok()?;
        let geode_op::Value::Geometry(g) = cached.value else {
            return None;
        };
        if g.content_hash() != hash {
            let _ = std::fs::remove_file(&path);
            return None;
        }
        self.lock_sources().insert(hash, Arc::downgrade(&g));
        Some(g)
    }

    fn lock_sources(&self) -> std::sync::MutexGuard<'_, HashMap<u128, Weak<Geometry>>> {
        self.sources.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Writes `bytes` under `path` (callers skip entries already there).
    fn write(&self, path: &Path, bytes: &[u8]) {
        if let Some(parent) = path.parent() {
            let _ = std::fs::create_dir_all(parent);
        }
        let r = geode_io::write_atomic_shared(path, |w| {
            w.write_all(bytes)
                .map_err(|e| geode_io::IoError::os(path, e))
        });
        if let Err(e) = r {
            tracing::warn!("disk cache: {e}");
        }
    }

    /// Writes packed sources (and theirs) not yet on disk.
    fn write_sources(&self, mut pending: Vec<Arc<Geometry>>) {
        let mut done = std::collections::HashSet::new();
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
                self.write(&path, &bytes);
            }
        }
    }

    /// Every entry and source file with its size and last use.
    fn files(&self) -> std::io::Result<Vec<(SystemTime, u64, PathBuf, bool)>> {
        let mut out = Vec::new();
        for dir in std::fs::read_dir(&self.dir)? {
            let dir = dir?.path();
            if !dir.is_dir() {
                continue;
            }
            for f in std::fs::read_dir(&dir)?.flatten() {
                let path = f.path();
                let is_entry = path.extension().is_some_and(|e| e == "gve");
                let is_source = path.extension().is_some_and(|e| e == "gvs");
                if !(is_entry || is_source) {
                    continue;
                }
                if let Ok(m) = f.metadata() {
                    let used = m.modified().unwrap_or(SystemTime::UNIX_EPOCH);
                    out.push((used, m.len(), path, is_entry));
                }
            }
        }
        Ok(out)
    }

    pub fn stats(&self) -> std::io::Result<DiskStats> {
        let files = self.files()?;
        Ok(DiskStats {
            entries: files.iter().filter(|f| f.3).count() as u64,
            sources: files.iter().filter(|f| !f.3).count() as u64,
            bytes: files.iter().map(|f| f.1).sum(),
            budget: self.budget,
        })
    }

    /// Removes the least recently used files until the directory holds at
    /// most its bound.
    pub fn gc(&self) -> std::io::Result<GcReport> {
        let mut files = self.files()?;
        let mut total: u64 = files.iter().map(|f| f.1).sum();
        let mut report = GcReport::default();
        files.sort_by(|a, b| a.0.cmp(&b.0).then_with(|| a.2.cmp(&b.2)));
        for (_, size, path, _) in files {
            if total <= self.budget {
                break;
            }
            if std::fs::remove_file(&path).is_ok() {
                total -= size;
                report.removed += 1;
                report.freed += size;
            }
        }
        report.bytes_after = total;
        Ok(report)
    }
}

/// Marks a file as just used (its modification time), for `gc`'s order.
fn touch(path: &Path) {
    if let Ok(f) = std::fs::File::options().append(true).open(path) {
        let _ = f.set_modified(SystemTime::now());
    }
}

impl Store for DiskCache {
    fn load(&self, key: u128) -> Option<Cached> {
        let path = self.path(key, "gve");
        let body = self.read(&path)?;
        match entry::decode(&body, false, &|h| self.source(h)) {
            Ok(c) => Some(c),
            Err(e) => {
                // A missing source is not damage: the entry may serve again once it is back.
                if !matches!(e, geode_geo::codec::DecodeError::MissingSource(_)) {
                    tracing::warn!(path = %path.display(), "disk cache: {e}, entry removed");
                    let _ = std::fs::remove_file(&path);
                }
                None
            }
        }
    }

    fn save(&self, key: u128, cached: &Cached) {
        // A value bigger than the whole cache would only evict everything else.
        if cached.bytes as u64 > self.budget {
            return;
        }
        let path = self.path(key, "gve");
        if path.exists() {
            touch(&path);
            return;
        }
        let Some((bytes, sources)) = entry::encode(cached) else {
            return;
        };
        // Sources first: an entry never appears before what it places.
        self.write_sources(sources);
        self.write(&path, &bytes);
        if self.saves.fetch_add(1, Ordering::Relaxed) % GC_EVERY == GC_EVERY - 1 {
            if let Err(e) = self.gc() {
                tracing::warn!("disk cache: collecting {}: {e}", self.dir.display());
            }
        }
    }
}
