//! Arbitrary-topology attachments (the thesis's section 2.4): cylinder
//! hsplines (limbs) joined to rectangular regions of a parent hspline. The
//! region's faces are cut out, each limb's rim row is bound to the ring of
//! parent vertices around its hole (the corners get five edges; limbs side
//! by side give six), and the combined control mesh is one Catmull-Clark
//! surface. Its refinement is a hierarchical subdivision surface: at level
//! k every vertex that is a level-k vertex of one of the hsplines gets that
//! hspline's offset, in the frame of the refined (still unedited) limit
//! surface there. Away from the joint Catmull-Clark refinement is the
//! B-spline refinement and that frame is the hspline's own, so there the
//! result is each hspline exactly; across the joint both surfaces' levels
//! and offsets act on one smooth surface.

use geode_geo::glam::{DQuat, DVec3};

use super::{Hspline, HsplineError, Topology};
use crate::subd::{
    limit_frame, limit_normals, limit_positions, mean_face_normal, plan, refine_topology,
    refine_values, Level, Rows,
};

/// Parent faces `u0..u1` x `v0..v1` (half-open, level-0 face indices).
pub type Region = ((usize, usize), (usize, usize));

/// A cylinder hspline joined at its first rows to a parent region.
#[derive(Clone, Debug, PartialEq)]
pub struct Limb {
    pub surface: Hspline,
    pub region: Region,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AttachError {
    #[error("limb {0} is not a cylinder (only a cylinder's rim wraps a hole)")]
    NotCylinder(usize),
    #[error("limb {limb}: region u {u0}..{u1} v {v0}..{v1} is empty or leaves the parent's {nu} x {nv} control vertices (an open side keeps its outer row of vertices, and a wrapped side cannot be cut all round)")]
    BadRegion {
        limb: usize,
        u0: usize,
        u1: usize,
        v0: usize,
        v1: usize,
        nu: usize,
        nv: usize,
    },
    #[error("limb {limb} has {around} vertices around but its region's rim has {ring} (2 x (region rows + region columns))")]
    RingMismatch {
        limb: usize,
        around: usize,
        ring: usize,
    },
    #[error("the regions of limbs {0} and {1} share faces")]
    Overlap(usize, usize),
    #[error("{0} subdivision levels would pass 64M faces")]
    TooLarge(usize),
    #[error(transparent)]
    Hspline(#[from] HsplineError),
}

/// The attached surface: limit points with normals, quads with uv per
/// corner and the surface each came from (0 the parent, then the limbs),
/// the hspline vertex each point is (surface, i, j at the final level),
/// and the level-0 Catmull-Clark control mesh.
#[derive(Clone, Debug, Default)]
pub struct Attached {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    pub quads: Vec<[u32; 4]>,
    pub uvs: Vec<[f64; 2]>,
    pub surface: Vec<u32>,
    pub origin: Vec<(u32, u32, u32)>,
    pub cage_points: Vec<DVec3>,
    pub cage_quads: Vec<[u32; 4]>,
}

/// One hspline's vertices in the combined mesh: its native grid (every
/// Catmull-Clark vertex of its faces, open sides keeping the vertices
/// outside the surface's domain) mapped to mesh vertices.
struct Native<'a> {
    h: &'a Hspline,
    wrap: (bool, bool),
    is_limb: bool,
    nu: usize,
    nv: usize,
    map: Vec<Option<u32>>,
}

impl Native<'_> {
    fn step(&self, k: usize, d: isize, n: usize, wraps: bool) -> Option<usize> {
        let x = k as isize + d;
        if wraps {
            Some(x.rem_euclid(n as isize) as usize)
        } else {
            (0..n as isize).contains(&x).then_some(x as usize)
        }
    }

    fn at(&self, i: usize, j: usize, di: isize, dj: isize) -> Option<u32> {
        let a = self.step(i, di, self.nu, self.wrap.0)?;
        let b = self.step(j, dj, self.nv, self.wrap.1)?;
        self.map[a * self.nv + b]
    }

    /// The native grid one level finer over the child level of `l`.
    fn refine(&mut self, l: &Level) {
        let size = |n: usize, wraps: bool| if wraps { 2 * n } else { 2 * n - 1 };
        let (nu, nv) = (size(self.nu, self.wrap.0), size(self.nv, self.wrap.1));
        let (nvert, nface) = (l.num_vertices as u32, l.faces.len() as u32);
        let mut map = vec![None; nu * nv];
        for ci in 0..nu {
            for cj in 0..nv {
                let (a, b) = (ci / 2, cj / 2);
                map[ci * nv + cj] =
                    match (ci % 2, cj % 2) {
                        (0, 0) => self.at(a, b, 0, 0),
                        (1, 0) => edge(l, self.at(a, b, 0, 0), self.at(a, b, 1, 0))
                            .map(|e| nvert + nface + e),
                        (0, 1) => edge(l, self.at(a, b, 0, 0), self.at(a, b, 0, 1))
                            .map(|e| nvert + nface + e),
                        _ => face(
                            l,
                            [
                                self.at(a, b, 0, 0),
                                self.at(a, b, 1, 0),
                                self.at(a, b, 1, 1),
                                self.at(a, b, 0, 1),
                            ],
                        )
                        .map(|f| nvert + f),
                    };
            }
        }
        (self.nu, self.nv, self.map) = (nu, nv, map);
    }

    /// Native index of hspline index `k` at `level` (an open side keeps
    /// 2^level - 1 vertices outside the hspline's own grid).
    fn native(k: usize, level: usize, wraps: bool) -> usize {
        if wraps {
            k
        } else {
            k + (1 << level) - 1
        }
    }
}

fn edge(l: &Level, a: Option<u32>, b: Option<u32>) -> Option<u32> {
    let (a, b) = (a?, b?);
    l.vertex_edges
        .row(a as usize)
        .iter()
        .copied()
        .find(|&e| l.other_end(e, a) == b)
}

fn face(l: &Level, c: [Option<u32>; 4]) -> Option<u32> {
    let c = [c[0]?, c[1]?, c[2]?, c[3]?];
    l.vertex_faces
        .row(c[0] as usize)
        .iter()
        .copied()
        .find(|&f| {
            let r = l.faces.row(f as usize);
            r.len() == 4 && c.iter().all(|x| r.contains(x))
        })
}

/// The parent vertices around a region, in the direction of the parent
/// faces' edges along it (u0 side along +v, then the v1 side along +u,
/// the u1 side along -v, the v0 side along -u).
fn ring(((u0, u1), (v0, v1)): Region) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    out.extend((v0..v1).map(|j| (u0, j)));
    out.extend((u0..u1).map(|i| (i, v1)));
    out.extend((v0 + 1..=v1).rev().map(|j| (u1, j)));
    out.extend((u0 + 1..=u1).rev().map(|i| (i, v0)));
    out
}

fn check_region(parent: &Hspline, limb: &Limb, index: usize) -> Result<(), AttachError> {
    let ((u0, u1), (v0, v1)) = limb.region;
    let (nu, nv) = (parent.base.nu, parent.base.nv);
    let (wu, wv) = parent.wrap();
    let fits = |a: usize, b: usize, n: usize, wraps: bool| {
        a < b
            && if wraps {
                b - a < n - 1 && b < 2 * n
            } else {
                a >= 1 && b + 2 <= n
            }
    };
    if !(fits(u0, u1, nu, wu) && fits(v0, v1, nv, wv)) {
        return Err(AttachError::BadRegion {
            limb: index,
            u0,
            u1,
            v0,
            v1,
            nu,
            nv,
        });
    }
    if limb.surface.topology != Topology::Cylinder {
        return Err(AttachError::NotCylinder(index));
    }
    let ring = 2 * (u1 - u0 + v1 - v0);
    if limb.surface.base.nv != ring {
        return Err(AttachError::RingMismatch {
            limb: index,
            around: limb.surface.base.nv,
            ring,
        });
    }
    Ok(())
}

/// Which limb column sits on ring place 0, and the rigid motion (rotation,
/// then translation) that carries the limb there: its rim centre onto the
/// ring's centre, its axis along the parent's normal there, turned about it
/// to fit its rim to the ring best. Without `place` the limb stays and
/// only the column is chosen.
fn fit(ring: &[DVec3], limb: &Hspline, place: bool) -> (usize, DQuat, DVec3) {
    let nv = limb.base.nv;
    let row = |i: usize| &limb.base.points[i * nv..(i + 1) * nv];
    let centre = |p: &[DVec3]| p.iter().sum::<DVec3>() / p.len() as f64;
    let (rim, ring_centre) = (centre(row(1)), centre(ring));
    // The ring runs against the parent's normal (Newell), the rim against
    // the limb's axis.
    let newell = |p: &[DVec3]| {
        (0..p.len())
            .map(|k| p[k].cross(p[(k + 1) % p.len()]))
            .sum::<DVec3>()
    };
    let normal = -newell(ring).normalize_or_zero();
    let axis = (centre(row(limb.base.nu - 2)) - rim).normalize_or_zero();
    let arc = if place && normal != DVec3::ZERO && axis != DVec3::ZERO {
        DQuat::from_rotation_arc(axis, normal)
    } else {
        DQuat::IDENTITY
    };
    let mut best = (f64::INFINITY, 0, DQuat::IDENTITY, DVec3::ZERO);
    for shift in 0..nv {
        let column = |k: usize| row(1)[(k + shift) % nv];
        let (rotation, translation) = if place {
            // The best turn about the normal (2-D Procrustes).
            let (mut dot, mut cross) = (0.0, 0.0);
            for (k, target) in ring.iter().enumerate() {
                let a = arc * (column(k) - rim);
                let b = *target - ring_centre;
                let (a, b) = (a - normal * a.dot(normal), b - normal * b.dot(normal));
                dot += a.dot(b);
                cross += normal.dot(a.cross(b));
            }
            let twist = DQuat::from_axis_angle(normal, cross.atan2(dot));
            let rotation = twist * arc;
            (rotation, ring_centre - rotation * rim)
        } else {
            (DQuat::IDENTITY, DVec3::ZERO)
        };
        let err: f64 = ring
            .iter()
            .enumerate()
            .map(|(k, t)| (rotation * column(k) + translation - *t).length_squared())
            .sum();
        if err < best.0 - 1e-12 {
            best = (err, shift, rotation, translation);
        }
    }
    (best.1, best.2, best.3)
}

/// Joins `limbs` to `parent` and refines the combined surface to the finest
/// hspline level plus `subdivisions`, returning its limit surface. With
/// `place` each limb is first moved rigidly onto its region (its offsets,
/// being local, follow).
pub fn attach(
    parent: &Hspline,
    limbs: &[Limb],
    place: bool,
    subdivisions: usize,
) -> Result<Attached, AttachError> {
    for (k, limb) in limbs.iter().enumerate() {
        check_region(parent, limb, k)?;
    }
    let (pu, pv) = (parent.base.nu, parent.base.nv);
    let pwrap = parent.wrap();
    let wrapped = |i: usize, n: usize| i % n;
    // Faces and interior vertices each region removes.
    let mut hole_of = vec![None::<usize>; pu * pv];
    let mut inside = vec![false; pu * pv];
    for (k, limb) in limbs.iter().enumerate() {
        let ((u0, u1), (v0, v1)) = limb.region;
        for i in u0..u1 {
            for j in v0..v1 {
                let f = wrapped(i, pu) * pv + wrapped(j, pv);
                if let Some(other) = hole_of[f] {
                    return Err(AttachError::Overlap(other, k));
                }
                hole_of[f] = Some(k);
                if i > u0 && j > v0 {
                    inside[f] = true;
                }
            }
        }
    }
    // Level-0 vertices: the parent's (less region interiors), then each
    // limb's rows from the second on (the first row drops, the second is
    // bound to the ring).
    let mut points = Vec::new();
    let mut parent_map = vec![None; pu * pv];
    for (k, slot) in parent_map.iter_mut().enumerate() {
        if !inside[k] {
            *slot = Some(points.len() as u32);
            points.push(parent.base.points[k]);
        }
    }
    let mut placed = Vec::with_capacity(limbs.len());
    let mut limb_maps = Vec::with_capacity(limbs.len());
    for limb in limbs {
        let ring_at = ring(limb.region);
        let ring_ids: Vec<u32> = ring_at
            .iter()
            .map(|&(i, j)| parent_map[wrapped(i, pu) * pv + wrapped(j, pv)].expect("rim vertex"))
            .collect();
        let ring_points: Vec<DVec3> = ring_ids.iter().map(|&v| points[v as usize]).collect();
        let (shift, rotation, translation) = fit(&ring_points, &limb.surface, place);
        let mut h = limb.surface.clone();
        for p in h.base.points.iter_mut() {
            *p = rotation * *p + translation;
        }
        let (nu, nv) = (h.base.nu, h.base.nv);
        let mut map = vec![None; nu * nv];
        for (k, &id) in ring_ids.iter().enumerate() {
            map[nv + (k + shift) % nv] = Some(id);
        }
        for (k, slot) in map.iter_mut().enumerate().skip(2 * nv) {
            *slot = Some(points.len() as u32);
            points.push(h.base.points[k]);
        }
        placed.push(h);
        limb_maps.push(map);
    }
    let mut natives = vec![Native {
        h: parent,
        wrap: pwrap,
        is_limb: false,
        nu: pu,
        nv: pv,
        map: parent_map,
    }];
    for (h, map) in placed.iter().zip(limb_maps) {
        natives.push(Native {
            h,
            wrap: (false, true),
            is_limb: true,
            nu: h.base.nu,
            nv: h.base.nv,
            map,
        });
    }
    // Level-0 faces: every cell of every native grid whose corners exist,
    // except the parent's holes and a limb's dropped first row.
    let mut quads: Vec<[u32; 4]> = Vec::new();
    for (s, n) in natives.iter().enumerate() {
        let cu = if n.wrap.0 { n.nu } else { n.nu - 1 };
        let cv = if n.wrap.1 { n.nv } else { n.nv - 1 };
        for i in 0..cu {
            for j in 0..cv {
                if s == 0 && hole_of[i * pv + j].is_some() {
                    continue;
                }
                let c = [
                    n.at(i, j, 0, 0),
                    n.at(i, j, 1, 0),
                    n.at(i, j, 1, 1),
                    n.at(i, j, 0, 1),
                ];
                if let [Some(a), Some(b), Some(c), Some(d)] = c {
                    quads.push([a, b, c, d]);
                }
            }
        }
    }
    let levels = natives.iter().map(|n| n.h.levels()).max().unwrap_or(1) - 1 + subdivisions;
    if levels > 12 || (quads.len() as u64) << (2 * levels as u64) > 1 << 26 {
        return Err(AttachError::TooLarge(levels));
    }
    let mut level = Level::from_faces(
        points.len(),
        Rows {
            offsets: (0..=quads.len() as u32).map(|f| 4 * f).collect(),
            items: quads.iter().flatten().copied().collect(),
        },
        |_| 0.0,
    );
    level.sharpen_boundaries(false);
    let cage_points = points.clone();
    let cage_quads = quads;
    let mut flat: Vec<f64> = points.iter().flat_map(|p| p.to_array()).collect();
    for k in 1..=levels {
        let child = refine_topology(&level, false);
        let pl = plan(&level, &child, false);
        flat = refine_values(&level, &child, &pl, &flat, 3);
        for n in natives.iter_mut() {
            n.refine(&level);
        }
        level = child;
        apply_offsets(&natives, &level, k, &mut flat);
    }
    Ok(output(
        &natives,
        &level,
        &flat,
        levels,
        cage_points,
        cage_quads,
    ))
}

/// Adds every hspline's level-`k` offsets to the refined mesh, each in the
/// limit frame of the unedited refined surface at its vertex.
fn apply_offsets(natives: &[Native], level: &Level, k: usize, flat: &mut [f64]) {
    let points: Vec<DVec3> = flat
        .chunks(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect();
    let mut moves = Vec::new();
    for n in natives {
        let Some(overlay) = n.h.overlays.get(k - 1) else {
            continue;
        };
        let (nu, nv) = n.h.grid_size(k).expect("a level with an overlay");
        for i in overlay.u.0..overlay.u.1 {
            for j in overlay.v.0..overlay.v.1 {
                let o = overlay.offsets[overlay.index(i, j).expect("inside")];
                // A limb's first two rows are the dropped row and the rim,
                // which belongs to the parent.
                if o == DVec3::ZERO || (n.is_limb && i < 2) || !n.h.movable(k, i, j) {
                    continue;
                }
                let ci = Native::native(i, k, n.wrap.0);
                let cj = Native::native(j, k, n.wrap.1);
                let Some(v) = n.at(ci, cj, 0, 0) else {
                    continue; // cut out by a region
                };
                // As in the hspline, a vertex beyond an open edge of the
                // domain takes the frame at that edge.
                let inward = |x: usize, size: usize, wraps: bool| {
                    if wraps {
                        0
                    } else {
                        (x.clamp(1, size - 2) as isize) - x as isize
                    }
                };
                let (di, dj) = (inward(i, nu, n.wrap.0), inward(j, nv, n.wrap.1));
                let at = n.at(ci, cj, di, dj).unwrap_or(v);
                let frame = match (n.at(ci, cj, di + 1, dj), n.at(ci, cj, di - 1, dj)) {
                    (Some(t), _) => limit_frame(level, &points, at, t, false),
                    (None, Some(t)) => limit_frame(level, &points, at, t, true),
                    _ => None,
                }
                .unwrap_or_else(|| fallback_frame(level, &points, at));
                let [nrm, tu, tv] = frame;
                moves.push((v, nrm * o.x + tu * o.y + tv * o.z));
            }
        }
    }
    for (v, d) in moves {
        let at = 3 * v as usize;
        for (c, x) in d.to_array().into_iter().enumerate() {
            flat[at + c] += x;
        }
    }
}

/// A frame where the limit masks do not apply: the mean face normal and
/// the direction to the first neighbour.
fn fallback_frame(level: &Level, p: &[DVec3], v: u32) -> [DVec3; 3] {
    let n = mean_face_normal(level, p, v);
    let n = if n == DVec3::ZERO { DVec3::Z } else { n };
    let to = level
        .vertex_edges
        .row(v as usize)
        .first()
        .map(|&e| p[level.other_end(e, v) as usize] - p[v as usize])
        .unwrap_or(DVec3::X);
    let tu = (to - n * to.dot(n)).normalize_or(n.any_orthonormal_vector());
    [n, tu, n.cross(tu)]
}

/// The limit surface over each hspline's domain, welded where surfaces meet.
fn output(
    natives: &[Native],
    level: &Level,
    flat: &[f64],
    levels: usize,
    cage_points: Vec<DVec3>,
    cage_quads: Vec<[u32; 4]>,
) -> Attached {
    let points: Vec<DVec3> = flat
        .chunks(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect();
    let limit = limit_positions(level, &points);
    let normals = limit_normals(level, &points);
    let mut out = Attached {
        cage_points,
        cage_quads,
        ..Attached::default()
    };
    let mut index = vec![u32::MAX; points.len()];
    let outside = (1usize << levels) - 1;
    for (s, n) in natives.iter().enumerate() {
        // Cells over the domain: from hspline index 1 to n - 2 on open sides.
        let range = |size: usize, wraps: bool| {
            if wraps {
                (0, size)
            } else {
                (outside + 1, size - outside - 2)
            }
        };
        let (ru, rv) = (range(n.nu, n.wrap.0), range(n.nv, n.wrap.1));
        let param = |k: usize, (lo, hi): (usize, usize), wraps: bool| {
            if wraps {
                k as f64 / hi as f64
            } else {
                (k - lo) as f64 / (hi - lo) as f64
            }
        };
        let hspline_index = |k: usize, wraps: bool| if wraps { k } else { k - outside };
        for i in ru.0..ru.1 {
            for j in rv.0..rv.1 {
                let corners: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
                let ids = corners.map(|(a, b)| n.at(i, j, a as isize, b as isize));
                if face(level, ids).is_none() {
                    continue;
                }
                let mut quad = [0u32; 4];
                for (c, &(a, b)) in corners.iter().enumerate() {
                    let v = ids[c].expect("a face's corner") as usize;
                    if index[v] == u32::MAX {
                        index[v] = out.positions.len() as u32;
                        out.positions.push(limit[v]);
                        out.normals.push(normals[v]);
                        let (ci, cj) = (i + a, j + b);
                        out.origin.push((
                            s as u32,
                            hspline_index(ci % n.nu, n.wrap.0) as u32,
                            hspline_index(cj % n.nv, n.wrap.1) as u32,
                        ));
                    }
                    quad[c] = index[v];
                    out.uvs
                        .push([param(i + a, ru, n.wrap.0), param(j + b, rv, n.wrap.1)]);
                }
                out.quads.push(quad);
                out.surface.push(s as u32);
            }
        }
    }
    out
}

#[cfg(test)]
#[path = "attach_tests.rs"]
mod tests;
