//! Benchmarks of wrangles at realistic sizes (filled in below).
fn main() {}
