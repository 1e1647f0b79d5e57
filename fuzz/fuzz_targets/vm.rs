//! Fuzz target: the fidget `.vm` reader must return a field or an error with a line on any text, never panic or overflow the stack.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(field) = geode_frep::parse_vm(text) {
        // The field must compile to a tape and evaluate, however deep it is.
        let tape = geode_frep::Tape::compile(&field);
        let _ = geode_frep::PointEval::new(&tape).eval([0.1, 0.2, 0.3]);
    }
});
