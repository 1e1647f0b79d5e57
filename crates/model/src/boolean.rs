//! Booleans of closed meshes: union, intersection, subtraction and
//! shatter (A cut into its pieces outside and inside B).
//!
//! The exact, robust part is manifold (the C++ library, through
//! `geode-manifold`: symbolic perturbation, so coplanar faces and touching
//! edges and vertices give a closed manifold result). This module is
//! geode's side of it: the inputs are triangulated, each triangle is given
//! its number as manifold's face number, and every output triangle comes
//! back naming the source triangle it lies in; the output's attributes are
//! read back from there. A new point on a cut lies inside a source
//! triangle, so its point and vertex attributes are that triangle's corners
//! weighted by its barycentric coordinates (integers, strings and matrices
//! take the nearest corner's); primitive attributes and groups are the
//! source polygon's. The result is triangles.
//!
//! Groups mark where each face came from, as Houdini's Boolean names them:
//! `a_inside_b`, `a_outside_b`, `b_inside_a`, `b_outside_a` (primitives),
//! and `seam` (the points where faces of A meet faces of B: geode has no
//! edge groups, so the seam's edges are those between two seam points).

use std::sync::mpsc;

use rayon::prelude::*;
use std::time::Duration;

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, TypeInfo};
use geode_manifold::{Mesh, Op, Solid};

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
/// to hold at its peak (measured on sphere pairs: manifold's half-edge
/// meshes and colliders, the merged sources and the output's columns), so
/// a caller can refuse a request before it is made.
pub fn estimate_bytes(triangles: usize) -> f64 {
    1200.0 * triangles as f64
}

/// The boolean `op` of closed meshes `a` and `b`; `cancel` is polled
/// between the phases and while manifold works (which it cannot be
/// interrupted in: a cancelled boolean returns at once and its thread
/// finishes unobserved).
pub fn boolean(
    a: &Geometry,
    b: &Geometry,
    op: BooleanOp,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    if let Some(g) = with_an_empty_side(a, b, op) {
        return Ok(g);
    }
    let sources = Sources::new(a, b, cancel)?;
    let check = || ModelError::unless_cancelled(cancel);
    check()?;
    let (ia, ib) = (sources.solid_input(Side::A), sources.solid_input(Side::B));
    check()?;
    let ops = match op {
        BooleanOp::Union => vec![Op::Union],
        BooleanOp::Intersect => vec![Op::Intersect],
        BooleanOp::Subtract => vec![Op::Subtract],
        BooleanOp::Shatter => vec![Op::Subtract, Op::Intersect],
    };
    let meshes = apart(ia, ib, ops, cancel).map_err(|e| match e {
        Apart::NotClosed(side, why) => ModelError::NotClosed {
            input: if side == Side::A { "A" } else { "B" },
            why: format!("{why} ({})", boundary_report(&sources.both, side, &sources)),
        },
        Apart::Model(e) => e,
    })?;
    match op {
        BooleanOp::Shatter => {
            let outside = sources.output(&meshes[0], Some(BooleanOp::Subtract), Some(0))?;
            check()?;
            let inside = sources.output(&meshes[1], Some(BooleanOp::Intersect), Some(1))?;
            ops::merge(&[&outside, &inside]).map_err(|e| ModelError::Failed {
                op: "shatter",
                why: e.to_string(),
            })
        }
        _ => sources.output(&meshes[0], Some(op), None),
    }
}

/// `g`'s connected pieces (closed meshes, wound outward) joined where
/// they overlap: manifold's union of its pieces, so overlapping closed
/// shells become one boundary. Attributes carry as a boolean's do (no
/// origin groups); the result is triangles.
pub fn union_pieces(
    g: &Geometry,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    if g.num_prims() == 0 {
        return Ok(g.clone());
    }
    let t = triangles_of(g, "input", cancel)?;
    let sources = Sources {
        a_triangles: t.num_prims(),
        a_points: t.num_points(),
        both: t,
    };
    let input = sources.solid_input(Side::A);
    let threads = rayon::current_num_threads();
    let work = move || {
        let solid = match Solid::new(&input.positions, &input.triangles, &input.faces, 1, threads) {
            Ok(s) => s,
            Err(e) => return (Err(Apart::NotClosed(Side::A, e)), vec![]),
        };
        let one = geode_manifold::union_pieces(&solid, threads);
        let mesh = one
            .as_ref()
            .map_err(Clone::clone)
            .and_then(|s| s.mesh(threads));
        let keep: Vec<Solid> = std::iter::once(solid).chain(one.ok()).collect();
        (
            mesh.map_err(|e| {
                Apart::Model(ModelError::Failed {
                    op: "union pieces",
                    why: e.to_string(),
                })
            }),
            keep,
        )
    };
    let mesh = on_own_thread(cancel, work)?.map_err(|e| match e {
        Apart::NotClosed(side, why) => ModelError::NotClosed {
            input: "input",
            why: format!("{why} ({})", boundary_report(&sources.both, side, &sources)),
        },
        Apart::Model(e) => e,
    })?;
    sources.output(&mesh, None, None)
}

/// One side's solid as arrays (owned, to cross to the boolean's thread).
struct SolidInput {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    faces: Vec<u32>,
}

/// Why the boolean's thread stopped short.
enum Apart {
    /// A side manifold refused as a solid.
    NotClosed(Side, geode_manifold::ManifoldError),
    Model(ModelError),
}

/// manifold's work (both solids built at once, then each boolean of
/// `ops` and its mesh) on a thread of its own, so that a cancelled cook
/// returns at once (manifold cannot be interrupted: the thread finishes
/// unobserved and its result is dropped) and a fault in it is this
/// boolean's error.
fn apart(
    a: SolidInput,
    b: SolidInput,
    ops: Vec<Op>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Mesh>, Apart> {
    // manifold's own threads (where it is built on TBB) are as many as
    // the cook's pool has.
    let threads = rayon::current_num_threads();
    // The solids are returned beside the meshes and dropped after the
    // meshes are sent, so the cook does not wait for manifold to free them.
    let work = move || -> (Result<Vec<Mesh>, Apart>, Vec<Solid>) {
        // Each side's source number orders the result's triangles (A's
        // first), whichever thread builds its solid first.
        let build = |i: &SolidInput, source| {
            Solid::new(&i.positions, &i.triangles, &i.faces, source, threads)
        };
        let (sa, sb) = if threads > 1 && !geode_manifold::parallel() {
            // Built serially, manifold is given a thread per side here.
            std::thread::scope(|s| {
                let sb = s.spawn(|| build(&b, 2));
                let sa = build(&a, 1);
                let sb = sb.join().unwrap_or_else(|_| {
                    Err(geode_manifold::ManifoldError::Other(
                        "it stopped on B".into(),
                    ))
                });
                (sa, sb)
            })
        } else {
            (build(&a, 1), build(&b, 2))
        };
        drop((a, b));
        let (sa, sb) = match (sa, sb) {
            (Ok(sa), Ok(sb)) => (sa, sb),
            (Err(e), _) => return (Err(Apart::NotClosed(Side::A, e)), vec![]),
            (_, Err(e)) => return (Err(Apart::NotClosed(Side::B, e)), vec![]),
        };
        let mut results = Vec::with_capacity(ops.len());
        let meshes = ops
            .iter()
            .map(|&op| {
                let r = geode_manifold::boolean(&sa, &sb, op, threads)?;
                let mesh = r.mesh(threads);
                results.push(r);
                mesh
            })
            .collect::<Result<Vec<Mesh>, _>>()
            .map_err(|e| {
                Apart::Model(ModelError::Failed {
                    op: "boolean",
                    why: e.to_string(),
                })
            });
        results.extend([sa, sb]);
        (meshes, results)
    };
    on_own_thread(cancel, work).map_err(Apart::Model)?
}

/// `work` on a thread of its own, polling `cancel` while it runs: a
/// cancelled wait returns at once and the thread finishes unobserved (what
/// it returns is dropped there); a thread that dies is this operation's
/// error. A result is returned as a pair so that the second part (big
/// solids) is freed on that thread after the first is handed over.
fn on_own_thread<T: Send + 'static, K: Send + 'static>(
    cancel: &(dyn Fn() -> bool + Sync),
    work: impl FnOnce() -> (T, K) + Send + 'static,
) -> Result<T, ModelError> {
    const POLL: Duration = Duration::from_millis(10);
    let failed = |why: String| ModelError::Failed { op: "boolean", why };
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("boolean".into())
        .spawn(move || {
            let (result, keep) = work();
            let _ = tx.send(result);
            drop(keep);
        })
        .map_err(|e| failed(format!("no thread for it: {e}")))?;
    loop {
        match rx.recv_timeout(POLL) {
            Ok(result) => return Ok(result),
            Err(mpsc::RecvTimeoutError::Timeout) if cancel() => return Err(ModelError::Cancelled),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(failed("it stopped on these inputs".into()))
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
/// Triangle `t` of the merge is manifold's face number `t`.
struct Sources {
    both: Geometry,
    /// A's triangles (B's are numbered from here).
    a_triangles: usize,
    a_points: usize,
}

impl Sources {
    fn new(
        a: &Geometry,
        b: &Geometry,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Sources, ModelError> {
        let (ta, tb) = rayon::join(
            || triangles_of(a, "A", cancel),
            || triangles_of(b, "B", cancel),
        );
        let (ta, tb) = (ta?, tb?);
        let (a_triangles, a_points) = (ta.num_prims(), ta.num_points());
        let both = ops::merge(&[&ta, &tb]).map_err(|e| ModelError::Failed {
            op: "boolean",
            why: e.to_string(),
        })?;
        Ok(Sources {
            both,
            a_triangles,
            a_points,
        })
    }

    /// Source triangle `t`'s points and their positions.
    fn corners(&self, positions: &[Vec3], t: usize) -> ([u32; 3], [DVec3; 3]) {
        let p = self.both.prim_points(t);
        let points = [p[0], p[1], p[2]];
        (points, points.map(|k| positions[k as usize].as_dvec3()))
    }

    fn side_of(&self, triangle: usize) -> Side {
        if triangle < self.a_triangles {
            Side::A
        } else {
            Side::B
        }
    }

    /// One side's solid as arrays, each triangle's face number its
    /// number in the merge.
    fn solid_input(&self, side: Side) -> SolidInput {
        let (prims, points) = match side {
            Side::A => (0..self.a_triangles, 0..self.a_points),
            Side::B => (
                self.a_triangles..self.both.num_prims(),
                self.a_points..self.both.num_points(),
            ),
        };
        let base = points.start as u32;
        let positions: Vec<[f32; 3]> = self.both.positions()[points]
            .iter()
            .map(|p| p.to_array())
            .collect();
        let triangles: Vec<[u32; 3]> = prims
            .clone()
            .map(|t| {
                let p = self.both.prim_points(t);
                [p[0] - base, p[1] - base, p[2] - base]
            })
            .collect();
        let faces: Vec<u32> = prims.map(|t| t as u32).collect();
        SolidInput {
            positions,
            triangles,
            faces,
        }
    }

    /// The geometry of manifold's result `r`: triangles, attributes from
    /// their sources, the origin groups of `op` when given; `piece` numbers
    /// a shatter piece.
    fn output(
        &self,
        r: &Mesh,
        op: Option<BooleanOp>,
        piece: Option<i32>,
    ) -> Result<Geometry, ModelError> {
        let failed = |why: String| ModelError::Failed { op: "boolean", why };
        if r.triangles.is_empty() {
            return Ok(Geometry::new());
        }
        if let Some(&face) = r
            .faces
            .iter()
            .find(|&&f| f as usize >= self.both.num_prims())
        {
            return Err(failed(format!("a face lost its source ({face})")));
        }
        let sources = &r.faces;
        // Per output corner: the source triangle's points, the corner's
        // weights there (manifold keeps every output triangle inside the
        // source triangle it names, so a corner is in it up to rounding: a
        // few parts in a thousand of a sliver's height on a hundred-sphere
        // union, and the clamped weights are its nearest point there) and
        // the source triangle.
        let source_positions = self.both.positions();
        let mut corners = vec![([0u32; 3], [0f32; 3], 0usize); 3 * r.triangles.len()];
        corners
            .par_chunks_mut(3)
            .zip(r.triangles.par_iter().zip(sources.par_iter()))
            .for_each(|(out, (tri, &face))| {
                let face = face as usize;
                let (points, at) = self.corners(source_positions, face);
                for (slot, &v) in out.iter_mut().zip(tri) {
                    let p = Vec3::from_array(r.positions[v as usize]).as_dvec3();
                    *slot = (points, clamped(barycentric(p, at)), face);
                }
            });
        let triangles = &r.triangles;
        let positions: Vec<Vec3> = r.positions.iter().map(|p| Vec3::from_array(*p)).collect();
        let mut out =
            Geometry::from_triangles(positions, triangles).map_err(|e| failed(e.to_string()))?;
        self.carry_points(&mut out, triangles, &corners)?;
        self.carry_vertices(&mut out, &corners)?;
        self.carry_prims(&mut out, sources)?;
        if let Some(op) = op {
            self.mark_origins(&mut out, triangles, sources, op)?;
        }
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

/// The result when an input has no primitives, as Houdini's Boolean
/// gives it: the other side for a union, A less nothing is A, nothing
/// less B or met with anything is nothing, A shattered by nothing is A.
fn with_an_empty_side(a: &Geometry, b: &Geometry, op: BooleanOp) -> Option<Geometry> {
    let (a_empty, b_empty) = (a.num_prims() == 0, b.num_prims() == 0);
    if !a_empty && !b_empty {
        return None;
    }
    Some(match op {
        BooleanOp::Union if a_empty => b.clone(),
        BooleanOp::Union | BooleanOp::Subtract | BooleanOp::Shatter if b_empty => a.clone(),
        _ => Geometry::default(),
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
    let t = ops::triangulate_with(g, None, cancel).ok_or(ModelError::Cancelled)?;
    // manifold takes a solid's winding as given: inside out, A's shell
    // came back as two coincident copies of B's.
    let volume = f64::from(ops::signed_volume(&t));
    if volume < 0.0 {
        return Err(ModelError::InsideOut {
            input: name,
            volume,
        });
    }
    Ok(t)
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
