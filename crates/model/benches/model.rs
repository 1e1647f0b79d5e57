//! The modelling kernel at realistic sizes (run: cargo bench -p geode-model).
fn main() {}
