//! The disk cache: entries read back by other processes' caches, damage is a miss, concurrent writers never corrupt, collection keeps the bound.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, SystemTime};

use geode_geo::glam::{Mat4, Vec3};
use geode_geo::{primitives, Geometry};
use geode_graph::{Cached, Store};
use geode_op::{Bundle, Value};
use geode_store::DiskCache;

fn cached(value: Value, warnings: &[&str]) -> Cached {
    Cached::new(
        value,
        warnings
            .iter()
            .map(|w| w.to_string())
            .collect::<Vec<_>>()
            .into(),
    )
}

/// Packed copies of two sources, one of which places the other in turn.
fn instanced() -> Geometry {
    let ball = Arc::new(primitives::uv_sphere(0.3, 8, 6));
    let mut pair = Geometry::new();
    let p = pair.add_point(Vec3::X);
    pair.add_packed(p, Arc::clone(&ball), Mat4::IDENTITY)
        .unwrap();
    let pair = Arc::new(pair);
    let mut g = Geometry::new();
    for i in 0..10 {
        let p = g.add_point(Vec3::new(i as f32, 0.0, 0.0));
        let src = if i % 2 == 0 { &ball } else { &pair };
        g.add_packed(p, Arc::clone(src), Mat4::from_rotation_y(i as f32))
            .unwrap();
    }
    g
}

fn files(dir: &Path, ext: &str) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for d in std::fs::read_dir(dir).unwrap().flatten() {
        if d.path().is_dir() {
            for f in std::fs::read_dir(d.path()).unwrap().flatten() {
                if f.path().extension().is_some_and(|e| e == ext) {
                    out.push(f.path());
                }
            }
        }
    }
    out
}

#[test]
fn another_cache_on_the_directory_reads_every_value_back() {
    let dir = tempfile::tempdir().unwrap();
    let torus = Value::geometry(primitives::torus(1.0, 0.3, 12, 8));
    let scene = Value::geometry(instanced());
    let mut entries = BTreeMap::new();
    entries.insert("a".to_owned(), Arc::new(primitives::cube(1.0)));
    entries.insert("b".to_owned(), Arc::new(instanced()));
    let bundle = Value::Bundle(Arc::new(Bundle { entries }));
    {
        let writer = DiskCache::open(dir.path(), u64::MAX).unwrap();
        writer.save(1, &cached(torus.clone(), &["a warning"]));
        writer.save(2, &cached(scene.clone(), &[]));
        writer.save(3, &cached(bundle.clone(), &[]));
    }
    // Sources are written once however many entries place them.
    assert_eq!(files(dir.path(), "gvs").len(), 2);
    let reader = DiskCache::open(dir.path(), u64::MAX).unwrap();
    for (key, value) in [(1, &torus), (2, &scene), (3, &bundle)] {
        let back = reader
            .load(key)
            .unwrap_or_else(|| panic!("entry {key} missing"));
        assert!(back.from_store);
        assert_eq!(back.identity(), value.identity());
        assert_eq!(back.value.identity(), value.identity(), "entry {key}");
        assert_eq!(back.bytes, value.bytes());
    }
    assert_eq!(
        &*reader.load(1).unwrap().warnings,
        &["a warning".to_owned()]
    );
    assert!(reader.load(4).is_none());
    // Instances of one source share it after reading, as they did before.
    let back = reader.load(2).unwrap();
    let g = back.value.as_geometry().unwrap();
    let (a, b) = (
        &g.packed_instances()[0].source,
        &g.packed_instances()[2].source,
    );
    assert!(Arc::ptr_eq(a, b));
    let stats = reader.stats().unwrap();
    assert_eq!((stats.entries, stats.sources), (3, 2));
}

#[test]
fn a_damaged_entry_is_a_miss_and_is_removed() {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    let v = Value::geometry(primitives::cube(1.0));
    cache.save(7, &cached(v.clone(), &[]));
    let path = files(dir.path(), "gve").pop().unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x10;
    std::fs::write(&path, &bytes).unwrap();
    assert!(cache.load(7).is_none(), "a flipped byte must be a miss");
    assert!(!path.exists(), "the damaged entry is removed");
    // Truncated, and empty: misses too.
    cache.save(7, &cached(v.clone(), &[]));
    let good = std::fs::read(&path).unwrap();
    std::fs::write(&path, &good[..good.len() - 3]).unwrap();
    assert!(cache.load(7).is_none());
    std::fs::write(
        dir.path()
            .join(path.parent().unwrap())
            .join(path.file_name().unwrap()),
        b"",
    )
    .unwrap();
    assert!(cache.load(7).is_none());
    cache.save(7, &cached(v, &[]));
    assert!(cache.load(7).is_some(), "written again after the damage");
}

#[test]
fn fields_are_stored_and_payloads_are_not() {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    let points: Vec<[f64; 3]> = (0..30)
        .map(|i| [i as f64 * 0.1, 0.0, (i as f64).sin()])
        .collect();
    let sweep = geode_frep::shapes::sphere_sweep(&points, &[0.1; 30]).unwrap();
    let field = Value::Field(geode_frep::shapes::blend_union(
        &sweep,
        &geode_frep::shapes::sphere([0.0; 3], 1.0),
        [0.3, 1.0, 1.0],
    ));
    cache.save(1, &cached(field.clone(), &[]));
    let mut g = primitives::cube(1.0);
    g.set_payload("h", geode_geo::Payload::new(1u8, 9, 1));
    cache.save(2, &cached(Value::geometry(g), &[]));
    assert_eq!(cache.stats().unwrap().entries, 1);
    let back = DiskCache::open(dir.path(), u64::MAX)
        .unwrap()
        .load(1)
        .expect("the field is stored");
    assert_eq!(back.value.identity(), field.identity());
    assert!(cache.load(2).is_none(), "a payload has no byte form");
}

/// Four caches (as four processes would) write the same entries at once
/// while four more read them: every read is whole or a miss, and every
/// entry reads back at the end.
#[test]
fn concurrent_writers_never_corrupt_an_entry() {
    let dir = tempfile::tempdir().unwrap();
    let values: Vec<Value> = (0..16)
        .map(|i| Value::geometry(primitives::torus(1.0, 0.2, 8 + i, 6)))
        .collect();
    std::thread::scope(|s| {
        for t in 0..8 {
            let (dir, values) = (dir.path(), &values);
            s.spawn(move || {
                let cache = DiskCache::open(dir, u64::MAX).unwrap();
                for round in 0..3 {
                    for (k, v) in values.iter().enumerate() {
                        let key = k as u128 + 100;
                        if t % 2 == 0 {
                            cache.save(key, &cached(v.clone(), &[]));
                        } else if let Some(c) = cache.load(key) {
                            assert_eq!(c.value.identity(), v.identity(), "round {round} key {key}");
                        }
                    }
                }
            });
        }
    });
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    for (k, v) in values.iter().enumerate() {
        assert_eq!(
            cache.load(k as u128 + 100).unwrap().value.identity(),
            v.identity()
        );
    }
    let stray: Vec<_> = walk(dir.path())
        .into_iter()
        .filter(|p| !p.ends_with(".gve") && !p.ends_with(geode_store::USAGE_LOG))
        .collect();
    assert!(stray.is_empty(), "temporary files left: {stray:?}");
}

/// Every file in the cache directory and its folders.
fn walk(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for d in std::fs::read_dir(dir).unwrap().flatten() {
        if !d.path().is_dir() {
            out.push(d.path().display().to_string());
            continue;
        }
        for f in std::fs::read_dir(d.path()).unwrap().flatten() {
            out.push(f.path().display().to_string());
        }
    }
    out
}

#[test]
fn collection_keeps_the_bound_and_the_recently_used() {
    let dir = tempfile::tempdir().unwrap();
    let v = |i: u32| Value::geometry(primitives::torus(1.0, 0.2, 16 + i, 8));
    let unbounded = DiskCache::open(dir.path(), u64::MAX).unwrap();
    for i in 0..10 {
        unbounded.save(i as u128, &cached(v(i), &[]));
    }
    // Ages by hand: entry i last used i hours ago, then entry 9 read now.
    for (i, path) in (0..10).map(|i| (i, entry_path(dir.path(), i))) {
        let f = std::fs::File::options().append(true).open(&path).unwrap();
        f.set_modified(SystemTime::now() - Duration::from_secs(3600 * (i as u64 + 1)))
            .unwrap();
    }
    assert!(unbounded.load(9).is_some());
    let total = unbounded.stats().unwrap().bytes;
    let budget = total / 2;
    let bounded = DiskCache::open(dir.path(), budget).unwrap();
    let report = bounded.gc().unwrap();
    let after = bounded.stats().unwrap();
    assert!(after.bytes <= budget, "{after:?} over {budget}");
    assert_eq!(report.bytes_after, after.bytes);
    assert!(report.removed >= 4);
    // The oldest went first; the one just read and the newest stay.
    assert!(bounded.load(9).is_some(), "read a moment ago: kept");
    assert!(bounded.load(0).is_some(), "the most recent save: kept");
    assert!(
        bounded.load(8).is_none(),
        "the least recently used: removed"
    );
}

fn entry_path(dir: &Path, key: u128) -> std::path::PathBuf {
    let hex = format!("{key:032x}");
    dir.join(&hex[..2]).join(format!("{hex}.gve"))
}

/// The bytes of every file under `dir`, the usage log and temporaries
/// included: what the bound promises to keep.
fn bytes_on_disk(dir: &Path) -> u64 {
    let mut total = 0;
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let m = e.metadata().unwrap();
        total += if m.is_dir() {
            bytes_on_disk(&e.path())
        } else {
            m.len()
        };
    }
    total
}

/// A torus of about 35 KB, of another radius for every `i`.
fn torus(i: u32) -> Value {
    Value::geometry(primitives::torus(1.0 + i as f32 / 1024.0, 0.2, 40, 24))
}

#[test]
fn an_entry_under_another_keys_name_is_a_miss_and_is_removed() {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    let (twelve, thirteen) = (torus(12), torus(13));
    cache.save(12, &cached(twelve.clone(), &[]));
    cache.save(13, &cached(thirteen.clone(), &[]));
    let (p12, p13) = (entry_path(dir.path(), 12), entry_path(dir.path(), 13));
    std::fs::copy(&p13, &p12).unwrap();
    let fresh = DiskCache::open(dir.path(), u64::MAX).unwrap();
    assert!(
        fresh.load(12).is_none(),
        "key 13's valid entry under key 12's name must be a miss"
    );
    assert!(!p12.exists(), "the entry under the wrong name is removed");
    assert_eq!(
        fresh.load(13).unwrap().value.identity(),
        thirteen.identity(),
        "the original stays"
    );
    fresh.save(12, &cached(twelve.clone(), &[]));
    assert_eq!(fresh.load(12).unwrap().value.identity(), twelve.identity());

    // A packed source under a cook key's name: the wrong kind.
    cache.save(20, &cached(Value::geometry(instanced()), &[]));
    let source = files(dir.path(), "gvs").pop().unwrap();
    std::fs::copy(&source, &p12).unwrap();
    assert!(fresh.load(12).is_none(), "a source is not a cook result");
    assert!(!p12.exists(), "the entry of the wrong kind is removed");

    // An entry of the layout before keys (version 1): a miss, removed.
    let v2 = std::fs::read(&p13).unwrap();
    let body = &v2[..v2.len() - 16];
    let mut v1 = Vec::new();
    v1.extend_from_slice(&body[..8]);
    v1.extend_from_slice(&1u32.to_le_bytes());
    v1.push(body[12]);
    v1.extend_from_slice(&body[13 + 16..]);
    v1.extend_from_slice(&xxhash_rust::xxh3::xxh3_128(&v1).to_le_bytes());
    std::fs::write(&p13, &v1).unwrap();
    assert!(
        fresh.load(13).is_none(),
        "an entry without its key is a miss"
    );
    assert!(!p13.exists(), "the old entry is removed");
}

/// 24 short processes (each a fresh cache that saves six values and is
/// gone), then 4 at once while 2 more read: the directory never passes
/// the bound by more than 10%, and readers of collected entries only miss.
#[test]
fn many_short_processes_keep_the_bound() {
    let dir = tempfile::tempdir().unwrap();
    let one = {
        let probe = tempfile::tempdir().unwrap();
        DiskCache::open(probe.path(), u64::MAX)
            .unwrap()
            .save(0, &cached(torus(0), &[]));
        bytes_on_disk(probe.path())
    };
    // Room for about 20 of the 144 values saved.
    let budget = one * 20;
    for process in 0..24u32 {
        let cache = DiskCache::open(dir.path(), budget).unwrap();
        for i in 0..6 {
            let n = process * 6 + i;
            cache.save(n as u128, &cached(torus(n), &[]));
        }
        let on_disk = bytes_on_disk(dir.path());
        assert!(
            on_disk <= budget + budget / 10,
            "after process {process}: {on_disk} bytes on disk, bound {budget}"
        );
    }
    let sequential = bytes_on_disk(dir.path());
    assert!(
        sequential >= budget / 2,
        "collected down to {sequential} of {budget}: far below the low-water mark"
    );

    std::thread::scope(|s| {
        for t in 0..6u32 {
            let dir = dir.path();
            s.spawn(move || {
                for process in 0..4u32 {
                    let cache = DiskCache::open(dir, budget).unwrap();
                    for i in 0..6 {
                        let n = 1000 + (process * 6 + i) * 4 + t % 4;
                        if t < 4 {
                            cache.save(n as u128, &cached(torus(n), &[]));
                        } else if let Some(c) = cache.load(n as u128) {
                            assert_eq!(c.value.identity(), torus(n).identity());
                        }
                    }
                }
            });
        }
    });
    let on_disk = bytes_on_disk(dir.path());
    assert!(
        on_disk <= budget + budget / 10,
        "after 4 concurrent writers: {on_disk} bytes on disk, bound {budget}"
    );
}

/// Files a killed process wrote without accounting them, and a lost usage
/// log: the estimate is counted again, and the bound holds again.
#[test]
fn accounting_lost_by_a_killed_process_is_counted_again() {
    let dir = tempfile::tempdir().unwrap();
    let one = {
        let probe = tempfile::tempdir().unwrap();
        DiskCache::open(probe.path(), u64::MAX)
            .unwrap()
            .save(0, &cached(torus(0), &[]));
        bytes_on_disk(probe.path())
    };
    let budget = one * 10;
    let recount = geode_store::Recount {
        records: 8,
        age: Duration::from_secs(600),
    };
    let cache = DiskCache::open(dir.path(), budget)
        .unwrap()
        .with_recount(recount);
    // Entries a killed process renamed into place but never added to the
    // estimate (copies of one: only their size matters here).
    let killed_wrote = |cache: &DiskCache, keys: std::ops::Range<u128>| {
        cache.save(keys.start, &cached(torus(keys.start as u32), &[]));
        for n in keys.clone().skip(1) {
            let path = entry_path(dir.path(), n);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::copy(entry_path(dir.path(), keys.start), &path).unwrap();
        }
    };
    killed_wrote(&cache, 0..30);
    assert!(bytes_on_disk(dir.path()) > budget * 2);
    // ... and a log it damaged: the next save lists the directory.
    std::fs::write(dir.path().join(geode_store::USAGE_LOG), b"GEODEUSE").unwrap();
    cache.save(100, &cached(torus(100), &[]));
    let on_disk = bytes_on_disk(dir.path());
    assert!(
        on_disk <= budget + budget / 10,
        "a damaged log is recounted at the next save: {on_disk} of {budget}"
    );
    // The log is whole, but the killed process's files are not in it:
    // within `recount.records` saves the directory is listed again.
    killed_wrote(&cache, 200..230);
    assert!(bytes_on_disk(dir.path()) > budget * 2);
    for n in 300..308 {
        cache.save(n, &cached(torus(n as u32), &[]));
    }
    let on_disk = bytes_on_disk(dir.path());
    assert!(
        on_disk <= budget + budget / 10,
        "unaccounted files are counted within 8 saves: {on_disk} of {budget}"
    );
}

/// A save's temporary file left by a process killed mid-save counts against
/// the bound once no save could still be writing it, and is collected;
/// one being written (recent) is left alone.
#[test]
fn temporaries_abandoned_by_a_killed_save_are_collected() {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), 1 << 20).unwrap();
    cache.save(1, &cached(torus(1), &[]));
    let folder = entry_path(dir.path(), 1).parent().unwrap().to_owned();
    let abandoned = folder.join(".geode-tmp-4242-abandoned");
    let writing = folder.join(".geode-tmp-4243-writing");
    for path in [&abandoned, &writing] {
        std::fs::write(path, vec![0u8; 2 << 20]).unwrap();
    }
    let f = std::fs::File::options()
        .append(true)
        .open(&abandoned)
        .unwrap();
    f.set_modified(SystemTime::now() - Duration::from_secs(3600))
        .unwrap();
    let before = cache.stats().unwrap();
    assert!(
        before.bytes > 2 << 20,
        "the abandoned file counts: {before:?}"
    );
    cache.gc().unwrap();
    assert!(!abandoned.exists(), "abandoned an hour ago: collected");
    assert!(writing.exists(), "a save in progress: left alone");
    assert!(
        cache.load(1).is_some(),
        "the entry stays: the bound holds without it"
    );
}
