//! The surface kernels at realistic sizes (run: cargo bench -p geode-model --bench surface).
fn main() {}
