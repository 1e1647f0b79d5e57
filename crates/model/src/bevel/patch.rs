//! Profiles and corner patches: the superellipse a bevel's cross-section
//! follows (Blender's profile), and the triangular grid that fills a
//! corner where three profiles meet.

use geode_geo::glam::Vec3;

/// Blender's profile shape (0..1, 0.5 a circular arc, 0.25 a straight
/// chamfer, 1 a square corner) as the superellipse exponent r of
/// |x|^r + |y|^r = 1 (Blender's `-ln 2 / ln sqrt(profile)`), kept finite.
pub(crate) fn exponent(profile: f32) -> f32 {
    let p = profile.clamp(1e-6, 1.0 - 1e-6) as f64;
    (-2.0 * std::f64::consts::LN_2 / p.ln()).clamp(0.05, 1000.0) as f32
}

/// The n - 1 points strictly between `l` and `r` of a profile of `n`
/// segments whose corner (the sharp edge it rounds) is `c`: the
/// superellipse of exponent `e` in the parallelogram with corners l, c, r
/// and m = l + r - c, so it leaves l toward c and reaches r from c
/// (tangent to both faces). Angles are uniform: for e = 2 and a right
/// corner the points are evenly spaced on the circle about m.
pub(crate) fn profile(l: Vec3, r: Vec3, c: Vec3, e: f32, n: u32) -> Vec<Vec3> {
    let m = l + r - c;
    let (a, b) = (l - m, r - m);
    (1..n)
        .map(|j| {
            let phi = std::f32::consts::FRAC_PI_2 * j as f32 / n as f32;
            let (x, y) = (phi.cos(), phi.sin());
            // (x^e + y^e)^(-1/e), written about the larger to stay finite.
            let big = x.max(y);
            let q = x.min(y) / big;
            let s = (1.0 + q.powf(e)).powf(-1.0 / e) / big;
            m + a * (s * x) + b * (s * y)
        })
        .collect()
}

/// The centre the parallelogram of a profile turns about.
pub(crate) fn centre(l: Vec3, r: Vec3, c: Vec3) -> Vec3 {
    l + r - c
}

/// The inside points of a triangular grid of `n` segments a side whose
/// sides are `s0` (K0 to K1), `s1` (K1 to K2) and `s2` (K2 to K0), of
/// n + 1 points each. Grid point (i, j), i + j <= n, is K0 moved i
/// steps toward K1 and j toward K2; the inside ones (i, j, n - i - j all positive) are
/// listed by i then j. Each is the mean of the three straight lines
/// through it between opposite sides; when every side point lies on one
/// sphere about `centre` (a rounded corner with a circular profile) they
/// are pushed onto it.
pub(crate) fn tri_inside(s: [&[Vec3]; 3], n: usize, centre: Option<Vec3>) -> Vec<Vec3> {
    let at = |i: usize, j: usize| -> Vec3 {
        if j == 0 {
            s[0][i]
        } else if i == 0 {
            s[2][n - j]
        } else {
            // i + j == n
            s[1][j]
        }
    };
    let sphere = centre.and_then(|c| {
        let d: Vec<f32> = s
            .iter()
            .flat_map(|x| x.iter().map(|p| (*p - c).length()))
            .collect();
        let r = d.iter().sum::<f32>() / d.len() as f32;
        let fits = r > 0.0 && d.iter().all(|x| (x - r).abs() <= 1e-3 * r);
        fits.then_some((c, r))
    });
    let mut out = Vec::new();
    for i in 1..n {
        for j in 1..n - i {
            let k = n - i - j;
            let lerp = |a: Vec3, b: Vec3, t: f32| a + (b - a) * t;
            let by_j = lerp(at(0, j), at(n - j, j), i as f32 / (n - j) as f32);
            let by_i = lerp(at(i, 0), at(i, n - i), j as f32 / (n - i) as f32);
            let by_k = lerp(at(n - k, 0), at(0, n - k), j as f32 / (n - k) as f32);
            let mut p = (by_i + by_j + by_k) / 3.0;
            if let Some((c, r)) = sphere {
                p = c + (p - c).normalize_or_zero() * r;
            }
            out.push(p);
        }
    }
    out
}

/// The triangles of that grid over point numbers: `side` as `tri_inside`
/// lists them (three sides of n + 1 ids, K0 to K1, K1 to K2, K2 to K0)
/// and `inside` in its order. Wound as K0, K1, K2.
pub(crate) fn tri_faces(side: [&[u32]; 3], inside: &[u32], n: usize) -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| -> u32 {
        if j == 0 {
            side[0][i]
        } else if i == 0 {
            side[2][n - j]
        } else if i + j == n {
            side[1][j]
        } else {
            // Inside points by i then j: row i holds n - i - 1 of them.
            let before: usize = (1..i).map(|r| n - r - 1).sum();
            inside[before + j - 1]
        }
    };
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..n - i {
            tris.push([id(i, j), id(i + 1, j), id(i, j + 1)]);
            if i + j + 2 <= n {
                tris.push([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    tris
}
