//! Fuzzes the `.hs` hierarchical-spline reader: any bytes give a hierarchy
//! or an error with a line, never a panic; what loads saves and loads again
//! to the same hierarchy.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(h) = geode_spline::hspline::file::load(text) {
            let again = geode_spline::hspline::file::load(&geode_spline::hspline::file::save(&h, true));
            assert_eq!(again.as_ref(), Ok(&h));
        }
    }
});
