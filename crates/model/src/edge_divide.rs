//! Points inserted evenly along edges (Houdini's Edge Divide): every
//! chosen edge gets `divisions` new points, made once and shared by every
//! polygon or polyline along it, so a connected (or closed) mesh stays so.
//!
//! Edges are chosen by a point group (geode has no edge groups): an edge
//! is divided when both its ends are in the group (all edges without
//! one). Edges are found by sorting each side's point pair (rayon's sort
//! of unique keys: the same order on any thread count); new points come
//! after the old ones, edge by edge in that order, running from the lower
//! point number to the higher. New points blend their edge's two points
//! (attributes and point groups as `carry` does) and join the point group
//! `group_name` when one is named; vertices blend their side's two
//! vertices; primitives keep their attributes and groups.

use geode_geo::{Geometry, Group};
use rayon::prelude::*;

use crate::carry::{self, copy, Plan};
use crate::ModelError;

/// An edge: its lower and higher point.
type Edge = (u32, u32);

#[derive(Clone, Debug)]
pub struct EdgeDivideOptions {
    /// New points per edge (at least 1).
    pub divisions: u32,
    /// The point group the new points join (None: none made).
    pub group_name: Option<String>,
}

/// Divides `g`'s edges whose ends are both in `points` (all when None);
/// see the module doc.
pub fn edge_divide(
    g: &Geometry,
    points: Option<&Group>,
    options: &EdgeDivideOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    carry::polygons_and_polylines(g, "edge_divide")?;
    if options.divisions < 1 {
        return Err(ModelError::Invalid(
            "edge_divide needs at least 1 division".into(),
        ));
    }
    let n = options.divisions as usize;
    let (side_edge, edges) = edges(g, points, cancel)?;
    let np = g.num_points();
    let mut plan = Plan {
        first_new_prim: usize::MAX,
        ..Plan::default()
    };
    new_points(g, &edges, n, &mut plan);
    faces(g, &side_edge, &edges, n, &mut plan, cancel)?;
    let mut out = carry::build(g, plan, "edge_divide", cancel)?;
    if let Some(name) = options.group_name.as_deref().filter(|s| !s.is_empty()) {
        let total = out.num_points();
        out.set_point_group(name, Group::from_members(total, np..total))
            .map_err(|e| ModelError::Failed {
                op: "edge_divide",
                why: e.to_string(),
            })?;
    }
    Ok(out)
}

/// Per vertex: the edge its side (to the next vertex) is, u32::MAX when
/// not divided; and the distinct edges `(low, high)` in sorted order.
fn edges(
    g: &Geometry,
    points: Option<&Group>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Vec<u32>, Vec<Edge>), ModelError> {
    let vp = g.vertex_points();
    let offsets = g.prim_offsets();
    let kinds = g.prim_kinds();
    let chosen = |p: u32| points.is_none_or(|grp| grp.contains(p as usize));
    let mut keys: Vec<(u64, u32)> = (0..g.num_prims())
        .into_par_iter()
        .flat_map_iter(|prim| {
            let (lo, hi) = (offsets[prim] as usize, offsets[prim + 1] as usize);
            let closed = kinds[prim] == geode_geo::PrimKind::Polygon && hi - lo > 2;
            let sides = if closed {
                hi - lo
            } else {
                (hi - lo).saturating_sub(1)
            };
            (0..sides).filter_map(move |j| {
                let (v, w) = (lo + j, lo + (j + 1) % (hi - lo));
                let (a, b) = (vp[v], vp[w]);
                (a != b && chosen(a) && chosen(b)).then(|| {
                    let key = (a.min(b) as u64) << 32 | a.max(b) as u64;
                    (key, v as u32)
                })
            })
        })
        .collect();
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    keys.par_sort_unstable();
    let mut side_edge = vec![u32::MAX; g.num_vertices()];
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for (k, &(key, v)) in keys.iter().enumerate() {
        if k % 65536 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        if k == 0 || keys[k - 1].0 != key {
            edges.push(((key >> 32) as u32, key as u32));
        }
        side_edge[v as usize] = edges.len() as u32 - 1;
    }
    Ok((side_edge, edges))
}

/// The old points, then each edge's new points from its low end.
fn new_points(g: &Geometry, edges: &[(u32, u32)], n: usize, plan: &mut Plan) {
    let p = g.positions();
    plan.positions.extend_from_slice(p);
    plan.point_sources.extend((0..p.len() as u32).map(copy));
    let (positions, sources): (Vec<_>, Vec<_>) = edges
        .par_iter()
        .flat_map_iter(|&(a, b)| {
            (1..=n).map(move |k| {
                let t = k as f32 / (n + 1) as f32;
                (p[a as usize].lerp(p[b as usize], t), (a, b, t))
            })
        })
        .unzip();
    plan.positions.extend(positions);
    plan.point_sources.extend(sources);
}

/// Every primitive again, each divided side's new points inserted after
/// its first vertex in the side's direction.
fn faces(
    g: &Geometry,
    side_edge: &[u32],
    edges: &[(u32, u32)],
    n: usize,
    plan: &mut Plan,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    let vp = g.vertex_points();
    let offsets = g.prim_offsets();
    let base = g.num_points() as u32;
    for prim in 0..g.num_prims() {
        if prim % 16384 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        let (lo, hi) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        let before = plan.vertex_points.len();
        for v in lo..hi {
            plan.vertex_points.push(vp[v]);
            plan.vertex_sources.push(copy(v as u32));
            let e = side_edge[v];
            if e == u32::MAX {
                continue;
            }
            let w = if v + 1 == hi { lo } else { v + 1 };
            let forward = edges[e as usize].0 == vp[v];
            for i in 1..=n {
                let k = if forward { i } else { n + 1 - i };
                plan.vertex_points.push(base + e * n as u32 + k as u32 - 1);
                plan.vertex_sources
                    .push((v as u32, w as u32, i as f32 / (n + 1) as f32));
            }
        }
        plan.prim_counts
            .push((plan.vertex_points.len() - before) as u32);
        plan.prim_kinds.push(g.prim_kinds()[prim]);
        plan.prim_sources.push(prim as u32);
    }
    Ok(())
}
