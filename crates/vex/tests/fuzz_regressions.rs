//! Inputs that once crashed the VEX compiler or the parameter expression
//! parser under the fuzzer (kept in tests/fuzz_regressions by tools/fuzz.sh)
//! are replayed as the `vex_text` fuzz target runs them: an error or a
//! result, never a panic.

mod common;

use geode_vex::{parse_expression, Globals};

#[test]
fn vex_text_crashes_stay_fixed() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz_regressions");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries {
        let Ok(text) = String::from_utf8(std::fs::read(entry.unwrap().path()).unwrap()) else {
            continue;
        };
        if let Ok(e) = parse_expression(&text) {
            let g = Globals {
                frame: 3.0,
                fps: 24.0,
                hip: "/h",
                node: "n",
            };
            let _ = e.eval(&g, &common::any_channel);
        }
        let _ = common::compile_over_points(&text);
    }
}
