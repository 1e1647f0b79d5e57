//! The collapse loop: edges in a binary heap by quadric error, stale
//! entries recognised by the points' stamps and dropped when popped (lazy
//! invalidation, no decrease-key), each popped edge checked (kinds, link
//! condition, seam wedges, flips, the error bound) and collapsed. It runs
//! on one thread in heap order, so the result does not depend on the
//! thread count; only the first costs are computed in parallel. Nothing
//! is allocated per collapse: the neighbour lists and wedge maps live in
//! scratch buffers.

use geode_geo::glam::DVec3;
use geode_geo::ops::Quadric;
use rayon::prelude::*;

use super::heap::Heap;
use super::mesh::{Kind, Mesh, NONE};
use crate::ModelError;

/// When to stop and what may not happen.
pub(crate) struct Limits {
    /// Stop once this many triangles or fewer are left.
    pub target: usize,
    /// No collapse whose error (root mean squared distance to its planes)
    /// is larger.
    pub max_error: f64,
    /// No triangle may turn further than this (cosine between its normal
    /// before and after a collapse).
    pub min_cos: f64,
}

/// Float attribute values carried through collapses, a row per element.
pub(crate) struct Rows {
    pub width: usize,
    pub data: Vec<f32>,
}

impl Rows {
    /// Row `into` becomes `(1 - t) row(from) + t row(into)`.
    fn blend_into(&mut self, from: u32, into: u32, t: f32) {
        let w = self.width;
        if w == 0 || from == into {
            return;
        }
        let (f, i) = (from as usize * w, into as usize * w);
        for k in 0..w {
            let a = self.data[f + k];
            let b = &mut self.data[i + k];
            *b = (1.0 - t) * a + t * *b;
        }
    }
}

/// A heap entry, packed in a `u128` from the top: the cost's f32 bits
/// (a non-negative cost's bits order as the cost does), the edge's points
/// `a` and `b`, and the sum of their stamps when it was costed (it is
/// stale once that changes). Ties break by point indices, so the order is
/// total.
type Entry = u128;

/// One collapse: point `r` goes, `k` stays and moves to `p`.
#[derive(Clone, Copy)]
struct Choice {
    r: u32,
    k: u32,
    p: DVec3,
    cost: f64,
    /// The heap's key: the cost over the worst shape it leaves.
    priority: f64,
    quadric: Quadric,
}

/// What a reduction did.
pub(crate) struct Outcome {
    pub collapses: usize,
    /// The largest error of a collapse made (root mean squared distance).
    pub max_error: f64,
}

/// Scratch kept across collapses.
struct Scratch {
    mark: Vec<u32>,
    epoch: u32,
    neighbours: Vec<u32>,
    /// (wedge at r, wedge at k) of the triangles an edge collapse removes.
    map: Vec<(u32, u32)>,
}

pub(crate) fn run(
    mesh: &mut Mesh,
    points: &mut Rows,
    wedges: &mut Rows,
    limits: &Limits,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Outcome, ModelError> {
    let mut out = Outcome {
        collapses: 0,
        max_error: 0.0,
    };
    let mut s = Scratch {
        mark: vec![0; mesh.pos.len()],
        epoch: 0,
        neighbours: Vec::new(),
        map: Vec::new(),
    };
    let mut pops = 0usize;
    // A rejected edge is dropped until one of its points changes; a later
    // pass over every edge retries those whose surroundings changed.
    loop {
        if mesh.live <= limits.target {
            break;
        }
        let before = out.collapses;
        let mut heap = first_heap(mesh, cancel).ok_or(ModelError::Cancelled)?;
        while let Some(e) = heap.pop() {
            if mesh.live <= limits.target {
                break;
            }
            pops += 1;
            if pops.is_multiple_of(4096) && cancel() {
                return Err(ModelError::Cancelled);
            }
            let (a, b) = ((e >> 64) as u32, (e >> 32) as u32);
            if mesh.removed[a as usize]
                || mesh.removed[b as usize]
                || stamps(mesh, a, b) != e as u32
            {
                continue;
            }
            let Some(c) = choose(mesh, a, b) else {
                continue;
            };
            let error = (c.cost / c.quadric.weight().max(f64::MIN_POSITIVE)).sqrt();
            if error > limits.max_error || !allowed(mesh, &c, limits, &mut s) {
                continue;
            }
            apply(mesh, &c, points, wedges, &mut s);
            out.collapses += 1;
            out.max_error = out.max_error.max(error);
            push_around(mesh, c.k, &mut heap, &mut s);
        }
        if out.collapses == before {
            break;
        }
    }
    Ok(out)
}

fn stamps(mesh: &Mesh, a: u32, b: u32) -> u32 {
    mesh.stamp[a as usize].wrapping_add(mesh.stamp[b as usize])
}

fn entry(mesh: &Mesh, c: &Choice, a: u32, b: u32) -> Entry {
    let cost = (c.priority as f32).max(0.0);
    (u128::from(cost.to_bits()) << 96)
        | (u128::from(a) << 64)
        | (u128::from(b) << 32)
        | u128::from(stamps(mesh, a, b))
}

/// Every live edge's best collapse, costed in parallel, as a heap; None
/// if cancelled meanwhile.
fn first_heap(mesh: &Mesh, cancel: &(dyn Fn() -> bool + Sync)) -> Option<Heap> {
    let entries: Vec<Entry> = (0..mesh.pos.len() as u32)
        .into_par_iter()
        .with_min_len(1024)
        .map_init(Vec::new, |nbs, a| {
            // Every point asks: in a parallel map only the items that ask
            // are skipped once it says stop.
            if mesh.removed[a as usize] || cancel() {
                return Vec::new();
            }
            neighbours(mesh, a, nbs);
            nbs.iter()
                .filter(|&&b| b > a)
                .filter_map(|&b| choose(mesh, a, b).map(|c| entry(mesh, &c, a, b)))
                .collect::<Vec<_>>()
        })
        .flatten_iter()
        .collect();
    (!cancel()).then(|| Heap::from_vec(entries))
}

/// The distinct points sharing a live triangle with `a`, sorted.
fn neighbours(mesh: &Mesh, a: u32, out: &mut Vec<u32>) {
    out.clear();
    for c in mesh.corners(a) {
        let t = mesh.tris[c as usize / 3];
        if t[0] == NONE {
            continue;
        }
        let k = c as usize % 3;
        out.push(t[(k + 1) % 3]);
        out.push(t[(k + 2) % 3]);
    }
    out.sort_unstable();
    out.dedup();
}

/// How many live triangles hold edge `a b`, and whether it is a seam (two
/// triangles whose wedges differ at either end).
fn edge_info(mesh: &Mesh, a: u32, b: u32) -> (u32, bool) {
    let (mut count, mut first, mut seam) = (0, NONE, false);
    for c in mesh.corners(a) {
        let t = c as usize / 3;
        let tri = mesh.tris[t];
        if tri[0] == NONE || !tri.contains(&b) {
            continue;
        }
        count += 1;
        if first == NONE {
            first = t as u32;
        } else {
            let f = first as usize;
            seam |= mesh.wedge_in(f, a) != mesh.wedge_in(t, a)
                || mesh.wedge_in(f, b) != mesh.wedge_in(t, b);
        }
    }
    (count, count == 2 && seam)
}

/// The collapse edge `a b` would make, or None if its points' kinds allow
/// none. Two interior points meet at the quadric's minimiser (the best of
/// the ends and the midpoint when it has none, or it lies far off the
/// edge); otherwise a point moves onto the other along the edge.
fn choose(mesh: &Mesh, a: u32, b: u32) -> Option<Choice> {
    let (ka, kb) = (mesh.kind[a as usize], mesh.kind[b as usize]);
    let q = mesh.quadric[a as usize].sum(&mesh.quadric[b as usize]);
    let (pa, pb) = (mesh.pos[a as usize], mesh.pos[b as usize]);
    if ka == Kind::Interior && kb == Kind::Interior {
        let mid = 0.5 * (pa + pb);
        let p = match q.minimizer() {
            // Near the edge and inside the input's box: the last few
            // planes of a coarse mesh can place a point far outside.
            Some(p)
                if (p - mid).length_squared() <= 4.0 * pa.distance_squared(pb)
                    && p.cmpge(mesh.bounds[0]).all()
                    && p.cmple(mesh.bounds[1]).all() =>
            {
                p
            }
            _ => {
                let mut best = (q.eval(pa), pa);
                for p in [pb, mid] {
                    let e = q.eval(p);
                    if e < best.0 {
                        best = (e, p);
                    }
                }
                best.1
            }
        };
        // The nearer point survives, keeping what cannot be blended.
        let (r, k) = if p.distance_squared(pa) < p.distance_squared(pb) {
            (b, a)
        } else {
            (a, b)
        };
        let cost = q.eval(p);
        return Some(Choice {
            r,
            k,
            p,
            cost,
            priority: priority(mesh, r, k, p, cost),
            quadric: q,
        });
    }
    if ka == Kind::Locked && kb == Kind::Locked {
        return None;
    }
    let (count, seam) = edge_info(mesh, a, b);
    let can = |r: Kind, k: Kind| match r {
        Kind::Interior => true,
        Kind::Border => count == 1 && matches!(k, Kind::Border | Kind::Locked),
        Kind::Seam => seam && matches!(k, Kind::Seam | Kind::Locked),
        Kind::Locked => false,
    };
    let onto_b = can(ka, kb).then(|| (q.eval(pb), a, b, pb));
    let onto_a = can(kb, ka).then(|| (q.eval(pa), b, a, pa));
    let (cost, r, k, p) = match (onto_b, onto_a) {
        (Some(x), Some(y)) => {
            if y.0 < x.0 {
                y
            } else {
                x
            }
        }
        (Some(x), None) | (None, Some(x)) => x,
        (None, None) => return None,
    };
    Some(Choice {
        r,
        k,
        p,
        cost,
        priority: priority(mesh, r, k, p, cost),
        quadric: q,
    })
}

/// Below this shape quality (twice the area over the longest edge
/// squared: 0.87 equilateral) a collapse's cost grows as its worst
/// triangle thins: MeshLab's quality threshold, whose default is this.
const QUALITY: f64 = 0.3;

/// The order collapses are taken in, as MeshLab's quadric decimation
/// keys them: the cost (at least a trace of the mesh's scale, so flat
/// regions go best shapes first) over the worst quality among the
/// triangles left around `r` and `k` with both at `p`, capped at
/// [`QUALITY`]; a collapse leaving a triangle of no area comes last.
fn priority(mesh: &Mesh, r: u32, k: u32, p: DVec3, cost: f64) -> f64 {
    let mut worst = QUALITY;
    for v in [r, k] {
        for corner in mesh.corners(v) {
            let tri = mesh.tris[corner as usize / 3];
            if tri[0] == NONE || (tri.contains(&r) && tri.contains(&k)) {
                continue;
            }
            let at = tri.map(|q| {
                if q == r || q == k {
                    p
                } else {
                    mesh.pos[q as usize]
                }
            });
            let longest = (at[1] - at[0])
                .length_squared()
                .max((at[2] - at[1]).length_squared())
                .max((at[0] - at[2]).length_squared());
            let twice_area = (at[1] - at[0]).cross(at[2] - at[0]).length();
            if longest > 0.0 {
                worst = worst.min(twice_area / longest);
            }
        }
    }
    cost.max(mesh.cost_floor) / worst.max(f64::MIN_POSITIVE)
}

/// Whether collapse `c` keeps the mesh sound: the link condition (the
/// points share exactly the neighbours their shared triangles hold, so a
/// closed manifold stays one), wedges that map one to one (a seam stays
/// a seam) and no triangle flipped, folded or made degenerate.
fn allowed(mesh: &Mesh, c: &Choice, limits: &Limits, s: &mut Scratch) -> bool {
    let (r, k) = (c.r, c.k);
    s.epoch = s.epoch.wrapping_add(2);
    if s.epoch < 2 {
        s.mark.fill(0);
        s.epoch = 2;
    }
    let (on, seen) = (s.epoch, s.epoch + 1);
    let mut shared = 0;
    s.map.clear();
    for corner in mesh.corners(r) {
        let t = corner as usize / 3;
        let tri = mesh.tris[t];
        if tri[0] == NONE {
            continue;
        }
        if tri.contains(&k) {
            shared += 1;
            let pair = (mesh.wedge[corner as usize], mesh.wedge_in(t, k));
            match s.map.iter().find(|m| m.0 == pair.0) {
                Some(m) if m.1 != pair.1 => return false,
                Some(_) => {}
                None => s.map.push(pair),
            }
        }
        for p in tri {
            s.mark[p as usize] = on;
        }
    }
    let mut common = 0;
    for corner in mesh.corners(k) {
        let tri = mesh.tris[corner as usize / 3];
        if tri[0] == NONE {
            continue;
        }
        for p in tri {
            if p != r && p != k && s.mark[p as usize] == on {
                s.mark[p as usize] = seen;
                common += 1;
            }
        }
    }
    if shared == 0 || common != shared {
        return false;
    }
    // A closed fan of three would be left with two triangles back to
    // back (a tetrahedron collapses to a flat pair): its corner goes no
    // lower.
    for corner in mesh.corners(r) {
        let tri = mesh.tris[corner as usize / 3];
        if tri[0] == NONE || !tri.contains(&k) {
            continue;
        }
        let third = tri.into_iter().find(|&p| p != r && p != k);
        if third.is_some_and(|x| thin_fan(mesh, x)) {
            return false;
        }
    }
    // Every corner of r must know its wedge at k.
    for corner in mesh.corners(r) {
        let tri = mesh.tris[corner as usize / 3];
        if tri[0] != NONE && !s.map.iter().any(|m| m.0 == mesh.wedge[corner as usize]) {
            return false;
        }
    }
    let moves_k = c.p != mesh.pos[k as usize];
    turns_ok(mesh, r, k, c.p, limits.min_cos)
        && (!moves_k || turns_ok(mesh, k, r, c.p, limits.min_cos))
}

/// Whether `x` is a closed fan (interior or seam) of three triangles.
fn thin_fan(mesh: &Mesh, x: u32) -> bool {
    let closed = matches!(mesh.kind[x as usize], Kind::Interior | Kind::Seam);
    closed
        && mesh
            .corners(x)
            .filter(|&c| mesh.tris[c as usize / 3][0] != NONE)
            .take(4)
            .count()
            <= 3
}

/// Whether moving point `v` to `p` keeps every triangle of `v` without
/// `other` facing as it did (within `min_cos`) and not degenerate.
fn turns_ok(mesh: &Mesh, v: u32, other: u32, p: DVec3, min_cos: f64) -> bool {
    for corner in mesh.corners(v) {
        let tri = mesh.tris[corner as usize / 3];
        if tri[0] == NONE || tri.contains(&other) {
            continue;
        }
        let at = tri.map(|q| mesh.pos[q as usize]);
        let k = corner as usize % 3;
        let mut moved = at;
        moved[k] = p;
        let n0 = (at[1] - at[0]).cross(at[2] - at[0]);
        let n1 = (moved[1] - moved[0]).cross(moved[2] - moved[0]);
        let (l0, l1) = (n0.length(), n1.length());
        if l0 == 0.0 {
            continue;
        }
        let degenerate = l1.is_nan() || l1 <= 1e-12 * l0;
        if degenerate || n0.dot(n1) < min_cos * l0 * l1 {
            return false;
        }
    }
    true
}

/// Makes collapse `c` (checked by [`allowed`], whose wedge map is in `s`).
fn apply(mesh: &mut Mesh, c: &Choice, points: &mut Rows, wedges: &mut Rows, s: &mut Scratch) {
    let (r, k) = (c.r as usize, c.k as usize);
    let (pr, pk) = (mesh.pos[r], mesh.pos[k]);
    let d = pk - pr;
    // Where p lies from r (0) to k (1): the blend of their attributes.
    let t = if d.length_squared() > 0.0 {
        ((c.p - pr).dot(d) / d.length_squared()).clamp(0.0, 1.0) as f32
    } else {
        1.0
    };
    points.blend_into(c.r, c.k, t);
    if t < 1.0 {
        // Both points are interior, one wedge each.
        for &(wr, wk) in &s.map {
            wedges.blend_into(wr, wk, t);
        }
    }
    let mut corner = mesh.head[r];
    while corner != NONE {
        let next = mesh.next[corner as usize];
        let ti = corner as usize / 3;
        let tri = mesh.tris[ti];
        if tri[0] != NONE {
            if tri.contains(&c.k) {
                mesh.tris[ti] = [NONE; 3];
                mesh.live -= 1;
            } else {
                mesh.tris[ti][corner as usize % 3] = c.k;
                let w = mesh.wedge[corner as usize];
                let to = s.map.iter().find(|m| m.0 == w).expect("checked").1;
                mesh.wedge[corner as usize] = to;
                mesh.next[corner as usize] = mesh.head[k];
                mesh.head[k] = corner;
            }
        }
        corner = next;
    }
    mesh.head[r] = NONE;
    mesh.removed[r] = true;
    mesh.pos[k] = c.p;
    mesh.quadric[k] = c.quadric;
    mesh.stamp[k] = mesh.stamp[k].wrapping_add(1);
    prune(mesh, c.k);
}

/// Unlinks the corners of dead triangles from point `v`'s list.
fn prune(mesh: &mut Mesh, v: u32) {
    let mut prev = NONE;
    let mut corner = mesh.head[v as usize];
    while corner != NONE {
        let next = mesh.next[corner as usize];
        if mesh.tris[corner as usize / 3][0] == NONE {
            if prev == NONE {
                mesh.head[v as usize] = next;
            } else {
                mesh.next[prev as usize] = next;
            }
        } else {
            prev = corner;
        }
        corner = next;
    }
}

/// Pushes the edges around `k`, which just changed.
fn push_around(mesh: &Mesh, k: u32, heap: &mut Heap, s: &mut Scratch) {
    let mut nbs = std::mem::take(&mut s.neighbours);
    neighbours(mesh, k, &mut nbs);
    for &w in &nbs {
        let (a, b) = (k.min(w), k.max(w));
        if let Some(c) = choose(mesh, a, b) {
            heap.push(entry(mesh, &c, a, b));
        }
    }
    s.neighbours = nbs;
}
