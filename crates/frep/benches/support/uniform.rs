//! A seeded stream of uniform numbers in [0, 1) for the benchmarks' sample
//! points (xorshift: the same points on every run).

pub fn uniform() -> impl FnMut() -> f64 {
    let mut s = 0x9e37_79b9_7f4a_7c15_u64;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}
