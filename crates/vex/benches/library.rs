//! The library and detail mode at realistic sizes (run:
//! cargo bench -p geode-vex --bench library):
//!
//! - a detail loop of scalar arithmetic, 1M iterations (the bar: under
//!   20 ns an iteration);
//! - 1M two-point polylines made by a detail loop (under 300 ms);
//! - `push` 1M times in a detail loop (amortised O(1));
//! - compiling a 1 MB snippet (linear in its size);
//! - `nearpoint` without a radius on 1M points;
//! - `xyzdist` and `primuv` from 1M points onto a 1M-triangle mesh;
//! - 200k points each appending its number to one detail array
//!   (`setdetailattrib(..., "append")`: amortised O(1) per element).

use divan::Bencher;
use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{primitives, AttribClass, Geometry};
use geode_vex::{compile, run, BindSpec, Channel, Program, RunOptions};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn no_channels(_: &str) -> Option<Channel> {
    None
}

fn no_names() -> Vec<String> {
    Vec::new()
}

fn program(src: &str, class: AttribClass, inputs: &[Option<&Geometry>]) -> Program {
    let spec = BindSpec {
        run_over: class,
        inputs: inputs.to_vec(),
        channels: &no_channels,
        channel_names: &no_names,
        frame: 1.0,
        time: 0.0,
    };
    compile(src, &spec).unwrap()
}

fn wrangle(bencher: Bencher, src: &str, class: AttribClass, inputs: &[Option<&Geometry>]) {
    let p = program(src, class, inputs);
    let g = inputs[0].unwrap();
    let cancel = || false;
    bencher
        .with_inputs(|| g.clone())
        .bench_local_values(|mut out| {
            let opts = RunOptions {
                group: None,
                cancel: &cancel,
                memory_budget: u64::MAX,
            };
            run(&p, &mut out, inputs, &opts).unwrap();
            out
        });
}

fn one_point() -> Geometry {
    let mut g = Geometry::new();
    g.add_point(Vec3::ZERO);
    g
}

/// `n` points spread through the unit cube (a deterministic hash).
fn cloud(n: usize) -> Geometry {
    let mut g = Geometry::new();
    let h = |i: usize, k: u64| geode_geo::random::unit(i as u64, k, 7);
    let p: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(h(i, 0), h(i, 1), h(i, 2)))
        .collect();
    g.set_positions(p);
    g
}

#[divan::bench(sample_count = 10)]
fn detail_loop_1m_iterations(bencher: Bencher) {
    let g = one_point();
    wrangle(
        bencher,
        "float s = 0; for (int i = 0; i < 1000000; i++) { s += i * 0.5; } f@s = s;",
        AttribClass::Detail,
        &[Some(&g)],
    );
}

#[divan::bench(sample_count = 5)]
fn detail_polylines_1m(bencher: Bencher) {
    let g = one_point();
    wrangle(
        bencher,
        "for (int i = 0; i < 1000000; i++) { int a = addpoint(0, set(i, 0, 0)); int b = addpoint(0, set(i, 1, 0)); addprim(0, \"polyline\", a, b); }",
        AttribClass::Detail,
        &[Some(&g)],
    );
}

#[divan::bench(sample_count = 5)]
fn detail_push_1m(bencher: Bencher) {
    let g = one_point();
    wrangle(
        bencher,
        "int a[]; for (int i = 0; i < 1000000; i++) { push(a, i); } i@n = len(a);",
        AttribClass::Detail,
        &[Some(&g)],
    );
}

#[divan::bench(args = [100_000, 1_000_000], sample_count = 5)]
fn compile_snippet_bytes(bencher: Bencher, bytes: usize) {
    let line = "f@r += sin(@P.x * 3.0) + fit(@P.y, 0, 1, 2, 3);\n";
    let src = line.repeat(bytes / line.len());
    let g = one_point();
    bencher.bench(|| program(&src, AttribClass::Point, &[Some(&g)]));
}

#[divan::bench(sample_count = 5)]
fn nearpoint_unbounded_1m(bencher: Bencher) {
    let g = cloud(1_000_000);
    wrangle(
        bencher,
        "i@near = nearpoint(0, @P + {0.001, 0, 0});",
        AttribClass::Point,
        &[Some(&g)],
    );
}

/// A wavy grid of about `n` triangles.
fn surface(n: usize) -> Geometry {
    let side = ((n / 2) as f64).sqrt() as usize;
    let mut g = primitives::grid(Vec2::splat(1.0), side as u32, side as u32);
    for p in g.positions_mut() {
        p.y = 0.05 * (p.x * 9.0).sin() * (p.z * 7.0).cos();
    }
    geode_geo::ops::triangulate(&g, None)
}

#[divan::bench(sample_count = 5)]
fn xyzdist_1m_onto_1m_triangles(bencher: Bencher) {
    let points = cloud(1_000_000);
    let mesh = surface(1_000_000);
    wrangle(
        bencher,
        // Points within 0.01 of the surface (seven mesh cells), as points
        // projected onto a surface they follow are.
        "float x = @P.x - 0.5, z = @P.z - 0.5; vector q = set(x, 0.05 * sin(x * 9) * cos(z * 7) + (@P.y - 0.5) * 0.02, z); int pr; vector uv; f@d = xyzdist(1, q, pr, uv); i@pr = pr; v@uv = uv;",
        AttribClass::Point,
        &[Some(&points), Some(&mesh)],
    );
}

#[divan::bench(sample_count = 5)]
fn primuv_1m_onto_1m_triangles(bencher: Bencher) {
    let points = cloud(1_000_000);
    let mesh = surface(1_000_000);
    wrangle(
        bencher,
        "v@q = primuv(1, \"P\", @ptnum % nprimitives(1), set(@P.x * 0.5, @P.y * 0.5, 0));",
        AttribClass::Point,
        &[Some(&points), Some(&mesh)],
    );
}

#[divan::bench(sample_count = 5)]
fn append_to_detail_array_200k_points(bencher: Bencher) {
    let g = cloud(200_000);
    wrangle(
        bencher,
        r#"setdetailattrib(0, "ids", array(@ptnum), "append");"#,
        AttribClass::Point,
        &[Some(&g)],
    );
}
