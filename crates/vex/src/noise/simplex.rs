//! Simplex noise in 3D (Perlin 2001, as Gustavson explains it): the
//! lattice skewed into tetrahedra, four corners a point instead of eight,
//! radial falloff `(0.6 - r²)⁴` per corner; about [-1, 1], zero at lattice
//! points. Gradients and hashing share `perlin`'s permutation.

use super::perlin::perm;

/// Gradients to the edge midpoints of a cube.
const GRAD: [[f32; 3]; 12] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
];

/// Simplex noise at `p`; `salt` offsets the hash for independent channels.
pub fn simplex(p: [f32; 3], salt: i32) -> f32 {
    const F3: f32 = 1.0 / 3.0;
    const G3: f32 = 1.0 / 6.0;
    let [x, y, z] = p;
    // The cell of the skewed lattice.
    let s = (x + y + z) * F3;
    let (i, j, k) = ((x + s).floor(), (y + s).floor(), (z + s).floor());
    let t = (i + j + k) * G3;
    let x0 = [x - (i - t), y - (j - t), z - (k - t)];
    // Which tetrahedron of the cube: the order of the offsets.
    let (a, b) = if x0[0] >= x0[1] {
        if x0[1] >= x0[2] {
            ([1, 0, 0], [1, 1, 0])
        } else if x0[0] >= x0[2] {
            ([1, 0, 0], [1, 0, 1])
        } else {
            ([0, 0, 1], [1, 0, 1])
        }
    } else if x0[1] < x0[2] {
        ([0, 0, 1], [0, 1, 1])
    } else if x0[0] < x0[2] {
        ([0, 1, 0], [0, 1, 1])
    } else {
        ([0, 1, 0], [1, 1, 0])
    };
    let corner = |o: [i32; 3], g: f32| -> [f32; 3] {
        [
            x0[0] - o[0] as f32 + g,
            x0[1] - o[1] as f32 + g,
            x0[2] - o[2] as f32 + g,
        ]
    };
    let corners = [
        ([0, 0, 0], x0),
        (a, corner(a, G3)),
        (b, corner(b, 2.0 * G3)),
        ([1, 1, 1], corner([1, 1, 1], 3.0 * G3)),
    ];
    let (ii, jj, kk) = (
        i as i32 + salt * 57,
        j as i32 + salt * 131,
        k as i32 + salt * 17,
    );
    let mut n = 0.0;
    for (o, d) in corners {
        let r = 0.6 - d[0] * d[0] - d[1] * d[1] - d[2] * d[2];
        if r > 0.0 {
            let h = perm(ii + o[0] + perm(jj + o[1] + perm(kk + o[2]))) as usize % 12;
            let g = GRAD[h];
            let r2 = r * r;
            n += r2 * r2 * (g[0] * d[0] + g[1] * d[1] + g[2] * d[2]);
        }
    }
    // The corners' sum reaches about ±1/32.
    (32.0 * n).clamp(-1.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_at_lattice_points_continuous_and_bounded() {
        assert_eq!(simplex([0.0, 0.0, 0.0], 0), 0.0);
        let (mut lo, mut hi) = (0.0f32, 0.0f32);
        for i in 0..4000 {
            let t = i as f32 * 0.0413;
            let v = simplex([t, -t * 0.37, t * 1.21], 0);
            let w = simplex([t + 1e-3, -t * 0.37, t * 1.21], 0);
            assert!((v - w).abs() < 2e-2, "continuous at {t}");
            lo = lo.min(v);
            hi = hi.max(v);
        }
        assert!(lo < -0.4 && hi > 0.4, "{lo} {hi}");
    }
}
