//! Fuzz target: the Houdini .geo/.bgeo reader must return Ok or Err on any bytes, never panic.
#![no_main]

use geode_io::{parse_unguarded, Format, NoProgress};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = parse_unguarded(data, Format::Bgeo, None, &NoProgress);
});
