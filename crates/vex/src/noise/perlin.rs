//! Perlin's gradient noise over a fixed permutation: the improved noise
//! (2002: quintic fade, twelve edge gradients) behind `noise`, `snoise`
//! and `curlnoise`, and the original (1985: cubic fade, gradients from a
//! fixed table) behind `onoise`. `noise` maps to about [0, 1] centred on
//! 0.5 as Houdini's does; the signed forms are about [-1, 1].

/// Ken Perlin's reference permutation (public domain), doubled.
const PERM: [u8; 256] = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69,
    142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219,
    203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175,
    74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60, 211, 133, 230,
    220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216, 80, 73, 209, 76,
    132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100, 109, 198, 173,
    186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163,
    70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232,
    178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162,
    241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199, 106, 157, 184, 84, 204,
    176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114, 67, 29, 24, 72, 243, 141,
    128, 195, 78, 66, 215, 61, 156, 180,
];

pub(super) fn perm(i: i32) -> i32 {
    PERM[(i & 255) as usize] as i32
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn lerp(t: f32, a: f32, b: f32) -> f32 {
    a + t * (b - a)
}

fn grad(hash: i32, x: f32, y: f32, z: f32) -> f32 {
    let h = hash & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// The lattice cell of `p` (hashed coordinates, offset by `salt` for
/// independent channels) and `p`'s place inside it.
fn cell(p: [f32; 3], salt: i32) -> ([i32; 3], [f32; 3]) {
    let f = p.map(f32::floor);
    let salts = [57, 131, 17];
    (
        std::array::from_fn(|k| f[k] as i32 + salt * salts[k]),
        std::array::from_fn(|k| p[k] - f[k]),
    )
}

/// Signed gradient noise at `p`, zero on the integer lattice, about [-1, 1];
/// `salt` offsets the lattice hash for independent channels.
pub fn perlin(p: [f32; 3], salt: i32) -> f32 {
    let ([xi, yi, zi], [x, y, z]) = cell(p, salt);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = perm(xi) + yi;
    let (aa, ab) = (perm(a) + zi, perm(a + 1) + zi);
    let b = perm(xi + 1) + yi;
    let (ba, bb) = (perm(b) + zi, perm(b + 1) + zi);
    let n = lerp(
        w,
        lerp(
            v,
            lerp(u, grad(perm(aa), x, y, z), grad(perm(ba), x - 1.0, y, z)),
            lerp(
                u,
                grad(perm(ab), x, y - 1.0, z),
                grad(perm(bb), x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(perm(aa + 1), x, y, z - 1.0),
                grad(perm(ba + 1), x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(perm(ab + 1), x, y - 1.0, z - 1.0),
                grad(perm(bb + 1), x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    );
    n.clamp(-1.0, 1.0)
}

/// Perlin's original noise: the cubic fade `3t² - 2t³` and a gradient per
/// lattice point drawn from the permutation (unit vectors of a fixed
/// table), about [-1, 1], zero on the lattice.
pub fn original(p: [f32; 3], salt: i32) -> f32 {
    let ([xi, yi, zi], [x, y, z]) = cell(p, salt);
    let s = |t: f32| t * t * (3.0 - 2.0 * t);
    let (u, v, w) = (s(x), s(y), s(z));
    let dot = |i: i32, j: i32, k: i32, dx: f32, dy: f32, dz: f32| {
        let h = perm(perm(perm(xi + i) + yi + j) + zi + k) as usize;
        let g = GRADIENTS[h % GRADIENTS.len()];
        g[0] * dx + g[1] * dy + g[2] * dz
    };
    let corner = |i: i32, j: i32, k: i32| dot(i, j, k, x - i as f32, y - j as f32, z - k as f32);
    let n = lerp(
        w,
        lerp(
            v,
            lerp(u, corner(0, 0, 0), corner(1, 0, 0)),
            lerp(u, corner(0, 1, 0), corner(1, 1, 0)),
        ),
        lerp(
            v,
            lerp(u, corner(0, 0, 1), corner(1, 0, 1)),
            lerp(u, corner(0, 1, 1), corner(1, 1, 1)),
        ),
    );
    // Unit gradients reach about ±0.87 in 3D; scale to about ±1.
    (n * 1.15).clamp(-1.0, 1.0)
}

/// Unit gradients spread over the sphere (the vertices of an icosahedron
/// and the centres of its faces, normalised).
const GRADIENTS: [[f32; 3]; 16] = [
    [0.0, 0.525731, 0.850651],
    [0.0, -0.525731, 0.850651],
    [0.0, 0.525731, -0.850651],
    [0.0, -0.525731, -0.850651],
    [0.525731, 0.850651, 0.0],
    [-0.525731, 0.850651, 0.0],
    [0.525731, -0.850651, 0.0],
    [-0.525731, -0.850651, 0.0],
    [0.850651, 0.0, 0.525731],
    [-0.850651, 0.0, 0.525731],
    [0.850651, 0.0, -0.525731],
    [-0.850651, 0.0, -0.525731],
    [0.57735, 0.57735, 0.57735],
    [-0.57735, -0.57735, 0.57735],
    [0.57735, -0.57735, -0.57735],
    [-0.57735, 0.57735, -0.57735],
];

/// The curl of a 2D noise potential at (x, y): a divergence-free vector in
/// the plane (z is 0), by central differences.
pub fn curl2d(p: [f32; 2]) -> [f32; 3] {
    const H: f32 = 1e-3;
    let f = |x: f32, y: f32| perlin([x, y, 0.5], 5);
    let dx = (f(p[0] + H, p[1]) - f(p[0] - H, p[1])) / (2.0 * H);
    let dy = (f(p[0], p[1] + H) - f(p[0], p[1] - H)) / (2.0 * H);
    [dy, -dx, 0.0]
}

/// Curl of a vector potential of three independent noise channels, by
/// central differences (divergence-free up to the step).
pub fn curl(p: [f32; 3]) -> [f32; 3] {
    const H: f32 = 1e-3;
    let d = |axis: usize, channel: i32| {
        let (mut a, mut b) = (p, p);
        a[axis] += H;
        b[axis] -= H;
        (perlin(a, channel) - perlin(b, channel)) / (2.0 * H)
    };
    [d(1, 3) - d(2, 2), d(2, 1) - d(0, 3), d(0, 2) - d(1, 1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_on_the_lattice_and_bounded() {
        assert_eq!(perlin([3.0, -2.0, 5.0], 0), 0.0);
        for i in 0..1000 {
            let t = i as f32 * 0.137;
            let v = perlin([t, t * 0.7, -t * 1.3], 0);
            assert!((-1.0..=1.0).contains(&v));
        }
    }

    #[test]
    fn original_noise_is_zero_on_the_lattice_smooth_and_bounded() {
        assert_eq!(original([1.0, 2.0, -3.0], 0), 0.0);
        let mut lo = 0.0f32;
        let mut hi = 0.0f32;
        for i in 0..4000 {
            let t = i as f32 * 0.0371;
            let v = original([t, t * 0.61, -t * 1.7], 0);
            let w = original([t + 1e-3, t * 0.61, -t * 1.7], 0);
            assert!((v - w).abs() < 1e-2, "continuous at {t}");
            lo = lo.min(v);
            hi = hi.max(v);
        }
        assert!(
            lo < -0.3 && hi > 0.3 && lo >= -1.0 && hi <= 1.0,
            "{lo} {hi}"
        );
    }

    #[test]
    fn curl2d_is_divergence_free() {
        let (p, h) = ([0.3f32, 0.7], 1e-2);
        let dx = (curl2d([p[0] + h, p[1]])[0] - curl2d([p[0] - h, p[1]])[0]) / (2.0 * h);
        let dy = (curl2d([p[0], p[1] + h])[1] - curl2d([p[0], p[1] - h])[1]) / (2.0 * h);
        let size = curl2d(p)[0].abs() + curl2d(p)[1].abs();
        assert!((dx + dy).abs() < 0.05 * size.max(1.0));
    }

    #[test]
    fn curl_is_divergence_free() {
        let p = [0.3f32, 0.7, 1.1];
        let h = 1e-2;
        let mut div = 0.0;
        for a in 0..3 {
            let (mut x, mut y) = (p, p);
            x[a] += h;
            y[a] -= h;
            div += (curl(x)[a] - curl(y)[a]) / (2.0 * h);
        }
        let size: f32 = curl(p).iter().map(|c| c.abs()).sum();
        assert!(div.abs() < 0.05 * size.max(1.0), "div {div}");
    }
}
