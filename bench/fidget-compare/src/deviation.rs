//! How far a mesh strays from the exact surface: geode's measure
//! (`geode_mesher::surface_distances`, the first-order distance `|f| / |∇f|`
//! with exact gradients, the one adaptive output keeps within its
//! tolerance) at every vertex, triangle centroid and edge midpoint, the same
//! yardstick for both meshers.

use geode_frep::{Field, Tape};
use geode_mesher::surface_distances;
use geode_geo::glam::Vec3;

/// The largest and the 99th-percentile distance over the samples.
pub fn deviation(field: &Field, positions: &[[f32; 3]], triangles: &[[u32; 3]]) -> (f64, f64) {
    let mut samples: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    for t in triangles {
        let [a, b, c] = t.map(|i| samples[i as usize]);
        samples.extend([
            (a + b + c) / 3.0,
            0.5 * (a + b),
            0.5 * (b + c),
            0.5 * (c + a),
        ]);
    }
    let tape = Tape::compile(field);
    let mut d: Vec<f64> = surface_distances(&tape, &samples)
        .into_iter()
        .map(f64::from)
        .filter(|d| d.is_finite())
        .collect();
    d.sort_by(f64::total_cmp);
    let max = d.last().copied().unwrap_or(0.0);
    let p99 = d.get(d.len() * 99 / 100).copied().unwrap_or(0.0);
    (max, p99)
}
