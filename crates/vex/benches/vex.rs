//! Wrangles at realistic sizes, each beside the same work written as Rust
//! (the bar: within 3x). Run: cargo bench -p geode-vex --bench vex
//!
//! - `@P += @N * 0.1;` on 10M points;
//! - a 30-line displacement (noise, fit, normalize) on 10M points;
//! - `nearpoints` with a radius and 16 results on 1M points;
//! - `addpoint` + `addprim` making 1M two-point polylines;
//! - a parameter expression (`fit(sin($F) * ch("amp"), -1, 1, 0, 10)`)
//!   evaluated once, as the engine does per parameter per cook: it must stay
//!   far below a frame's budget for a network of hundreds of them.

use divan::Bencher;
use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_vex::{compile, run, BindSpec, Channel, Program, RunOptions};
use rayon::prelude::*;

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

/// `n` points on a jittered lattice with unit normals `N`.
fn cloud(n: usize) -> Geometry {
    let side = (n as f64).cbrt().ceil() as usize;
    let p: Vec<Vec3> = (0..n)
        .into_par_iter()
        .map(|i| {
            let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
            Vec3::new(x as f32, y as f32, z as f32) / side as f32
        })
        .collect();
    let normals: Vec<Vec3> = p
        .par_iter()
        .map(|q| (*q - Vec3::splat(0.5)).normalize_or(Vec3::Y))
        .collect();
    let mut g = Geometry::new();
    g.set_positions(p);
    g.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(normals), TypeInfo::Normal),
    )
    .unwrap();
    g
}

fn no_channels(_: &str) -> Option<Channel> {
    None
}

fn no_names() -> Vec<String> {
    Vec::new()
}

fn program(src: &str, class: AttribClass, g: &Geometry) -> Program {
    let spec = BindSpec {
        run_over: class,
        inputs: vec![Some(g)],
        channels: &no_channels,
        channel_names: &no_names,
        frame: 1.0,
        time: 0.0,
    };
    compile(src, &spec).unwrap()
}

fn wrangle(bencher: Bencher, src: &str, class: AttribClass, g: &Geometry) {
    let p = program(src, class, g);
    let cancel = || false;
    bencher
        .with_inputs(|| g.clone())
        .bench_local_values(|mut out| {
            run(
                &p,
                &mut out,
                &[Some(g)],
                &RunOptions {
                    group: None,
                    cancel: &cancel,
                    memory_budget: u64::MAX,
                },
            )
            .unwrap();
            out
        });
}

const TEN_M: usize = 10_000_000;

#[divan::bench(sample_count = 10)]
fn add_normal_vex(bencher: Bencher) {
    let g = cloud(TEN_M);
    wrangle(bencher, "@P += @N * 0.1;", AttribClass::Point, &g);
}

#[divan::bench(sample_count = 10)]
fn add_normal_rust(bencher: Bencher) {
    let g = cloud(TEN_M);
    bencher
        .with_inputs(|| g.clone())
        .bench_local_values(|mut out| {
            let n = g
                .attrib(AttribClass::Point, "N")
                .unwrap()
                .as_vec3()
                .unwrap();
            out.positions_mut()
                .par_iter_mut()
                .zip(n)
                .for_each(|(p, n)| *p += *n * 0.1);
            out
        });
}

/// Thirty lines of a typical displacement wrangle.
const DISPLACE: &str = r#"
float freq = 3.0;
float amp = 0.05;
int octaves = 3;
vector pos = @P * freq;
float total = 0;
float weight = 1;
for (int i = 0; i < octaves; i++) {
    total += weight * snoise(pos);
    pos *= 2.0;
    weight *= 0.5;
}
float shaped = fit(total, -1, 1, 0, 1);
shaped = smooth(0.2, 0.8, shaped);
vector n = normalize(@N);
vector side = normalize(cross(n, {0, 1, 0.001}));
float twist = fit01(shaped, -0.5, 0.5);
vector offset = n * amp * shaped + side * amp * 0.2 * twist;
float len = length(offset);
if (len > amp) {
    offset *= amp / len;
}
@P += offset;
f@height = shaped;
vector c = lerp({0.1, 0.2, 0.6}, {0.9, 0.8, 0.3}, shaped);
@Cd = clamp(c, 0, 1);
float ao = fit(dot(n, {0, 1, 0}), -1, 1, 0.4, 1);
@Cd *= ao;
f@mask = shaped > 0.5 ? 1 : 0;
"#;

#[divan::bench(sample_count = 10)]
fn displace_vex(bencher: Bencher) {
    let g = cloud(TEN_M);
    wrangle(bencher, DISPLACE, AttribClass::Point, &g);
}

fn smooth(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[divan::bench(sample_count = 10)]
fn displace_rust(bencher: Bencher) {
    use geode_vex::noise::perlin;
    let g = cloud(TEN_M);
    bencher
        .with_inputs(|| g.clone())
        .bench_local_values(|mut out| {
            let normals = g
                .attrib(AttribClass::Point, "N")
                .unwrap()
                .as_vec3()
                .unwrap();
            let results: Vec<(Vec3, f32, Vec3, f32)> = g
                .positions()
                .par_iter()
                .zip(normals)
                .map(|(p, n)| {
                    let (freq, amp) = (3.0, 0.05);
                    let mut pos = *p * freq;
                    let (mut total, mut weight) = (0.0, 1.0);
                    for _ in 0..3 {
                        total += weight * perlin(pos.to_array(), 0);
                        pos *= 2.0;
                        weight *= 0.5;
                    }
                    let shaped = smooth(0.2, 0.8, ((total + 1.0) / 2.0).clamp(0.0, 1.0));
                    let n = n.normalize_or_zero();
                    let side = n.cross(Vec3::new(0.0, 1.0, 0.001)).normalize_or_zero();
                    let twist = -0.5 + shaped;
                    let mut offset = n * amp * shaped + side * amp * 0.2 * twist;
                    let len = offset.length();
                    if len > amp {
                        offset *= amp / len;
                    }
                    let c = Vec3::new(0.1, 0.2, 0.6)
                        .lerp(Vec3::new(0.9, 0.8, 0.3), shaped)
                        .clamp(Vec3::ZERO, Vec3::ONE);
                    let ao = 0.4 + 0.6 * ((n.y + 1.0) / 2.0).clamp(0.0, 1.0);
                    (
                        *p + offset,
                        shaped,
                        c * ao,
                        if shaped > 0.5 { 1.0 } else { 0.0 },
                    )
                })
                .collect();
            out.set_positions(results.iter().map(|r| r.0).collect());
            out.set_attrib(
                AttribClass::Point,
                "height",
                Attribute::from_data(
                    AttribData::Float(results.iter().map(|r| r.1).collect()),
                    TypeInfo::None,
                ),
            )
            .unwrap();
            out.set_attrib(
                AttribClass::Point,
                "Cd",
                Attribute::from_data(
                    AttribData::Vec3(results.iter().map(|r| r.2).collect()),
                    TypeInfo::Color,
                ),
            )
            .unwrap();
            out.set_attrib(
                AttribClass::Point,
                "mask",
                Attribute::from_data(
                    AttribData::Float(results.iter().map(|r| r.3).collect()),
                    TypeInfo::None,
                ),
            )
            .unwrap();
            out
        });
}

const ONE_M: usize = 1_000_000;

#[divan::bench(sample_count = 5)]
fn nearpoints_vex(bencher: Bencher) {
    let g = cloud(ONE_M);
    wrangle(
        bencher,
        "int near[] = nearpoints(0, @P, 0.05, 16); i@count = len(near);",
        AttribClass::Point,
        &g,
    );
}

#[divan::bench(sample_count = 5)]
fn nearpoints_rust(bencher: Bencher) {
    let g = cloud(ONE_M);
    bencher.bench_local(|| {
        let tree =
            geode_vex::kdtree::KdTree::new(g.positions().iter().map(|p| p.to_array()).collect());
        let counts: Vec<i32> = g
            .positions()
            .par_iter()
            .map(|p| tree.nearest(p.to_array(), 0.05, 16).len() as i32)
            .collect();
        counts
    });
}

#[divan::bench(sample_count = 5)]
fn polylines_vex(bencher: Bencher) {
    let g = cloud(ONE_M);
    wrangle(
        bencher,
        "int p = addpoint(0, @P + {0, 0.01, 0}); addprim(0, \"polyline\", @ptnum, p);",
        AttribClass::Point,
        &g,
    );
}

#[divan::bench(sample_count = 5)]
fn polylines_rust(bencher: Bencher) {
    let g = cloud(ONE_M);
    bencher
        .with_inputs(|| g.clone())
        .bench_local_values(|mut out| {
            let tops: Vec<Vec3> = g
                .positions()
                .iter()
                .map(|p| *p + Vec3::new(0.0, 0.01, 0.0))
                .collect();
            let first = out.add_points(&tops);
            for i in 0..g.num_points() as u32 {
                out.add_polyline(&[i, first + i]).unwrap();
            }
            out
        });
}

/// One evaluation of a typical parameter expression (parse once, evaluate per frame).
#[divan::bench]
fn parameter_expression(b: Bencher) {
    let e = geode_vex::parse_expression("fit(sin($F * 0.1) * ch(\"../grow/amp\"), -1, 1, 0, 10)")
        .unwrap();
    let channel = |_: &str| Some(Channel::Num(vec![0.5]));
    let g = geode_vex::Globals {
        frame: 12.0,
        fps: 24.0,
        hip: "/proj",
        node: "n",
    };
    b.bench(|| e.eval(&g, &channel).unwrap());
}
