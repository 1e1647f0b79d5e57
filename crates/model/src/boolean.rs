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

use std::time::Duration;

use geode_geo::{ops, Geometry};
use geode_manifold::{Mesh, Op, Solid};

use crate::ModelError;
use sources::{boundary_report, Sources};

mod sources;

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
    let sources = Sources::one(g, cancel)?;
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
