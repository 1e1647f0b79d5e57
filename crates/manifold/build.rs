//! Builds manifold's C++ sources (vendor/manifold, serial) and geode's C
//! shim over them into one static library.

use std::path::Path;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let vendor = root.join("../../vendor/manifold");
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        // Optimised even in debug builds: the tests' booleans would
        // otherwise be slower than the rest of a test run put together.
        .opt_level(2)
        .debug(false)
        .warnings(false)
        .define("MANIFOLD_PAR", "-1")
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
    println!("cargo:rerun-if-changed=shim/shim.cpp");
    println!("cargo:rerun-if-changed=../../vendor/manifold");
}
