//! Fuzz target: the field codec (what the disk cache reads back, from a disk other machines share) must return a field or an error on any bytes, never panic, overflow the stack or allocate what the bytes do not hold.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(field) = geode_frep::codec::decode(data) {
        // What decodes compiles and evaluates (a mesh's indices were checked).
        let tape = geode_frep::Tape::compile(&field);
        let _ = geode_frep::PointEval::new(&tape).eval([0.1, 0.2, 0.3]);
    }
});
