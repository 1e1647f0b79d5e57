//! The UV kernel at realistic sizes (run: cargo bench -p geode-uv): LSCM
//! flattening and packing of a 200k-triangle hemisphere (one disk
//! island) and of a 200k-triangle torus cut along two seams (one
//! rectangle), each with both linear solvers; and projections of a
//! sphere of 1M vertices.

#[path = "../tests/common/meshes.rs"]
mod meshes;

use std::sync::OnceLock;

use divan::counter::ItemsCount;
use divan::Bencher;
use geode_geo::{ops, primitives, Geometry};
use geode_uv::{
    flatten, project, Axis, FlattenOptions, LinearSolver, ProjectOptions, Projection, SolverOptions,
};

/// The allocator the geode binary runs with.
#[global_allocator]
static ALLOC: geode_alloc::HugePages = geode_alloc::HugePages;

fn main() {
    divan::main();
}

fn never() -> bool {
    false
}

/// 6 x 183^2 = 200,934 triangles.
fn hemisphere() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| meshes::hemisphere(183))
}

/// 400 x 250 quads triangulated: 200,000 triangles, and its two seams
/// (a meridian and a ring), which open it into one rectangle.
fn cut_torus() -> &'static (Geometry, Vec<[u32; 2]>) {
    static G: OnceLock<(Geometry, Vec<[u32; 2]>)> = OnceLock::new();
    G.get_or_init(|| {
        let (cols, rows) = (400u32, 250u32);
        let g = ops::triangulate(&primitives::torus(2.0, 0.5, cols, rows), None);
        let id = |i: u32, j: u32| (i % cols) * rows + j % rows;
        let mut seams: Vec<[u32; 2]> = (0..rows).map(|j| [id(0, j), id(0, j + 1)]).collect();
        seams.extend((0..cols).map(|i| [id(i, 0), id(i + 1, 0)]));
        (g, seams)
    })
}

/// A UV sphere of 1000 x 251 rows: 1,002,000 vertices.
fn sphere() -> &'static Geometry {
    static G: OnceLock<Geometry> = OnceLock::new();
    G.get_or_init(|| primitives::uv_sphere(1.0, 1000, 251))
}

fn options(method: LinearSolver) -> FlattenOptions {
    FlattenOptions {
        solver: SolverOptions {
            method,
            ..SolverOptions::default()
        },
        ..FlattenOptions::default()
    }
}

const SOLVERS: [LinearSolver; 2] = [LinearSolver::Cholesky, LinearSolver::ConjugateGradient];

#[divan::bench(args = SOLVERS, sample_count = 3)]
fn flatten_hemisphere_200k_triangles(bencher: Bencher, method: LinearSolver) {
    let g = hemisphere();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| flatten(g, &[], &options(method), &never).unwrap());
}

#[divan::bench(args = SOLVERS, sample_count = 3)]
fn flatten_torus_200k_triangles_two_seams(bencher: Bencher, method: LinearSolver) {
    let (g, seams) = cut_torus();
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| flatten(g, seams, &options(method), &never).unwrap());
}

const PROJECTIONS: [Projection; 4] = [
    Projection::Planar { axis: Axis::Z },
    Projection::Cylindrical { axis: Axis::Y },
    Projection::Spherical { axis: Axis::Y },
    Projection::Box,
];

/// The spectral map of the same cut torus (Cholesky, then inverse
/// iteration on the one factorisation).
#[divan::bench(sample_count = 3)]
fn flatten_torus_200k_triangles_two_seams_spectral(bencher: Bencher) {
    let (g, seams) = cut_torus();
    let options = FlattenOptions {
        method: geode_uv::ConformalMethod::Spectral,
        ..FlattenOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_prims()))
        .bench(|| flatten(g, seams, &options, &never).unwrap());
}

#[divan::bench(args = PROJECTIONS, sample_count = 10)]
fn project_1m_vertices(bencher: Bencher, projection: Projection) {
    let g = sphere();
    let options = ProjectOptions {
        projection,
        ..ProjectOptions::default()
    };
    bencher
        .counter(ItemsCount::new(g.num_vertices()))
        .bench(|| project(g, &options).unwrap());
}
