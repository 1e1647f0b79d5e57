//! Inputs that once crashed the `.hs` hierarchical-spline reader under the
//! fuzzer (kept in tests/fuzz_regressions by tools/fuzz.sh) are replayed as
//! the `read_hs` fuzz target runs them: a hierarchy that saves and loads
//! back the same, or an error, never a panic.

use geode_spline::hspline::file::{load, save};

#[test]
fn read_hs_crashes_stay_fixed() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries {
        let Ok(text) = String::from_utf8(std::fs::read(entry.unwrap().path()).unwrap()) else {
            continue;
        };
        if let Ok(h) = load(&text) {
            assert_eq!(load(&save(&h, true)).as_ref(), Ok(&h));
        }
    }
}
