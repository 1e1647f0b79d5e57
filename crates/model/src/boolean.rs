//! Booleans of closed meshes: union, intersection, subtraction and
//! shatter (A cut into its pieces outside and inside B).
//!
//! The exact, robust part is `boolmesh` (a pure-Rust implementation of
//! manifold's algorithm: symbolic perturbation, so coplanar faces and
//! touching edges and vertices give a closed manifold result). This module
//! is geode's side of it: the inputs are triangulated, each corner carries
//! the number of the triangle it came from through the boolean, and the
//! output's attributes are read back from there. A new point on a cut lies
//! inside a source triangle, so its point and vertex attributes are that
//! triangle's corners weighted by its barycentric coordinates (integers,
//! strings and matrices take the nearest corner's); primitive attributes
//! and groups are the source polygon's. The result is triangles.
//!
//! Groups mark where each face came from, as Houdini's Boolean names them:
//! `a_inside_b`, `a_outside_b`, `b_inside_a`, `b_outside_a` (primitives),
//! and `seam` (the points where faces of A meet faces of B: geode has no
//! edge groups, so the seam's edges are those between two seam points).

use std::sync::{mpsc, Arc};
use std::time::Duration;

use boolmesh::prelude::{compute_boolean, Manifold, OpType};
use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, TypeInfo};

use crate::ModelError;

/// What a boolean keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BooleanOp {
    /// Everything inside A or B.
    Union,
    /// What is inside both.
    Intersect,
    /// A with B taken away.
    Subtract,
    /// A cut by B into two closed pieces: outside B (`piece` 0) and
    /// inside it (`piece` 1).
    Shatter,
}

impl BooleanOp {
    pub const NAMES: &'static [&'static str] = &["union", "intersect", "subtract", "shatter"];

    pub fn from_name(name: &str) -> Option<BooleanOp> {
        Some(match name {
            "union" => BooleanOp::Union,
            "intersect" => BooleanOp::Intersect,
            "subtract" => BooleanOp::Subtract,
            "shatter" => BooleanOp::Shatter,
            _ => return None,
        })
    }
}

/// Bytes a boolean of meshes of `triangles` triangles in all is expected
/// to hold at its peak (measured on sphere pairs: boolmesh's half-edge
/// meshes, colliders and the output's columns), so a caller can refuse a
/// request before it is made.
pub fn estimate_bytes(triangles: usize) -> f64 {
    1200.0 * triangles as f64
}

/// The boolean `op` of closed meshes `a` and `b`; `cancel` is polled
/// between the phases (the boolean itself runs to its end).
pub fn boolean(
    a: &Geometry,
    b: &Geometry,
    op: BooleanOp,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let sources = Sources::new(a, b, cancel)?;
    let check = || {
        if cancel() {
            Err(ModelError::Cancelled)
        } else {
            Ok(())
        }
    };
    check()?;
    let ma = sources.manifold(Side::A)?;
    let mb = sources.manifold(Side::B)?;
    check()?;
    let (ma, mb) = (Arc::new(ma), Arc::new(mb));
    let run = |op: OpType| apart(Arc::clone(&ma), Arc::clone(&mb), op, cancel);
    let output = |r: Option<Manifold<f64>>, op, piece| match r {
        Some(r) => sources.output(&r, op, piece),
        None => Ok(Geometry::new()),
    };
    match op {
        BooleanOp::Union => output(run(OpType::Add)?, op, None),
        BooleanOp::Intersect => output(run(OpType::Intersect)?, op, None),
        BooleanOp::Subtract => output(run(OpType::Subtract)?, op, None),
        BooleanOp::Shatter => {
            let outside = output(run(OpType::Subtract)?, BooleanOp::Subtract, Some(0))?;
            check()?;
            let inside = output(run(OpType::Intersect)?, BooleanOp::Intersect, Some(1))?;
            ops::merge(&[&outside, &inside]).map_err(|e| ModelError::Failed {
                op: "shatter",
                why: e.to_string(),
            })
        }
    }
}

/// boolmesh's boolean on a thread of its own, so that a cancelled cook
/// returns at once (the thread finishes unobserved and its result is
/// dropped) and a panic in it is this boolean's error, not the process's.
/// An empty result (disjoint solids intersected), which boolmesh reports
/// as an error about its empty position list, is `None`.
fn apart(
    a: Arc<Manifold<f64>>,
    b: Arc<Manifold<f64>>,
    op: OpType,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Option<Manifold<f64>>, ModelError> {
    const POLL: Duration = Duration::from_millis(10);
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("boolean".into())
        .spawn(move || {
            let _ = tx.send(compute_boolean(&a, &b, op));
        })
        .map_err(|e| ModelError::Failed {
            op: "boolean",
            why: format!("no thread for it: {e}"),
        })?;
    loop {
        match rx.recv_timeout(POLL) {
            Ok(Ok(r)) => return Ok(Some(r)),
            Ok(Err(why)) if why.contains("empty") => return Ok(None),
            Ok(Err(why)) => return Err(ModelError::Failed { op: "boolean", why }),
            Err(mpsc::RecvTimeoutError::Timeout) if cancel() => return Err(ModelError::Cancelled),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(ModelError::Failed {
                    op: "boolean",
                    why: "it stopped on these inputs (a fault in boolmesh)".into(),
                })
            }
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    A,
    B,
}

/// Both inputs triangulated and merged: A's triangles first, then B's.
/// Triangle `t` of the merge is what a corner's value names.
struct Sources {
    both: Geometry,
    /// A's triangles (B's are numbered from here).
    a_triangles: usize,
    a_points: usize,
    /// Per triangle of the merge, the triangle across each edge `k`
    /// (from corner k to k + 1), `NONE` at an open or shared edge.
    across: Vec<[u32; 3]>,
}

const NONE: u32 = u32::MAX;

/// Steps a point location walks before it settles for where it is.
const MAX_WALK: usize = 4096;

impl Sources {
    fn new(
        a: &Geometry,
        b: &Geometry,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Sources, ModelError> {
        let ta = triangles_of(a, "A", cancel)?;
        let tb = triangles_of(b, "B", cancel)?;
        let (a_triangles, a_points) = (ta.num_prims(), ta.num_points());
        let both = ops::merge(&[&ta, &tb]).map_err(|e| ModelError::Failed {
            op: "boolean",
            why: e.to_string(),
        })?;
        let across = across_edges(&both);
        Ok(Sources {
            both,
            a_triangles,
            a_points,
            across,
        })
    }

    fn corners(&self, t: usize) -> [DVec3; 3] {
        let p = self.both.prim_points(t);
        [0, 1, 2].map(|k| self.both.positions()[p[k] as usize].as_dvec3())
    }

    /// The source triangle holding `p` and its weights there, walking from
    /// `hint` across edges to coplanar neighbours. boolmesh retriangulates
    /// each flat region of the inputs as a whole, so the triangle a face
    /// names is only somewhere in the same flat region as the face.
    fn locate(&self, hint: usize, p: DVec3) -> (usize, [f32; 3]) {
        let mut t = hint;
        let mut w = barycentric(p, self.corners(t));
        for _ in 0..MAX_WALK {
            let j = (1..3).fold(0, |b, j| if w[j] < w[b] { j } else { b });
            if w[j] >= -1e-9 {
                break;
            }
            // Across the edge opposite the most negative corner.
            let next = self.across[t][(j + 1) % 3];
            if next == NONE || !coplanar(self.corners(t), self.corners(next as usize)) {
                break;
            }
            t = next as usize;
            w = barycentric(p, self.corners(t));
        }
        (t, clamped(w))
    }

    fn side_of(&self, triangle: usize) -> Side {
        if triangle < self.a_triangles {
            Side::A
        } else {
            Side::B
        }
    }

    /// One side as a boolmesh manifold, each corner's value its triangle's
    /// number in the merge.
    fn manifold(&self, side: Side) -> Result<Manifold<f64>, ModelError> {
        let (prims, points, name) = match side {
            Side::A => (0..self.a_triangles, 0..self.a_points, "A"),
            Side::B => (
                self.a_triangles..self.both.num_prims(),
                self.a_points..self.both.num_points(),
                "B",
            ),
        };
        let base = points.start;
        let pos: Vec<f64> = self.both.positions()[points]
            .iter()
            .flat_map(|p| p.to_array().map(f64::from))
            .collect();
        let mut idx = Vec::with_capacity(prims.len() * 3);
        let mut vals = Vec::with_capacity(prims.len() * 3);
        for t in prims {
            for &p in self.both.prim_points(t) {
                idx.push(p as usize - base);
                vals.push(t as f64);
            }
        }
        Manifold::new_with_values(&pos, &idx, &vals).map_err(|why| ModelError::NotClosed {
            input: name,
            why: format!("{why} ({})", boundary_report(&self.both, side, self)),
        })
    }

    /// The geometry of boolmesh's result `r`: triangles, attributes from
    /// their sources, the origin groups; `piece` numbers a shatter piece.
    fn output(
        &self,
        r: &Manifold<f64>,
        op: BooleanOp,
        piece: Option<i32>,
    ) -> Result<Geometry, ModelError> {
        let failed = |why: String| ModelError::Failed { op: "boolean", why };
        let mut triangles = Vec::with_capacity(r.hs.len() / 3);
        let mut sources = Vec::with_capacity(r.hs.len() / 3);
        // Per output corner: the source triangle's points and weights.
        let mut corners = Vec::with_capacity(r.hs.len());
        for (t, h) in r.hs.chunks_exact(3).enumerate() {
            let tri = [h[0].tail, h[1].tail, h[2].tail];
            if tri.iter().any(|&v| v >= r.ps.len()) {
                continue;
            }
            let hint = |k: usize| {
                let s = r.vals.get(3 * t + k).copied().unwrap_or(-1.0).round();
                if (0.0..self.both.num_prims() as f64).contains(&s) {
                    Ok(s as usize)
                } else {
                    Err(failed(format!("a face lost its source ({s})")))
                }
            };
            let at = tri.map(|v| ours(r.ps[v]));
            let (s, _) = self.locate(hint(0)?, (at[0] + at[1] + at[2]) / 3.0);
            for (k, &corner) in at.iter().enumerate() {
                let (c, w) = self.locate(hint(k)?, corner);
                let cp = self.both.prim_points(c);
                corners.push(([cp[0], cp[1], cp[2]], w, c));
            }
            triangles.push(tri.map(|v| v as u32));
            sources.push(s as u32);
        }
        let positions: Vec<Vec3> = r.ps.iter().map(|p| ours(*p).as_vec3()).collect();
        let mut out =
            Geometry::from_triangles(positions, &triangles).map_err(|e| failed(e.to_string()))?;
        self.carry_points(&mut out, &triangles, &corners)?;
        self.carry_vertices(&mut out, &corners)?;
        self.carry_prims(&mut out, &sources)?;
        self.mark_origins(&mut out, &triangles, &sources, op)?;
        if let Some(piece) = piece {
            let n = out.num_prims();
            let piece_attr = Attribute::from_data(AttribData::Int(vec![piece; n]), TypeInfo::None);
            out.set_attrib(AttribClass::Primitive, "piece", piece_attr)
                .map_err(|e| failed(e.to_string()))?;
        }
        Ok(out)
    }

    /// Point attributes (P aside: the output's own) from the first corner
    /// that uses each point, in triangle order.
    fn carry_points(
        &self,
        out: &mut Geometry,
        triangles: &[[u32; 3]],
        corners: &[([u32; 3], [f32; 3], usize)],
    ) -> Result<(), ModelError> {
        let mut first = vec![u32::MAX; out.num_points()];
        for (k, &p) in triangles.iter().flatten().enumerate() {
            if first[p as usize] == u32::MAX {
                first[p as usize] = k as u32;
            }
        }
        let items: Vec<([u32; 3], [f32; 3])> = first
            .iter()
            .map(|&k| match corners.get(k as usize) {
                Some((pts, w, _)) => (*pts, *w),
                None => ([0; 3], [1.0, 0.0, 0.0]),
            })
            .collect();
        for (name, attr) in self.both.attribs(AttribClass::Point).iter() {
            if name == "P" {
                continue;
            }
            set(out, AttribClass::Point, name, attr.mix3(&items))?;
        }
        for (name, group) in self.both.point_groups() {
            let members = items.iter().map(|(pts, w)| {
                let best = (1..3).fold(0, |b, j| if w[j] > w[b] { j } else { b });
                group.contains(pts[best] as usize)
            });
            out.set_point_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        Ok(())
    }

    /// Vertex attributes: each corner weighted over its source triangle's
    /// three vertices.
    fn carry_vertices(
        &self,
        out: &mut Geometry,
        corners: &[([u32; 3], [f32; 3], usize)],
    ) -> Result<(), ModelError> {
        let table = self.both.attribs(AttribClass::Vertex);
        if table.num_attribs() == 0 {
            return Ok(());
        }
        let items: Vec<([u32; 3], [f32; 3])> = corners
            .iter()
            .map(|(_, w, s)| {
                let r = self.both.prim_vertex_range(*s);
                ([r.start as u32, r.start as u32 + 1, r.start as u32 + 2], *w)
            })
            .collect();
        for (name, attr) in table.iter() {
            set(out, AttribClass::Vertex, name, attr.mix3(&items))?;
        }
        Ok(())
    }

    /// Primitive attributes and groups of each face's source polygon.
    fn carry_prims(&self, out: &mut Geometry, sources: &[u32]) -> Result<(), ModelError> {
        for (name, attr) in self.both.attribs(AttribClass::Primitive).iter() {
            set(out, AttribClass::Primitive, name, attr.gather(sources))?;
        }
        for (name, group) in self.both.prim_groups() {
            let members = sources.iter().map(|&s| group.contains(s as usize));
            out.set_prim_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        for (name, attr) in self.both.attribs(AttribClass::Detail).iter() {
            set(out, AttribClass::Detail, name, attr.clone())?;
        }
        Ok(())
    }

    /// The origin groups (which side each face came from and where it
    /// lies relative to the other) and the seam's points.
    fn mark_origins(
        &self,
        out: &mut Geometry,
        triangles: &[[u32; 3]],
        sources: &[u32],
        op: BooleanOp,
    ) -> Result<(), ModelError> {
        // A face of A kept by a union or a subtraction lies outside B; by
        // an intersection, inside. B's faces: outside A in a union, inside
        // it otherwise (a subtraction keeps B's faces inside A, reversed).
        let (a_group, b_group) = match op {
            BooleanOp::Union => ("a_outside_b", "b_outside_a"),
            BooleanOp::Intersect => ("a_inside_b", "b_inside_a"),
            BooleanOp::Subtract | BooleanOp::Shatter => ("a_outside_b", "b_inside_a"),
        };
        let from_a: Vec<bool> = sources
            .iter()
            .map(|&s| self.side_of(s as usize) == Side::A)
            .collect();
        for name in ["a_inside_b", "a_outside_b", "b_inside_a", "b_outside_a"] {
            let members = from_a
                .iter()
                .map(|&a| if a { name == a_group } else { name == b_group });
            out.set_prim_group(name, Group::from_flags(members))
                .map_err(|e| ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })?;
        }
        let mut touched = vec![0u8; out.num_points()];
        for (tri, &a) in triangles.iter().zip(&from_a) {
            for &p in tri {
                touched[p as usize] |= if a { 1 } else { 2 };
            }
        }
        out.set_point_group("seam", Group::from_flags(touched.iter().map(|&t| t == 3)))
            .map_err(|e| ModelError::Failed {
                op: "boolean",
                why: e.to_string(),
            })
    }
}

fn set(
    out: &mut Geometry,
    class: AttribClass,
    name: &str,
    attr: Attribute,
) -> Result<(), ModelError> {
    out.set_attrib(class, name, attr)
        .map_err(|e| ModelError::Failed {
            op: "boolean",
            why: e.to_string(),
        })
}

/// Input `name` as triangles: polygons only (a boolean needs solids).
fn triangles_of(
    g: &Geometry,
    name: &'static str,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    if let Some(k) = g.prim_kinds().iter().position(|k| *k != PrimKind::Polygon) {
        return Err(ModelError::NotClosed {
            input: name,
            why: format!(
                "primitive {k} is a {}: a boolean takes closed polygon meshes",
                g.prim_kinds()[k].name()
            ),
        });
    }
    if g.num_prims() == 0 {
        return Err(ModelError::NotClosed {
            input: name,
            why: "it has no polygons".into(),
        });
    }
    ops::triangulate_with(g, None, cancel).ok_or(ModelError::Cancelled)
}

/// Why a side is not a closed manifold: its open and over-shared edges.
fn boundary_report(both: &Geometry, side: Side, s: &Sources) -> String {
    let prims = match side {
        Side::A => 0..s.a_triangles,
        Side::B => s.a_triangles..both.num_prims(),
    };
    let tris: Vec<[u32; 3]> = prims
        .map(|t| {
            let p = both.prim_points(t);
            [p[0], p[1], p[2]]
        })
        .collect();
    // Only on the error path: the topology's report counts the edges.
    let report = Geometry::from_triangles(both.positions().to_vec(), &tris)
        .map(|g| g.topology().manifold_report(&g))
        .unwrap_or_default();
    format!(
        "{} open edges, {} edges shared by more than two faces",
        report.boundary_edges, report.non_manifold_edges
    )
}

/// A boolmesh vector (its own glam's) as ours.
fn ours(p: boolmesh::Vec3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

/// Barycentric weights of `p` (projected into the plane of `abc`); a
/// degenerate triangle gives its first corner.
fn barycentric(p: DVec3, [a, b, c]: [DVec3; 3]) -> [f64; 3] {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
    let (d20, d21) = (v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if den.abs() <= f64::EPSILON * d00 * d11 {
        return [1.0, 0.0, 0.0];
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    [1.0 - v - w, v, w]
}

/// Weights clamped into the triangle (a point of a cut lies on it up to
/// rounding) and summing to one.
fn clamped(w: [f64; 3]) -> [f32; 3] {
    let mut x = w.map(|t| t.max(0.0));
    let sum: f64 = x.iter().sum();
    if sum <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    x.iter_mut().for_each(|t| *t /= sum);
    x.map(|t| t as f32)
}

/// Whether two triangles lie in one plane (up to the inputs' f32
/// rounding, relative to their size).
fn coplanar(s: [DVec3; 3], t: [DVec3; 3]) -> bool {
    let n = (s[1] - s[0]).cross(s[2] - s[0]);
    let m = (t[1] - t[0]).cross(t[2] - t[0]);
    let (nl, ml) = (n.length(), m.length());
    if nl == 0.0 || ml == 0.0 {
        return false;
    }
    let size = (s[1] - s[0]).length().max((s[2] - s[0]).length());
    n.dot(m) >= (1.0 - 1e-6) * nl * ml
        && t.iter()
            .all(|q| (n / nl).dot(*q - s[0]).abs() <= 1e-5 * size)
}

/// Each triangle's neighbour across each edge: edges sorted by their
/// points (in parallel, stable, so any thread count gives the same), a
/// pair of triangles per edge used exactly twice.
fn across_edges(g: &Geometry) -> Vec<[u32; 3]> {
    use rayon::prelude::*;
    let n = g.num_prims();
    let mut edges: Vec<(u32, u32, u32)> = (0..n)
        .flat_map(|t| {
            let p = g.prim_points(t);
            (0..3).map(move |k| {
                let (a, b) = (p[k], p[(k + 1) % 3]);
                (a.min(b), a.max(b), (t * 3 + k) as u32)
            })
        })
        .collect();
    edges.par_sort_unstable();
    let mut across = vec![[NONE; 3]; n];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && (edges[j].0, edges[j].1) == (edges[i].0, edges[i].1) {
            j += 1;
        }
        if j - i == 2 {
            let (x, y) = (edges[i].2 as usize, edges[i + 1].2 as usize);
            across[x / 3][x % 3] = (y / 3) as u32;
            across[y / 3][y % 3] = (x / 3) as u32;
        }
        i = j;
    }
    across
}
