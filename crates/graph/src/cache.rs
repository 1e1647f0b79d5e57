//! The process-wide cook cache: values by 128-bit key, bounded by bytes, least recently used evicted first.

use std::sync::{Arc, Mutex, OnceLock};

use geode_op::Value;
use lru::LruCache;

/// A cached result: the value, its size and its content identity. The
/// identity is computed when first asked for (a cook key reading the value,
/// the store saving it) and kept, so a hit never touches geometry data and
/// an output nothing reads is never hashed.
#[derive(Clone, Debug)]
pub struct Cached {
    pub value: Value,
    pub(crate) identity: OnceLock<u128>,
    pub bytes: usize,
    /// The cook's warnings, replayed on every hit.
    pub warnings: Arc<[String]>,
    /// Read from the second level (another process's cook, on disk).
    pub from_store: bool,
}

impl Cached {
    /// A value just cooked, with its size and the cook's warnings.
    pub fn new(value: Value, warnings: Arc<[String]>) -> Cached {
        Cached {
            identity: OnceLock::new(),
            bytes: value.bytes(),
            value,
            warnings,
            from_store: false,
        }
    }

    /// A value read back from a store with the identity it was saved with
    /// (its content is not hashed again).
    pub fn stored(value: Value, identity: u128, bytes: usize, warnings: Arc<[String]>) -> Cached {
        Cached {
            value,
            identity: OnceLock::from(identity),
            bytes,
            warnings,
            from_store: true,
        }
    }

    /// The value's content identity ([`Value::identity`]), computed once.
    pub fn identity(&self) -> u128 {
        *self.identity.get_or_init(|| self.value.identity())
    }
}

/// A second level behind the memory cache (the disk cache a farm shares):
/// asked on a memory miss, written through on every insert. A store that
/// cannot serve or keep an entry says nothing: the cook simply runs.
pub trait Store: Send + Sync {
    fn load(&self, key: u128) -> Option<Cached>;
    fn save(&self, key: u128, entry: &Cached);
}

/// Counters, for tests, traces and `geode cook --stats`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheStats {
    pub hits: u64,
    pub misses: u64,
    pub evictions: u64,
    pub entries: usize,
    pub bytes: usize,
    pub budget: usize,
    /// Memory misses the second level served.
    pub store_hits: u64,
}

struct Inner {
    map: LruCache<u128, Cached>,
    bytes: usize,
    stats: CacheStats,
}

/// A byte-bounded LRU map from cook keys to results.
pub struct Cache {
    budget: usize,
    enabled: bool,
    inner: Mutex<Inner>,
    store: Option<Arc<dyn Store>>,
}

impl Cache {
    /// A cache holding at most `budget` bytes of values.
    pub fn new(budget: usize) -> Cache {
        Cache {
            budget,
            enabled: budget > 0,
            inner: Mutex::new(Inner {
                map: LruCache::unbounded(),
                bytes: 0,
                stats: CacheStats {
                    budget,
                    ..Default::default()
                },
            }),
            store: None,
        }
    }

    /// This cache with a second level behind it.
    pub fn with_store(mut self, store: Arc<dyn Store>) -> Cache {
        self.store = Some(store);
        self
    }

    /// A cache that stores nothing.
    pub fn disabled() -> Cache {
        Cache::new(0)
    }

    /// Configured from the environment: `GEODE_CACHE=off` disables it,
    /// `GEODE_CACHE_MB` sizes it in megabytes of 10^6 bytes, as messages
    /// print sizes (default 2048).
    pub fn from_env() -> Cache {
        if std::env::var("GEODE_CACHE").is_ok_and(|v| v.eq_ignore_ascii_case("off") || v == "0") {
            return Cache::disabled();
        }
        let mb = std::env::var("GEODE_CACHE_MB")
            .ok()
            .and_then(|v| v.trim().parse::<usize>().ok())
            .unwrap_or(2048);
        Cache::new(mb.saturating_mul(1_000_000))
    }

    /// The process-wide cache, configured from the environment on first use.
    pub fn global() -> &'static Cache {
        static GLOBAL: OnceLock<Cache> = OnceLock::new();
        GLOBAL.get_or_init(Cache::from_env)
    }

    pub fn is_enabled(&self) -> bool {
        self.enabled
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Inner> {
        // A panic while holding the lock leaves consistent data: keep going.
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The value under `key`, marking it most recently used.
    pub fn get(&self, key: u128) -> Option<Cached> {
        if !self.enabled {
            return None;
        }
        let mut inner = self.lock();
        let hit = inner.map.get(&key).cloned();
        if hit.is_some() {
            inner.stats.hits += 1;
            return hit;
        }
        drop(inner);
        // The store is read outside the lock: other cooks go on meanwhile.
        let stored = self.store.as_ref().and_then(|s| s.load(key));
        let mut inner = self.lock();
        match stored {
            Some(entry) => {
                inner.stats.store_hits += 1;
                drop(inner);
                self.keep(key, entry.clone());
                Some(Cached {
                    from_store: true,
                    ..entry
                })
            }
            None => {
                inner.stats.misses += 1;
                None
            }
        }
    }

    /// Stores a result, evicting least recently used entries until the byte
    /// budget holds. A value larger than the whole budget is not stored.
    pub fn insert(&self, key: u128, entry: Cached) {
        if !self.enabled {
            return;
        }
        if let Some(store) = &self.store {
            store.save(key, &entry);
        }
        self.keep(key, entry);
    }

    /// Holds an entry in memory (no write to the store).
    fn keep(&self, key: u128, entry: Cached) {
        if entry.bytes > self.budget {
            return;
        }
        let mut inner = self.lock();
        inner.bytes += entry.bytes;
        if let Some(old) = inner.map.put(key, entry) {
            inner.bytes -= old.bytes;
        }
        while inner.bytes > self.budget {
            match inner.map.pop_lru() {
                Some((_, old)) => {
                    inner.bytes -= old.bytes;
                    inner.stats.evictions += 1;
                }
                None => break,
            }
        }
    }

    pub fn contains(&self, key: u128) -> bool {
        self.enabled && self.lock().map.contains(&key)
    }

    pub fn clear(&self) {
        let mut inner = self.lock();
        inner.map.clear();
        inner.bytes = 0;
    }

    pub fn stats(&self) -> CacheStats {
        let inner = self.lock();
        CacheStats {
            entries: inner.map.len(),
            bytes: inner.bytes,
            ..inner.stats
        }
    }
}

impl std::fmt::Debug for Cache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cache({:?})", self.stats())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::Vec3;
    use geode_geo::Geometry;

    fn value(n: usize) -> Cached {
        let mut g = Geometry::new();
        g.add_points(&vec![Vec3::ZERO; n]);
        Cached::new(Value::geometry(g), Arc::from([]))
    }

    #[test]
    fn eviction_respects_the_byte_budget_lru_first() {
        let one = value(1000); // 12 kB of positions
        let cache = Cache::new(one.bytes * 3);
        for k in 0..3u128 {
            cache.insert(k, value(1000));
        }
        assert_eq!(cache.stats().entries, 3);
        assert!(
            cache.get(0).is_some(),
            "touch 0: 1 becomes the least recent"
        );
        cache.insert(3, value(1000));
        assert!(cache.stats().bytes <= cache.stats().budget);
        assert!(!cache.contains(1), "least recently used went first");
        assert!(cache.contains(0) && cache.contains(2) && cache.contains(3));
        assert_eq!(cache.stats().evictions, 1);
        cache.insert(9, value(10_000));
        assert!(
            !cache.contains(9),
            "larger than the whole budget: not stored"
        );
        assert_eq!(cache.stats().entries, 3);
    }

    /// A second level in memory, as the disk cache is on disk.
    #[derive(Default)]
    struct Shelf(Mutex<std::collections::HashMap<u128, Cached>>);

    impl Store for Shelf {
        fn load(&self, key: u128) -> Option<Cached> {
            self.0.lock().unwrap().get(&key).cloned()
        }
        fn save(&self, key: u128, entry: &Cached) {
            self.0.lock().unwrap().insert(key, entry.clone());
        }
    }

    #[test]
    fn a_memory_miss_asks_the_store_and_inserts_write_through() {
        let shelf = Arc::new(Shelf::default());
        let first = Cache::new(1 << 20).with_store(shelf.clone());
        first.insert(5, value(10));
        assert!(shelf.load(5).is_some(), "written through");
        let first_hit = first.get(5).unwrap();
        assert!(!first_hit.from_store, "served from memory");
        // Another process: an empty memory cache over the same store.
        let second = Cache::new(1 << 20).with_store(shelf);
        let hit = second.get(5).expect("the store serves the miss");
        assert!(hit.from_store);
        assert_eq!(hit.identity(), first_hit.identity());
        assert_eq!(second.stats().store_hits, 1);
        assert!(!second.get(5).unwrap().from_store, "kept in memory after");
        assert!(second.get(6).is_none());
        assert_eq!(second.stats().misses, 1);
    }

    #[test]
    fn disabled_cache_stores_nothing() {
        let c = Cache::disabled();
        c.insert(1, value(1));
        assert!(c.get(1).is_none());
    }
}
