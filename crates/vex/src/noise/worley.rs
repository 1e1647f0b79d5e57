//! Worley's cellular noise: one feature point jittered inside each unit
//! cell (hashed from the cell, so fixed), and for a position the distances
//! to the nearest two (F1 and F2) and the nearest one's cell id, searching
//! the 27 cells around it.

use super::perlin::perm;

/// The nearest two feature points' distances and the nearest one's id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub f1: f32,
    pub f2: f32,
    pub id: i32,
}

/// A hash of a cell in [0, 1) for channel `c`.
fn unit(x: i32, y: i32, z: i32, c: i32) -> f32 {
    let h = perm(x + perm(y + perm(z + perm(c * 61))));
    let h2 = perm(h + x.wrapping_mul(7) + c);
    ((h * 256 + h2) as f32 + 0.5) / 65536.0
}

/// F1, F2 and the nearest cell's id at `p`; `jitter` in [0, 1] scales how
/// far feature points stray from their cells' centres.
pub fn worley(p: [f32; 3], jitter: f32) -> Cell {
    let base = p.map(|c| c.floor() as i32);
    let (mut f1, mut f2, mut id) = (f32::INFINITY, f32::INFINITY, 0);
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (cx, cy, cz) = (base[0] + dx, base[1] + dy, base[2] + dz);
                let feature = [
                    cx as f32 + 0.5 + jitter * (unit(cx, cy, cz, 0) - 0.5),
                    cy as f32 + 0.5 + jitter * (unit(cx, cy, cz, 1) - 0.5),
                    cz as f32 + 0.5 + jitter * (unit(cx, cy, cz, 2) - 0.5),
                ];
                let d = ((feature[0] - p[0]).powi(2)
                    + (feature[1] - p[1]).powi(2)
                    + (feature[2] - p[2]).powi(2))
                .sqrt();
                if d < f1 {
                    f2 = f1;
                    f1 = d;
                    id = perm(cx + perm(cy + perm(cz))) * 256 + perm(cz + perm(cx));
                } else if d < f2 {
                    f2 = d;
                }
            }
        }
    }
    Cell { f1, f2, id }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f1_is_the_nearest_and_f2_the_next() {
        for i in 0..500 {
            let t = i as f32 * 0.173;
            let c = worley([t, t * 0.5, -t * 0.3], 1.0);
            assert!(c.f1 <= c.f2, "{c:?}");
            // A feature point lies in every cell, so F1 is at most the
            // cell diagonal.
            assert!(c.f1 <= 3f32.sqrt(), "{c:?}");
        }
        // Without jitter the features are the cell centres.
        let c = worley([0.5, 0.5, 0.5], 0.0);
        assert_eq!(c.f1, 0.0);
        assert!((c.f2 - 1.0).abs() < 1e-6);
    }
}
