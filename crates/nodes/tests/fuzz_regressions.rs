//! Inputs that once crashed the expression language or the network loader
//! under the fuzzer (kept in tests/fuzz_regressions/{expr,network} by
//! tools/fuzz.sh) are replayed as the fuzz targets run them: an error or a
//! value, never a panic.

use std::path::Path;

/// The UTF-8 files kept for one fuzz target.
fn kept(target: &str) -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_regressions")
        .join(target);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .filter_map(|e| String::from_utf8(std::fs::read(e.unwrap().path()).unwrap()).ok())
        .collect()
}

#[test]
fn expression_crashes_stay_fixed() {
    for text in kept("expr") {
        if let Ok(e) = geode_nodes::Expr::parse(&text, &["x", "y", "z"]) {
            let _ = e.eval(&[0.5, -1.0, 2.0]);
            let xyz = [
                geode_frep::Field::x(),
                geode_frep::Field::y(),
                geode_frep::Field::z(),
            ];
            let _ = geode_frep::Tape::compile(&e.to_field(&xyz));
        }
    }
}

#[test]
fn network_crashes_stay_fixed() {
    let registry = geode_nodes::registry();
    for text in kept("network") {
        let _ = geode_graph::load_str(&text, &registry);
    }
}
