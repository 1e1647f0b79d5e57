//! Edge flips for refinement: dual contouring splits each quad along its
//! shorter diagonal, which across a sharp crease can run from one face to
//! the other and cut the crease's corner off. Where an edge strays beyond
//! the tolerance and the other diagonal of its two triangles strays less,
//! the edge is flipped; splitting is left for what flips cannot mend.

use geode_geo::glam::Vec3;

use crate::surface::{field_distances, RegionTapes};

/// A flip of the edge shared by triangles `t1 = (a, b, c)` and
/// `t2 = (b, a, d)`: they become `(a, d, c)` and `(d, b, c)`.
struct Flip {
    t1: usize,
    t2: usize,
    a: u32,
    b: u32,
    c: u32,
    d: u32,
}

/// Flips those of `edges` (lower index first) whose other diagonal's
/// midpoint lies closer to the surface, when both new triangles face the
/// way both old ones did (no fold) and creates no edge twice; no triangle takes part in
/// two flips. Returns the triangles changed.
pub(crate) fn flip_edges(
    tapes: &RegionTapes,
    positions: &[Vec3],
    triangles: &mut [[u32; 3]],
    edges: &[[u32; 2]],
) -> Vec<usize> {
    // Every directed edge, with its triangle and the corner opposite, of
    // the triangles that touch a corner of a triangle on one of `edges`
    // (all a flip reads, the other diagonal's existence included).
    let mut near = vec![false; positions.len()];
    for e in edges {
        near[e[0] as usize] = true;
        near[e[1] as usize] = true;
    }
    let touching = |near: &[bool], t: &[u32; 3]| t.iter().any(|&v| near[v as usize]);
    let mut wider = near.clone();
    for t in triangles.iter().filter(|t| touching(&near, t)) {
        for &v in t {
            wider[v as usize] = true;
        }
    }
    let mut half: Vec<([u32; 2], u32, u32)> = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        if touching(&wider, tri) {
            for i in 0..3 {
                half.push(([tri[i], tri[(i + 1) % 3]], t as u32, tri[(i + 2) % 3]));
            }
        }
    }
    half.sort_unstable_by_key(|h| h.0);
    let find = |e: [u32; 2]| {
        half.binary_search_by_key(&e, |h| h.0)
            .ok()
            .map(|i| (half[i].1 as usize, half[i].2))
    };
    let p = |v: u32| positions[v as usize];
    let normal = |t: [u32; 3]| (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
    let flips: Vec<Flip> = edges
        .iter()
        .filter_map(|&[a, b]| {
            let ((t1, c), (t2, d)) = (find([a, b])?, find([b, a])?);
            let exists = find([c, d]).is_some() || find([d, c]).is_some();
            if c == d || exists {
                return None;
            }
            let before = [normal([a, b, c]), normal([b, a, d])];
            let keeps = [[a, d, c], [d, b, c]].iter().all(|&t| {
                let n = normal(t);
                n.length_squared() > 0.0 && before.iter().all(|o| n.dot(*o) > 0.0)
            });
            keeps.then_some(Flip { t1, t2, a, b, c, d })
        })
        .collect();
    // The edge's midpoint; the other diagonal's and the new triangles'
    // centroids, which must all lie closer.
    let mut samples = Vec::with_capacity(4 * flips.len());
    for f in &flips {
        samples.push(0.5 * (p(f.a) + p(f.b)));
        samples.push(0.5 * (p(f.c) + p(f.d)));
        samples.push((p(f.a) + p(f.d) + p(f.c)) / 3.0);
        samples.push((p(f.d) + p(f.b) + p(f.c)) / 3.0);
    }
    let mut far = vec![0.0f32; samples.len()];
    field_distances(tapes, &samples, &mut far);
    let mut used = vec![false; triangles.len()];
    // Two flips of one call may not make the same diagonal (two quads with
    // the same opposite corners, as around a split vertex).
    let mut made_edges = std::collections::HashSet::new();
    let mut made = Vec::new();
    for (f, d) in flips.iter().zip(far.chunks(4)) {
        let closer = d[1..].iter().all(|x| *x < d[0]);
        if !closer || used[f.t1] || used[f.t2] || !made_edges.insert([f.c.min(f.d), f.c.max(f.d)]) {
            continue;
        }
        used[f.t1] = true;
        used[f.t2] = true;
        triangles[f.t1] = [f.a, f.d, f.c];
        triangles[f.t2] = [f.d, f.b, f.c];
        made.extend([f.t1, f.t2]);
    }
    made
}
