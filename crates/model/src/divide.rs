//! Houdini's Divide SOP, convex polygons: every polygon that is not convex
//! (or has more than `max_edges` sides) becomes convex polygons over its
//! own corners, by Hertel and Mehlhorn's method: ear-clip the polygon in
//! its best-fit plane (its Newell normal), then remove diagonals, in the
//! order the ears were cut, wherever the two pieces beside one stay convex
//! at both its ends and within `max_edges` sides. Hertel-Mehlhorn gives at
//! most four times the fewest convex pieces; a triangle fan would give
//! n - 2. No point moves or is added, so area is unchanged and a closed
//! mesh stays closed (a diagonal is interior to its polygon). Pieces copy
//! their polygon's primitive attributes and groups, corners their vertex
//! attributes; polylines pass through.

use geode_geo::glam::{DVec2, DVec3};
use geode_geo::{Geometry, PrimKind};
use rayon::prelude::*;

use crate::carry::{self, copy, Blend, Plan};
use crate::fill::triangulate::{ear_clip, newell_normal, plane_basis};
use crate::ModelError;

#[derive(Clone, Debug)]
pub struct DivideOptions {
    /// Most sides a piece may have (at least 3).
    pub max_edges: u32,
}

impl Default for DivideOptions {
    fn default() -> Self {
        DivideOptions { max_edges: 64 }
    }
}

/// Convex pieces of `g`'s polygons (see the module doc).
pub fn convex_polygons(
    g: &Geometry,
    options: &DivideOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    carry::polygons_and_polylines(g, "divide")?;
    if options.max_edges < 3 {
        return Err(ModelError::Invalid(format!(
            "a convex piece needs at least 3 edges (max_edges is {})",
            options.max_edges
        )));
    }
    let max = options.max_edges as usize;
    let offsets = g.prim_offsets();
    let p = g.positions();
    let vp = g.vertex_points();
    // Per primitive: its pieces as corner lists (local corner numbers).
    let pieces: Vec<Vec<Vec<u32>>> = (0..g.num_prims())
        .into_par_iter()
        .map(|prim| {
            if prim % 4096 == 0 && cancel() {
                return Err(ModelError::Cancelled);
            }
            let (lo, hi) = (offsets[prim] as usize, offsets[prim + 1] as usize);
            let n = hi - lo;
            if g.prim_kinds()[prim] != PrimKind::Polygon || n <= 3 {
                return Ok(vec![(0..n as u32).collect()]);
            }
            let world: Vec<DVec3> = vp[lo..hi]
                .iter()
                .map(|&i| p[i as usize].as_dvec3())
                .collect();
            Ok(split(&world, max))
        })
        .collect::<Result<_, _>>()?;
    let mut plan = Plan {
        first_new_prim: usize::MAX,
        positions: p.to_vec(),
        point_sources: (0..p.len() as u32).map(copy).collect(),
        ..Plan::default()
    };
    for (prim, list) in pieces.iter().enumerate() {
        let lo = offsets[prim];
        for piece in list {
            for &c in piece {
                plan.vertex_points.push(vp[(lo + c) as usize]);
                plan.vertex_sources.push(copy(lo + c));
            }
            plan.prim_counts.push(piece.len() as u32);
            plan.prim_kinds.push(g.prim_kinds()[prim]);
            plan.prim_sources.push(prim as u32);
        }
    }
    carry::build(g, plan, "divide", cancel)
}

/// The convex pieces of one polygon (corner numbers, wound as it is).
fn split(world: &[DVec3], max: usize) -> Vec<Vec<u32>> {
    let n = world.len();
    let normal = newell_normal(world);
    let (u, v) = plane_basis(normal);
    let q: Vec<DVec2> = world
        .iter()
        .map(|x| DVec2::new(x.dot(u), x.dot(v)))
        .collect();
    let whole: Vec<u32> = (0..n as u32).collect();
    if normal.length() > 0.0 && n <= max && convex(&q, &whole) {
        return vec![whole];
    }
    let mut pieces: Vec<Option<Vec<u32>>> =
        ear_clip(&q).into_iter().map(|t| Some(t.to_vec())).collect();
    // Which piece holds each triangle (pieces merge into the lower).
    let mut owner: Vec<usize> = (0..pieces.len()).collect();
    let find = |owner: &Vec<usize>, mut k: usize| {
        while owner[k] != k {
            k = owner[k];
        }
        k
    };
    // Diagonals: the sides two triangles share, in ear order.
    let mut sides = std::collections::HashMap::new();
    let mut diagonals = Vec::new();
    for (t, tri) in pieces.iter().enumerate() {
        let tri = tri.as_ref().expect("all triangles to start");
        for j in 0..3 {
            let (a, b) = (tri[j], tri[(j + 1) % 3]);
            let key = (a.min(b), a.max(b));
            if let Some(other) = sides.insert(key, t) {
                diagonals.push((key, other, t));
            }
        }
    }
    for ((a, b), t0, t1) in diagonals {
        let (x, y) = (find(&owner, t0), find(&owner, t1));
        if x == y {
            continue;
        }
        let merged = merge(
            pieces[x].as_ref().expect("live"),
            pieces[y].as_ref().expect("live"),
            a,
            b,
        );
        if let Some(m) = merged.filter(|m| m.len() <= max && convex(&q, m)) {
            let (keep, gone) = (x.min(y), x.max(y));
            pieces[keep] = Some(m);
            pieces[gone] = None;
            owner[gone] = keep;
        }
    }
    pieces.into_iter().flatten().collect()
}

/// The polygon of pieces `x` and `y` joined along their shared side
/// `a`-`b` (None when they do not share it as one side each).
fn merge(x: &[u32], y: &[u32], a: u32, b: u32) -> Option<Vec<u32>> {
    // Rotate x to end ... -> a -> b? Find the side a-b (either way) in x.
    let nx = x.len();
    let i = (0..nx).find(|&i| {
        let (p, q) = (x[i], x[(i + 1) % nx]);
        (p == a && q == b) || (p == b && q == a)
    })?;
    let (from, to) = (x[i], x[(i + 1) % nx]);
    // In y the side runs to -> from; walk y from `from` round to `to`.
    let ny = y.len();
    let j = (0..ny).find(|&j| y[j] == to && y[(j + 1) % ny] == from)?;
    let mut out = Vec::with_capacity(nx + ny - 2);
    // x from `to` round to `from`, then y's corners strictly between.
    for k in 0..nx {
        out.push(x[(i + 1 + k) % nx]);
    }
    for k in 2..ny {
        out.push(y[(j + k) % ny]);
    }
    Some(out)
}

/// Whether the piece `corners` of ring `q` turns left (or straight) at
/// every corner.
fn convex(q: &[DVec2], corners: &[u32]) -> bool {
    let n = corners.len();
    let scale: f64 = corners
        .iter()
        .map(|&c| q[c as usize].abs().max_element())
        .fold(0.0, f64::max);
    let eps = 1e-12 * scale * scale;
    (0..n).all(|k| {
        let a = q[corners[k] as usize];
        let b = q[corners[(k + 1) % n] as usize];
        let c = q[corners[(k + 2) % n] as usize];
        (b - a).perp_dot(c - b) >= -eps
    })
}

/// Houdini's Divide "brick polygons": every polygon cut by the planes
/// `offset + k size` across each axis (x, then y, then z), so each piece
/// lies in one cell of the grid. Polygons are first made convex (as
/// above, without a side limit), so every cut splits one convex piece
/// into two. A cut point is made once per edge and plane (keyed by the
/// edge's two points and the plane), so neighbours share it and a closed
/// mesh stays closed; it is placed on its plane exactly. It blends its
/// edge's two points; where an end is itself a cut point, the source
/// point nearer that end stands for it (interior attributes are so
/// approximate, unlike Houdini's, which interpolates within the face).
pub fn bricker(
    g: &Geometry,
    size: geode_geo::glam::Vec3,
    offset: geode_geo::glam::Vec3,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    carry::polygons_and_polylines(g, "divide")?;
    if !(size.is_finite() && size.min_element() > 0.0 && offset.is_finite()) {
        return Err(ModelError::Invalid(format!(
            "brick size must be positive on every axis (got {size})"
        )));
    }
    let convex = convex_polygons(
        g,
        &DivideOptions {
            max_edges: u32::MAX,
        },
        cancel,
    )?;
    let mut bricks = Bricks {
        plan: Plan {
            first_new_prim: usize::MAX,
            positions: convex.positions().to_vec(),
            point_sources: (0..convex.num_points() as u32).map(copy).collect(),
            ..Plan::default()
        },
        cuts: std::collections::HashMap::new(),
        size: size.as_dvec3(),
        offset: offset.as_dvec3(),
    };
    let offsets = convex.prim_offsets();
    let vp = convex.vertex_points();
    for prim in 0..convex.num_prims() {
        if prim % 4096 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        let (lo, hi) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        let corners: Vec<(u32, Blend)> = (lo..hi).map(|v| (vp[v], copy(v as u32))).collect();
        if convex.prim_kinds()[prim] != PrimKind::Polygon {
            bricks.emit(&corners, PrimKind::Polyline, prim as u32);
            continue;
        }
        let mut pieces = vec![corners];
        for axis in 0..3 {
            pieces = pieces
                .into_iter()
                .flat_map(|piece| bricks.slice(piece, axis))
                .collect();
        }
        for piece in &pieces {
            bricks.emit(piece, PrimKind::Polygon, prim as u32);
        }
    }
    // The convex pieces carry every attribute of g: they are the source.
    carry::build(&convex, bricks.plan, "divide", cancel)
}

/// A convex piece's corners: output point and vertex blend.
type Piece = Vec<(u32, Blend)>;

/// The bricker's output under construction.
struct Bricks {
    plan: Plan,
    /// Cut points by (low point, high point, axis, plane).
    cuts: std::collections::HashMap<(u32, u32, usize, i64), u32>,
    size: DVec3,
    offset: DVec3,
}

impl Bricks {
    fn emit(&mut self, corners: &[(u32, Blend)], kind: PrimKind, prim: u32) {
        for &(p, b) in corners {
            self.plan.vertex_points.push(p);
            self.plan.vertex_sources.push(b);
        }
        self.plan.prim_counts.push(corners.len() as u32);
        self.plan.prim_kinds.push(kind);
        self.plan.prim_sources.push(prim);
    }

    fn coord(&self, p: u32, axis: usize) -> f64 {
        self.plan.positions[p as usize][axis] as f64
    }

    /// A convex piece cut by every plane across `axis` it spans.
    fn slice(&mut self, piece: Piece, axis: usize) -> Vec<Piece> {
        let (lo, hi) = piece.iter().fold((f64::MAX, f64::MIN), |(l, h), &(p, _)| {
            let x = self.coord(p, axis);
            (l.min(x), h.max(x))
        });
        let (s, o) = (self.size[axis], self.offset[axis]);
        let first = ((lo - o) / s).floor() as i64 + 1;
        let mut out = Vec::new();
        let mut rest = piece;
        let mut k = first;
        while o + k as f64 * s < hi {
            let plane = o + k as f64 * s;
            if plane > lo {
                let (below, above) = self.cut(&rest, axis, k, plane);
                if below.len() >= 3 {
                    out.push(below);
                }
                rest = above;
                if rest.len() < 3 {
                    return out;
                }
            }
            k += 1;
        }
        out.push(rest);
        out
    }

    /// A convex piece's parts below and above a plane.
    fn cut(&mut self, piece: &[(u32, Blend)], axis: usize, k: i64, plane: f64) -> (Piece, Piece) {
        let (mut below, mut above) = (Vec::new(), Vec::new());
        let n = piece.len();
        for j in 0..n {
            let (a, va) = piece[j];
            let (b, vb) = piece[(j + 1) % n];
            let (sa, sb) = (self.coord(a, axis) - plane, self.coord(b, axis) - plane);
            if sa <= 0.0 {
                below.push((a, va));
            }
            if sa >= 0.0 {
                above.push((a, va));
            }
            if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                let t = sa / (sa - sb);
                let m = self.cut_point(a, b, axis, k, plane);
                let vm = blend_of(va, vb, t as f32);
                below.push((m, vm));
                above.push((m, vm));
            }
        }
        (below, above)
    }

    /// The cut point of edge `a`-`b` on plane `k` of `axis`, made once.
    fn cut_point(&mut self, a: u32, b: u32, axis: usize, k: i64, plane: f64) -> u32 {
        let (lo, hi) = (a.min(b), a.max(b));
        if let Some(&m) = self.cuts.get(&(lo, hi, axis, k)) {
            return m;
        }
        // From the lower point, so both neighbours compute the same point.
        let (x, y) = (
            self.plan.positions[lo as usize].as_dvec3(),
            self.plan.positions[hi as usize].as_dvec3(),
        );
        let t = (plane - x[axis]) / (y[axis] - x[axis]);
        let mut at = x.lerp(y, t);
        at[axis] = plane;
        let src = blend_of(
            self.plan.point_sources[lo as usize],
            self.plan.point_sources[hi as usize],
            t as f32,
        );
        let m = self.plan.positions.len() as u32;
        self.plan.positions.push(at.as_vec3());
        self.plan.point_sources.push(src);
        self.cuts.insert((lo, hi, axis, k), m);
        m
    }
}

/// The blend `t` of the way from blend `a` to blend `b`, each end stood
/// for by its nearer source element when it is itself a blend.
fn blend_of(a: Blend, b: Blend, t: f32) -> Blend {
    let near = |(x, y, s): Blend| if s < 0.5 { x } else { y };
    (near(a), near(b), t)
}
