//! The disk cache's write and read speed for an 8M-point geometry beside the raw disk's for the same bytes, and what the shared size accounting adds to each save.
//! Run: cargo bench -p geode-store --bench store
//! (the accounting alone: cargo bench -p geode-store --bench store -- accounting)

use std::io::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

use divan::counter::BytesCount;
use divan::Bencher;
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_graph::{Cached, Store};
use geode_op::Value;
use geode_store::{DiskCache, Recount, UsageLog};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

const POINTS: usize = 8_000_000;

/// 8M points with a colour and a scale: 8M x 28 bytes, 224 MB.
fn points() -> &'static Cached {
    static C: OnceLock<Cached> = OnceLock::new();
    C.get_or_init(|| {
        let mut g = Geometry::new();
        let p: Vec<Vec3> = (0..POINTS)
            .map(|i| Vec3::new(i as f32, (i % 977) as f32, (i % 13) as f32))
            .collect();
        g.set_positions(p);
        let cd = (0..POINTS)
            .map(|i| Vec3::splat((i % 255) as f32 / 255.0))
            .collect();
        g.set_attrib(
            AttribClass::Point,
            "Cd",
            Attribute::from_data(AttribData::Vec3(cd), TypeInfo::Color),
        )
        .unwrap();
        let s = (0..POINTS).map(|i| (i % 7) as f32).collect();
        g.set_attrib(
            AttribClass::Point,
            "pscale",
            Attribute::from_data(AttribData::Float(s), TypeInfo::None),
        )
        .unwrap();
        Cached::new(Value::Geometry(Arc::new(g)), Arc::from([]))
    })
}

fn bytes() -> usize {
    POINTS * 28
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn save_8m_points(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    let key = AtomicU64::new(1);
    let c = points();
    bencher
        .counter(BytesCount::new(bytes()))
        .bench(|| cache.save(key.fetch_add(1, Ordering::Relaxed) as u128, c));
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn load_8m_points(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    cache.save(1, points());
    bencher
        .counter(BytesCount::new(bytes()))
        .bench(|| cache.load(1).expect("stored"));
}

/// The disk alone: the same number of bytes written, synced and renamed.
#[divan::bench(sample_count = 5, sample_size = 1)]
fn raw_write_same_bytes(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let data = vec![7u8; bytes()];
    let n = AtomicU64::new(0);
    bencher.counter(BytesCount::new(bytes())).bench(|| {
        let i = n.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.path().join(format!("t{i}"));
        let mut f = std::fs::File::create(&tmp).unwrap();
        f.write_all(&data).unwrap();
        f.sync_all().unwrap();
        std::fs::rename(&tmp, dir.path().join(format!("f{i}"))).unwrap();
    });
}

#[divan::bench(sample_count = 5, sample_size = 1)]
fn raw_read_same_bytes(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f");
    std::fs::write(&path, vec![7u8; bytes()]).unwrap();
    bencher
        .counter(BytesCount::new(bytes()))
        .bench(|| std::fs::read(&path).unwrap());
}

/// What the bound's accounting adds to one save: one record appended to
/// the shared usage log and the records since the last look read back.
#[divan::bench]
fn accounting_per_save(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let never = Recount {
        records: u64::MAX,
        age: std::time::Duration::from_secs(1 << 30),
    };
    let log = UsageLog::new(dir.path(), never);
    log.restart(0).unwrap();
    bencher.bench(|| log.record(35_000));
}

/// A whole save of a small value (a 35 KB torus), accounting included,
/// for scale: the write, its sync and rename dominate.
#[divan::bench(sample_count = 20, sample_size = 5)]
fn accounting_whole_small_save(bencher: Bencher) {
    let dir = tempfile::tempdir().unwrap();
    let cache = DiskCache::open(dir.path(), u64::MAX).unwrap();
    let torus = Cached::new(
        Value::geometry(geode_geo::primitives::torus(1.0, 0.2, 40, 24)),
        Arc::from([]),
    );
    let key = AtomicU64::new(1);
    bencher.bench(|| cache.save(key.fetch_add(1, Ordering::Relaxed) as u128, &torus));
}
