//! Limit positions and normals of the vertices of a refined (all-quad)
//! level: positions by the scheme's limit masks (`scheme.rs`), normals by
//! the matching tangent masks (Biermann et al. across irregular creases).

use geode_geo::glam::DVec3;
use rayon::prelude::*;

use super::level::{is_sharp, Level};
use super::refine::Rule;
use super::scheme::{self, Term};

/// The ring of a manifold vertex in counter-clockwise order: the far end of
/// each edge, and of each quad the corner opposite the vertex (face `i` lies
/// between edges `i` and `i + 1`); `None` where the faces do not form one
/// fan of quads.
fn ring(l: &Level, v: u32) -> Option<(Vec<u32>, Vec<u32>)> {
    let faces = l.vertex_faces.row(v as usize);
    let mut quads: Vec<(u32, u32, u32)> = Vec::with_capacity(faces.len()); // (next, opposite, prev)
    for &f in faces {
        let r = l.faces.row(f as usize);
        if r.len() != 4 {
            return None;
        }
        let k = r.iter().position(|&x| x == v)?;
        quads.push((r[(k + 1) % 4], r[(k + 2) % 4], r[(k + 3) % 4]));
    }
    let n = quads.len();
    if n == 0 {
        return None;
    }
    // The first face: one no other face leads into (a boundary start), else the first.
    let start = (0..n)
        .find(|&i| !quads.iter().any(|q| q.2 == quads[i].0))
        .unwrap_or(0);
    let (mut edges, mut opposite) = (vec![quads[start].0], Vec::with_capacity(n));
    let mut used = vec![false; n];
    let mut cur = start;
    loop {
        used[cur] = true;
        opposite.push(quads[cur].1);
        let trailing = quads[cur].2;
        match (0..n).find(|&j| !used[j] && quads[j].0 == trailing) {
            Some(j) => {
                edges.push(trailing);
                cur = j;
            }
            None => {
                if trailing != edges[0] {
                    edges.push(trailing); // boundary: the trailing edge ends the fan
                }
                break;
            }
        }
    }
    if used.iter().any(|u| !u) || edges.len() != l.vertex_edges.row(v as usize).len() {
        return None;
    }
    Some((edges, opposite))
}

fn rule_at(l: &Level, v: usize) -> (Rule, Vec<u32>) {
    let sharp: Vec<u32> = l
        .vertex_edges
        .row(v)
        .iter()
        .filter(|&&e| is_sharp(l.edge_sharpness[e as usize]))
        .map(|&e| l.other_end(e, v as u32))
        .collect();
    (Rule::of(l.vertex_sharpness[v], sharp.len()), sharp)
}

/// Limit positions of every vertex of an all-quad level.
pub fn limit_positions(l: &Level, p: &[DVec3]) -> Vec<DVec3> {
    (0..l.num_vertices)
        .into_par_iter()
        .map(|v| {
            if l.vertex_edges.row(v).is_empty() {
                return p[v];
            }
            let (rule, _) = rule_at(l, v);
            let (edges, faces) = (l.vertex_edges.row(v), l.vertex_faces.row(v));
            let sharp = |k: usize| is_sharp(l.edge_sharpness[edges[k] as usize]);
            let mut acc = DVec3::ZERO;
            scheme::limit_point(rule, edges.len(), faces.len(), sharp, 1.0, &mut |t, w| {
                let q = match t {
                    Term::Vertex => v,
                    Term::EdgeEnd(k) => l.other_end(edges[k], v as u32) as usize,
                    Term::Opposite(k) => {
                        let r = l.faces.row(faces[k] as usize);
                        let c = r.iter().position(|&x| x == v as u32).unwrap_or(0);
                        r[(c + 2) % r.len()] as usize
                    }
                    Term::FacePoint(_) => return,
                };
                acc += p[q] * w;
            });
            acc
        })
        .collect()
}

/// The unit mean of the (Newell) normals of the faces at `v`: the normal
/// where no limit mask applies (zero when they cancel).
pub fn mean_face_normal(l: &Level, p: &[DVec3], v: u32) -> DVec3 {
    let mut n = DVec3::ZERO;
    for &f in l.vertex_faces.row(v as usize) {
        let r = l.faces.row(f as usize);
        for k in 0..r.len() {
            n += p[r[k] as usize].cross(p[r[(k + 1) % r.len()] as usize]);
        }
    }
    n.normalize_or_zero()
}

/// The two limit tangents of an interior smooth vertex of valence `n`
/// from its ordered ring (edge ends `e`, opposite face corners `f`): the
/// first along edge 0, the second a quarter turn on.
fn smooth_tangents(
    n: usize,
    e: impl Fn(usize) -> DVec3,
    f: impl Fn(usize) -> DVec3,
) -> (DVec3, DVec3) {
    let theta = std::f64::consts::TAU / n as f64;
    let lambda = 5.0 / 16.0
        + (theta.cos() + (theta * 0.5).cos() * (2.0 * (9.0 + theta.cos())).sqrt()) / 16.0;
    let fs = if n == 4 {
        1.0
    } else {
        1.0 / (4.0 * lambda - 1.0)
    };
    let (mut t1, mut t2) = (DVec3::ZERO, DVec3::ZERO);
    for i in 0..n {
        let (c0, c1) = ((i as f64 * theta).cos(), ((i + 1) as f64 * theta).cos());
        let (s0, s1) = ((i as f64 * theta).sin(), ((i + 1) as f64 * theta).sin());
        t1 += e(i) * (4.0 * c0) + f(i) * (fs * (c0 + c1));
        t2 += e(i) * (4.0 * s0) + f(i) * (fs * (s0 + s1));
    }
    (t1, t2)
}

/// The orthonormal limit frame (normal, first tangent, second tangent) of
/// interior smooth vertex `v` with the first tangent pointing along its
/// edge to `toward`; `flip` points it the opposite way. The normal follows
/// the face winding. None where `v` is not an interior smooth vertex of
/// quads or `toward` is not a neighbour.
pub fn limit_frame(l: &Level, p: &[DVec3], v: u32, toward: u32, flip: bool) -> Option<[DVec3; 3]> {
    let (edges, faces) = ring(l, v)?;
    let n = faces.len();
    if n < 3 || edges.len() != n || rule_at(l, v as usize).0 != Rule::Smooth {
        return None;
    }
    let k = edges.iter().position(|&x| x == toward)?;
    let (t1, t2) = smooth_tangents(
        n,
        |i| p[edges[(i + k) % n] as usize],
        |i| p[faces[(i + k) % n] as usize],
    );
    let normal = t1.cross(t2).normalize_or_zero();
    let tu = if flip { -t1 } else { t1 }.normalize_or_zero();
    (normal != DVec3::ZERO && tu != DVec3::ZERO).then(|| [normal, tu, normal.cross(tu)])
}

/// Unit limit normals (tangent masks on the ordered ring; where a vertex
/// has no single fan of quads, the mean of its faces' normals).
pub fn limit_normals(l: &Level, p: &[DVec3]) -> Vec<DVec3> {
    (0..l.num_vertices)
        .into_par_iter()
        .map(|v| {
            let fallback = || mean_face_normal(l, p, v as u32);
            let Some((edges, faces)) = ring(l, v as u32) else {
                return fallback();
            };
            let pv = p[v];
            let e = |i: usize| p[edges[i] as usize];
            let f = |i: usize| p[faces[i] as usize];
            let (rule, sharp_ends) = rule_at(l, v);
            let (t1, t2) = match rule {
                Rule::Smooth | Rule::Dart if faces.len() > 2 && edges.len() == faces.len() => {
                    smooth_tangents(faces.len(), e, f)
                }
                Rule::Crease => {
                    // The crease ends' places in the ordered ring.
                    let sharp: Vec<usize> = (0..edges.len())
                        .filter(|&i| sharp_ends.contains(&edges[i]))
                        .collect();
                    if sharp.len() != 2 {
                        return fallback();
                    }
                    let (c0, c1) = (sharp[0], sharp[1]);
                    let t1 = (e(c0) - e(c1)) * 0.5;
                    let interior = c1 - c0 - 1;
                    let t2 = match interior {
                        0 => e(c0) * 3.0 + e(c1) * 3.0 - pv * 6.0,
                        1 => {
                            pv * (-4.0 / 6.0)
                                + (e(c0) + e(c1)) * (-1.0 / 6.0)
                                + e(c0 + 1) * (4.0 / 6.0)
                                + (f(c0) + f(c0 + 1)) * (1.0 / 6.0)
                        }
                        _ => {
                            let k = (interior + 1) as f64;
                            let theta = std::f64::consts::PI / k;
                            let denom = 1.0 / (k * (3.0 + theta.cos()));
                            let r = (theta.cos() + 1.0) / theta.sin();
                            let mut t = pv * (4.0 * r * (theta.cos() - 1.0) * denom)
                                + (e(c0) + e(c1)) * (-r * (1.0 + 2.0 * theta.cos()) * denom)
                                + f(c0) * (theta.sin() * denom);
                            for i in 1..interior + 1 {
                                let (si, si1) =
                                    ((i as f64 * theta).sin(), ((i + 1) as f64 * theta).sin());
                                t += e(c0 + i) * (4.0 * si * denom)
                                    + f(c0 + i) * ((si + si1) * denom);
                            }
                            t
                        }
                    };
                    (t1, t2)
                }
                _ if edges.len() >= 2 => (e(0) - pv, e(1) - pv),
                _ => return fallback(),
            };
            let n = t1.cross(t2).normalize_or_zero();
            if n == DVec3::ZERO {
                fallback()
            } else {
                n
            }
        })
        .collect()
}
