//! Seeded, counter-based random numbers: a value is a hash of (seed,
//! element, component), so it never depends on how work is split across
//! threads or in what order elements are visited.

fn mix(seed: u64, element: u64, component: u64) -> u64 {
    let mut z = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ element.wrapping_mul(0xBF58_476D_1CE4_E5B9)
        ^ component.wrapping_mul(0x94D0_49BB_1331_11EB);
    // SplitMix64's finaliser.
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform value in [0, 1) with 24 random bits.
pub fn unit(seed: u64, element: u64, component: u64) -> f32 {
    (mix(seed, element, component) >> 40) as f32 / (1u64 << 24) as f32
}

/// A uniform value in [0, 1) with 53 random bits.
pub fn unit_f64(seed: u64, element: u64, component: u64) -> f64 {
    (mix(seed, element, component) >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_enough_and_reproducible() {
        let n = 100_000;
        let mean: f64 = (0..n).map(|i| unit_f64(7, i, 0)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        assert_eq!(unit(1, 2, 3), unit(1, 2, 3));
        assert_ne!(unit(1, 2, 3), unit(2, 2, 3));
        assert!((0..n).all(|i| (0.0..1.0).contains(&unit(3, i, 1))));
    }
}
