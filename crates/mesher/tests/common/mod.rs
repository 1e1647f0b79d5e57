//! Helpers shared by the polygoniser's tests (each test file uses some).
#![allow(dead_code)]

use geode_frep::Field;
use geode_geo::Geometry;
use geode_mesher::{polygonise, MeshOptions};

/// Distance from `p` to the nearest vertex of `g`.
pub fn nearest_vertex(g: &Geometry, p: [f64; 3]) -> f64 {
    g.positions()
        .iter()
        .map(|v| {
            ((v.x as f64 - p[0]).powi(2)
                + (v.y as f64 - p[1]).powi(2)
                + (v.z as f64 - p[2]).powi(2))
            .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Meshes `f` over the cube `[-half, half]^3` at `depth`.
pub fn mesh(f: &Field, half: f64, depth: u32) -> Geometry {
    polygonise(
        f,
        &MeshOptions::new([-half; 3], [half; 3], depth),
        &|| false,
        &|_| {},
    )
    .unwrap()
    .0
}

/// The accuracy bar for solids with planar faces: every vertex within 1% of
/// a cell of the surface, every corner within 2% (both in cells).
pub fn assert_sharp(worst_vertex: f64, worst_corner: f64) {
    eprintln!("worst vertex {worst_vertex:.4} cells, worst corner {worst_corner:.4} cells");
    assert!(
        worst_vertex <= 0.01,
        "a vertex lies {worst_vertex} cells off the surface"
    );
    assert!(
        worst_corner <= 0.02,
        "a corner is missed by {worst_corner} cells"
    );
}

/// splitmix64: a seeded stream of uniform numbers in [0, 1).
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A uniformly distributed rotation (Shoemake's unit quaternion) as rows.
    pub fn rotation(&mut self) -> [[f64; 3]; 3] {
        let (u1, u2, u3) = (self.next(), self.next(), self.next());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let (x, y, z, w) = (
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
            b * (tau * u3).cos(),
        );
        [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - z * w),
                2.0 * (x * z + y * w),
            ],
            [
                2.0 * (x * y + z * w),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - x * w),
            ],
            [
                2.0 * (x * z - y * w),
                2.0 * (y * z + x * w),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ]
    }
}

/// `r p` for a 3x3 matrix given by rows.
pub fn apply(r: &[[f64; 3]; 3], p: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2])
}

pub fn transpose(r: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| r[j][i]))
}

/// Unsigned distance from `q` (in the box's frame) to the surface of the box
/// with half-extents `h` centred at the origin.
pub fn box_surface_distance(q: [f64; 3], h: [f64; 3]) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|k| q[k].abs() - h[k]);
    let outside = d.iter().map(|x| x.max(0.0).powi(2)).sum::<f64>().sqrt();
    let inside = d[0].max(d[1]).max(d[2]).min(0.0);
    outside + inside.abs()
}
