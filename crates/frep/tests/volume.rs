//! Fields sampled into narrow-band level sets, against the analytic
//! distance: every voxel within the band is found and holds the distance,
//! the inside is filled, the sampled field's values and intervals agree
//! with the volume, and the sampling is the same on any thread count.

use geode_frep::eval::{IntervalEval, PointEval};
use geode_frep::{shapes, Field, Interval, SampleOptions, SamplePlan, Tape, VolumeField};
use geode_geo::volume::{SparseVolume, VolumeClass, LEAF_VOXELS};

const CENTRE: [f64; 3] = [0.1, -0.2, 0.05];
const RADIUS: f64 = 0.5;

fn options(voxel: f64) -> SampleOptions {
    SampleOptions {
        min: [-0.6, -0.8, -0.6],
        max: [0.7, 0.4, 0.7],
        voxel_size: voxel,
        half_width: 3.0,
        memory_budget: 1 << 32,
    }
}

fn sample(f: &Field, o: SampleOptions) -> SparseVolume {
    let plan = SamplePlan::new(f, o, &|| false).unwrap();
    plan.sample(f, "surface", &|| false).unwrap()
}

fn sphere_distance(p: [f64; 3]) -> f64 {
    (0..3)
        .map(|k| (p[k] - CENTRE[k]).powi(2))
        .sum::<f64>()
        .sqrt()
        - RADIUS
}

#[test]
fn a_sampled_sphere_holds_its_distance_on_every_voxel_of_the_band() {
    let voxel = 0.02;
    let o = options(voxel);
    let v = sample(&shapes::sphere(CENTRE, RADIUS), o);
    assert_eq!(v.class, VolumeClass::LevelSet);
    let bg = v.background as f64;
    assert!((bg - 3.0 * voxel).abs() < 1e-7);
    // Every voxel of the bounds, by brute force: active exactly where the
    // analytic distance is within the band, holding it.
    let (mut inside_band, mut checked) = (0u64, 0u64);
    let lo = o.min.map(|m| (m / voxel).floor() as i32);
    let hi = o.max.map(|m| (m / voxel).ceil() as i32);
    for x in lo[0]..=hi[0] {
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                let p = [x, y, z].map(|i| i as f64 * voxel);
                let d = sphere_distance(p);
                let value = v.value([x, y, z]) as f64;
                if d.abs() < bg - 1e-6 {
                    inside_band += 1;
                    assert!((value - d).abs() < 2e-6, "({x}, {y}, {z}): {value} for {d}");
                } else if d.abs() > bg + 1e-6 {
                    assert_eq!(
                        value,
                        bg.copysign(d) as f32 as f64,
                        "({x}, {y}, {z}) at {d}"
                    );
                }
                checked += 1;
            }
        }
    }
    let active = v.active_voxel_count();
    assert!(
        active.abs_diff(inside_band) < inside_band / 1000 + 10,
        "{active} active, {inside_band} within the band"
    );
    eprintln!(
        "{checked} voxels checked, {active} active; {} leaves, {} tiles",
        v.leaves().len(),
        v.tiles().len()
    );
    assert!(v
        .tiles()
        .iter()
        .all(|t| t.value == -v.background && !t.active));
}

#[test]
fn the_sampled_field_reads_the_distance_between_voxels() {
    let voxel = 0.02;
    let volume = sample(&shapes::sphere(CENTRE, RADIUS), options(voxel));
    let f = Field::volume(VolumeField::new(volume));
    let tape = Tape::compile(&f);
    let mut eval = PointEval::new(&tape);
    let mut worst: f64 = 0.0;
    let mut rng = 7u64;
    let mut next = || {
        rng = rng
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..20_000 {
        // Points within two voxels of the surface (positive inside).
        let dir = [next() - 0.5, next() - 0.5, next() - 0.5];
        let len = (dir.iter().map(|d| d * d).sum::<f64>()).sqrt().max(1e-9);
        let r = RADIUS + (next() - 0.5) * 4.0 * voxel;
        let p: [f64; 3] = std::array::from_fn(|k| CENTRE[k] + dir[k] / len * r);
        worst = worst.max((eval.eval(p) + sphere_distance(p)).abs());
    }
    // Trilinear interpolation of a distance: second-order in the voxel.
    assert!(worst < voxel * voxel / RADIUS, "worst {worst}");
    eprintln!(
        "sampled field against the distance: worst {worst:.2e} ({:.4} voxel)",
        worst / voxel
    );
    // Intervals hold every value they bound.
    let mut ieval = IntervalEval::new(&tape);
    for k in 0..300 {
        let c: [f64; 3] = std::array::from_fn(|a| CENTRE[a] + (next() - 0.5) * 1.3);
        let h = 0.001 + 0.2 * (k as f64 / 300.0).powi(2);
        let range = ieval.eval(
            Interval::new(c[0] - h, c[0] + h),
            Interval::new(c[1] - h, c[1] + h),
            Interval::new(c[2] - h, c[2] + h),
        );
        for _ in 0..20 {
            let p: [f64; 3] = std::array::from_fn(|a| c[a] + (next() * 2.0 - 1.0) * h);
            let v = eval.eval(p);
            assert!(range.lo <= v && v <= range.hi, "{v} outside {range:?}");
        }
    }
}

#[test]
fn sampling_is_the_same_on_any_thread_count() {
    let f = shapes::blend_union(
        &shapes::torus([0.0; 3], 0.4, 0.12),
        &shapes::block([0.2, 0.1, 0.0], [0.2, 0.2, 0.2]),
        [0.1, 1.0, 1.0],
    );
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| sample(&f, options(0.025)))
    };
    let one = run(1);
    assert!(one.leaves().len() > 50);
    assert_eq!(one, run(4));
    // Every leaf holds at least one active voxel or is a sign change.
    assert!(one.leaves().iter().all(|l| l.active_count() > 0 || {
        let v = &l.values;
        v.iter().any(|x| *x < 0.0) && v.iter().any(|x| *x > 0.0)
    }));
    assert_eq!(one.leaves()[0].values.len(), LEAF_VOXELS);
}

#[test]
fn bad_options_and_cancelling_are_errors() {
    let f = shapes::sphere(CENTRE, RADIUS);
    let mut o = options(0.0);
    assert_eq!(
        SamplePlan::new(&f, o, &|| false).err(),
        Some(geode_frep::SampleError::VoxelSize)
    );
    o.voxel_size = 0.1;
    o.half_width = 0.5;
    assert_eq!(
        SamplePlan::new(&f, o, &|| false).err(),
        Some(geode_frep::SampleError::HalfWidth)
    );
    o.half_width = 3.0;
    o.max[1] = o.min[1];
    assert_eq!(
        SamplePlan::new(&f, o, &|| false).err(),
        Some(geode_frep::SampleError::Bounds)
    );
    let o = options(1e-9);
    assert!(matches!(
        SamplePlan::new(&f, o, &|| false).err(),
        Some(geode_frep::SampleError::TooManyVoxels(_))
    ));
    assert_eq!(
        SamplePlan::new(&f, options(0.01), &|| true).err(),
        Some(geode_frep::SampleError::Cancelled)
    );
    let mut o = options(0.01);
    o.memory_budget = 100_000;
    assert!(matches!(
        SamplePlan::new(&f, o, &|| false).err(),
        Some(geode_frep::SampleError::TooLarge { .. })
    ));
}

/// A field that is not a distance (a gyroid: its gradient vanishes along
/// its channels, where Newton steps toward the surface may overshoot):
/// every voxel of the band keeps the field's own side.
#[test]
fn a_gyroid_s_voxels_keep_the_field_s_side() {
    let (x, y, z) = (Field::x() * 10.0, Field::y() * 10.0, Field::z() * 10.0);
    let g = x.sin() * y.cos() + y.sin() * z.cos() + z.sin() * x.cos();
    let tape = Tape::compile(&g);
    let mut eval = PointEval::new(&tape);
    let o = SampleOptions {
        min: [-0.5; 3],
        max: [0.5; 3],
        voxel_size: 0.02,
        half_width: 3.0,
        memory_budget: 1 << 32,
    };
    let v = sample(&g, o);
    let (mut checked, mut wrong) = (0, 0);
    for l in v.leaves() {
        for n in 0..LEAF_VOXELS {
            let i = [
                l.origin[0] + (n >> 6) as i32,
                l.origin[1] + ((n >> 3) & 7) as i32,
                l.origin[2] + (n & 7) as i32,
            ];
            let f = eval.eval(i.map(|c| (c as f64 * 0.02) as f32 as f64));
            let phi = l.values[n];
            if f.abs() > 1e-6 && (f > 0.0) != (phi < 0.0) {
                wrong += 1;
            }
            checked += 1;
        }
    }
    assert!(checked > 100_000, "{checked}");
    assert_eq!(wrong, 0, "{wrong} of {checked} voxels on the wrong side");
}
