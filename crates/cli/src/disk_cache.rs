//! The cook cache of `geode cook` and `geode serve` (memory, with the disk cache behind it when `GEODE_CACHE_DIR` names one) and `geode cache stats|gc`.
//!
//! The bound (`GEODE_CACHE_DISK_MB`) is the whole directory's, whatever
//! number of processes share it: every save of every process (each task of
//! `geode farm`) adds to the directory's shared size estimate and collects
//! when it passes the bound (see `geode_store`).

use std::path::PathBuf;
use std::sync::OnceLock;

use anyhow::{anyhow, Context, Result};
use geode_graph::Cache;
use geode_store::DiskCache;

/// A cook cache: `Cache::from_env()`, with the disk cache of
/// `GEODE_CACHE_DIR` (bounded by `GEODE_CACHE_DISK_MB`) as its second level.
pub fn new_cache() -> Result<Cache> {
    DiskCache::cook_cache_from_env()
        .context("GEODE_CACHE_DIR: the disk cache's folder cannot be created")
}

/// The process's cook cache for `geode cook` (see [`new_cache`]).
pub fn cook_cache() -> Result<&'static Cache> {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    if let Some(c) = CACHE.get() {
        return Ok(c);
    }
    let cache = new_cache()?;
    Ok(CACHE.get_or_init(|| cache))
}

/// The disk cache `--dir` or `GEODE_CACHE_DIR` names, bounded by
/// `--max-mb` or `GEODE_CACHE_DISK_MB`.
fn open(dir: Option<PathBuf>, max_mb: Option<u64>) -> Result<DiskCache> {
    let dir = dir
        .or_else(|| {
            std::env::var_os("GEODE_CACHE_DIR")
                .filter(|d| !d.is_empty())
                .map(PathBuf::from)
        })
        .ok_or_else(|| {
            crate::exit::tagged(
                crate::exit::Exit::Usage,
                anyhow!("no disk cache: pass --dir or set GEODE_CACHE_DIR"),
            )
        })?;
    let mb = max_mb
        .or_else(|| {
            std::env::var("GEODE_CACHE_DISK_MB")
                .ok()
                .and_then(|v| v.trim().parse().ok())
        })
        .unwrap_or(geode_store::DEFAULT_DISK_MB);
    DiskCache::open(&dir, mb.saturating_mul(geode_op::MB))
        .with_context(|| format!("{}: cannot open the disk cache", dir.display()))
}

pub fn stats(dir: Option<PathBuf>, max_mb: Option<u64>) -> Result<()> {
    let cache = open(dir, max_mb)?;
    let s = cache
        .stats()
        .with_context(|| format!("{}: cannot list the disk cache", cache.dir().display()))?;
    say!("disk cache:  {}", cache.dir().display());
    say!("entries:     {}", s.entries);
    say!(
        "sources:     {} (packed sources, shared by entries)",
        s.sources
    );
    say!(
        "size:        {:.1} MB of {:.1} MB",
        s.bytes as f64 / 1e6,
        s.budget as f64 / 1e6
    );
    Ok(())
}

pub fn gc(dir: Option<PathBuf>, max_mb: Option<u64>) -> Result<()> {
    let cache = open(dir, max_mb)?;
    let r = cache
        .gc()
        .with_context(|| format!("{}: cannot collect the disk cache", cache.dir().display()))?;
    say!(
        "removed {} files ({:.1} MB), least recently used first, down to {:.1} MB when over {:.1} MB; {:.1} MB left",
        r.removed,
        r.freed as f64 / 1e6,
        cache.low_water() as f64 / 1e6,
        cache.budget() as f64 / 1e6,
        r.bytes_after as f64 / 1e6
    );
    Ok(())
}
