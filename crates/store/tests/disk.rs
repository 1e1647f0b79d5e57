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
        assert_eq!(back.identity, value.identity());
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
        .filter(|p| !p.ends_with(".gve"))
        .collect();
    assert!(stray.is_empty(), "temporary files left: {stray:?}");
}

fn walk(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for d in std::fs::read_dir(dir).unwrap().flatten() {
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
