//! Builds manifold's C++ sources (vendor/manifold) and geode's C shim over
//! them into one static library: on TBB, manifold's parallel backend, where
//! its headers and library are installed (Debian's libtbb-dev), serially
//! otherwise or when GEODE_MANIFOLD_SERIAL is set.

use std::path::Path;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let vendor = root.join("../../vendor/manifold");
    let tbb = tbb_installed();
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        // Optimised even in debug builds: the tests' booleans would
        // otherwise be slower than the rest of a test run put together.
        .opt_level(2)
        .debug(false)
        .warnings(false)
        .define("MANIFOLD_PAR", if tbb { "1" } else { "-1" })
        .define("NDEBUG", None)
        .include(vendor.join("include"))
        .include(vendor.join("src"))
        .file(root.join("shim/shim.cpp"));
    let sources = std::fs::read_dir(vendor.join("src")).expect("vendor/manifold/src is there");
    let mut files: Vec<_> = sources
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cpp"))
        .collect();
    files.sort();
    build.files(&files);
    build.compile("geode_manifold");
    if tbb {
        println!("cargo:rustc-link-lib=tbb");
    }
    println!("cargo:rerun-if-changed=shim/shim.cpp");
    println!("cargo:rerun-if-changed=../../vendor/manifold");
    println!("cargo:rerun-if-env-changed=GEODE_MANIFOLD_SERIAL");
}

/// Where a system package puts TBB's headers and library.
const INCLUDE_DIRS: &[&str] = &["/usr/include", "/usr/local/include"];
const LIB_DIRS: &[&str] = &[
    "/usr/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/usr/lib",
    "/usr/local/lib",
];

/// Whether oneTBB can be compiled against and linked here.
fn tbb_installed() -> bool {
    if std::env::var_os("GEODE_MANIFOLD_SERIAL").is_some() {
        return false;
    }
    let header = INCLUDE_DIRS
        .iter()
        .map(|d| Path::new(d).join("tbb/task_arena.h"))
        .find(|h| h.exists());
    // Rebuilt if the headers go (watching a file that is not there would
    // rebuild manifold every time; installing TBB later needs `cargo clean
    // -p geode-manifold`).
    if let Some(h) = &header {
        println!("cargo:rerun-if-changed={}", h.display());
    }
    let library = LIB_DIRS
        .iter()
        .any(|d| Path::new(d).join("libtbb.so").exists());
    header.is_some() && library
}
