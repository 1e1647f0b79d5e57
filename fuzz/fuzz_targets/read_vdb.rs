//! Fuzz target: the VDB reader must return Ok or Err on any bytes, never
//! panic, and hold no more than its memory budget.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = geode_io::vdb::read_vdb(data, 1 << 28, &|| false);
});
