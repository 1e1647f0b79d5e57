//! A test mesh for the mesh-field benchmarks (geode-frep's and geode-mesher's).

/// A UV sphere of radius about 1 with `n` rings (4 n^2 triangles), its
/// radius rippled so no two rings are alike.
pub fn wavy_sphere(n: u32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let pi = std::f32::consts::PI;
    let radius = |th: f32, ph: f32| 1.0 + 0.05 * (7.0 * th).sin() * (5.0 * ph).cos();
    let mut p = vec![[0.0, 0.0, radius(0.0, 0.0)]];
    for i in 1..n {
        let th = pi * i as f32 / n as f32;
        for j in 0..2 * n {
            let ph = pi * j as f32 / n as f32;
            let r = radius(th, ph);
            p.push([
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                r * th.cos(),
            ]);
        }
    }
    p.push([0.0, 0.0, -radius(pi, 0.0)]);
    let ring = |i: u32, j: u32| 1 + (i - 1) * 2 * n + j % (2 * n);
    let last = p.len() as u32 - 1;
    let mut t = Vec::new();
    for j in 0..2 * n {
        t.push([0, ring(1, j), ring(1, j + 1)]);
        t.push([last, ring(n - 1, j + 1), ring(n - 1, j)]);
    }
    for i in 1..n - 1 {
        for j in 0..2 * n {
            t.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
    }
    (p, t)
}
