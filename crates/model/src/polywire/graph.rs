//! The wire skeleton: the distinct edges of the chosen polylines and
//! polygons, and the chains they form between points where the skeleton
//! ends or branches (points with other than two edges), plus closed loops.

use geode_geo::{Geometry, Group, PrimKind};

use crate::ModelError;

/// One distinct skeleton edge, in the direction its first primitive runs.
#[derive(Clone, Copy, Debug)]
pub(super) struct Edge {
    pub a: u32,
    pub b: u32,
    /// The first primitive that has it, and its vertices at `a` and `b`.
    pub prim: u32,
    pub va: u32,
    pub vb: u32,
}

/// A run of edges between two points of valence other than two (or a
/// loop through valence-two points only).
#[derive(Clone, Debug)]
pub(super) struct Chain {
    /// Points along the chain; a loop repeats its first point last.
    pub points: Vec<u32>,
    /// Per step: the edge and whether it runs backwards along the chain.
    pub edges: Vec<(u32, bool)>,
    pub closed: bool,
}

/// The skeleton: edges, each point's edges, and the chains.
pub(super) struct Skeleton {
    pub edges: Vec<Edge>,
    /// Per point: its edges (by edge number, ascending).
    pub incident: Vec<Vec<u32>>,
    pub chains: Vec<Chain>,
}

impl Skeleton {
    /// The edges of `g`'s primitives in `group` (all when None), first
    /// occurrence kept, and their chains. Zero-length edges are refused.
    pub fn new(
        g: &Geometry,
        group: Option<&Group>,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Skeleton, ModelError> {
        let edges = distinct_edges(g, group, cancel)?;
        let p = g.positions();
        if let Some(e) = edges.iter().find(|e| p[e.a as usize] == p[e.b as usize]) {
            return Err(ModelError::Invalid(format!(
                "the edge from point {} to point {} has no length: fuse the points first",
                e.a, e.b
            )));
        }
        let mut incident = vec![Vec::new(); g.num_points()];
        for (k, e) in edges.iter().enumerate() {
            incident[e.a as usize].push(k as u32);
            incident[e.b as usize].push(k as u32);
        }
        let chains = chains(&edges, &incident, cancel)?;
        Ok(Skeleton {
            edges,
            incident,
            chains,
        })
    }

    pub fn valence(&self, point: u32) -> usize {
        self.incident[point as usize].len()
    }
}

/// Every polyline segment and polygon side once (a side two polygons
/// share is one edge), in primitive order.
fn distinct_edges(
    g: &Geometry,
    group: Option<&Group>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Edge>, ModelError> {
    let offsets = g.prim_offsets();
    let vp = g.vertex_points();
    let mut seen = std::collections::HashSet::new();
    let mut edges = Vec::new();
    for prim in 0..g.num_prims() {
        if prim % 4096 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        if group.is_some_and(|grp| !grp.contains(prim)) {
            continue;
        }
        let (lo, hi) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        let n = hi - lo;
        let closed = g.prim_kinds()[prim] == PrimKind::Polygon;
        let sides = if closed && n > 2 {
            n
        } else {
            n.saturating_sub(1)
        };
        for j in 0..sides {
            let (va, vb) = (lo + j, lo + (j + 1) % n);
            let (a, b) = (vp[va], vp[vb]);
            if a == b || !seen.insert((a.min(b), a.max(b))) {
                continue;
            }
            edges.push(Edge {
                a,
                b,
                prim: prim as u32,
                va: va as u32,
                vb: vb as u32,
            });
        }
    }
    Ok(edges)
}

/// Walks the chains: first from every point of valence other than two
/// (in point order, its edges in order), then the loops left over (from
/// their lowest edge).
fn chains(
    edges: &[Edge],
    incident: &[Vec<u32>],
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Chain>, ModelError> {
    let mut used = vec![false; edges.len()];
    let mut out = Vec::new();
    let other = |e: u32, p: u32| {
        let e = &edges[e as usize];
        if e.a == p {
            (e.b, false)
        } else {
            (e.a, true)
        }
    };
    let walk = |start: u32, first: u32, used: &mut Vec<bool>| {
        let mut chain = Chain {
            points: vec![start],
            edges: Vec::new(),
            closed: false,
        };
        let (mut at, mut e) = (start, first);
        loop {
            used[e as usize] = true;
            let (next, backwards) = other(e, at);
            chain.edges.push((e, backwards));
            chain.points.push(next);
            at = next;
            let inc = &incident[at as usize];
            if inc.len() != 2 {
                break;
            }
            let e2 = if inc[0] == e { inc[1] } else { inc[0] };
            if used[e2 as usize] {
                // Back at the start of a loop.
                chain.closed = at == start;
                break;
            }
            e = e2;
        }
        chain
    };
    for (p, inc) in incident.iter().enumerate() {
        if p % 4096 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        if inc.len() == 2 || inc.is_empty() {
            continue;
        }
        for &e in inc {
            if !used[e as usize] {
                out.push(walk(p as u32, e, &mut used));
            }
        }
    }
    for e in 0..edges.len() {
        if !used[e] {
            let start = edges[e].a;
            out.push(walk(start, e as u32, &mut used));
        }
    }
    Ok(out)
}
