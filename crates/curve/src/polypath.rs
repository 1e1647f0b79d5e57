//! PolyPath (Houdini's node of that name): the edges of every polyline and
//! polygon rewired into maximal polylines, each running until a point where
//! the edges end or branch (a point on one edge, or on three or more), so
//! segments grown one at a time become one curve per branch. Edges that
//! occur more than once count once, edges from a point to itself go;
//! points, their attributes and groups are kept as they are.
//!
//! Each path runs the way most of its source edges ran (ties: from its
//! lower-numbered end), so a skeleton grown root to tip stays root to tip.
//! A loop nothing else touches is a closed polygon (`close_loops`, Houdini's
//! "Make Isolated Loops Closed") or an open polyline ending where it
//! starts. Paths come in the order of their first source edge and take the
//! primitive attributes and groups of its primitive; each output vertex
//! takes the attributes of a source vertex of its point on an edge of the
//! path. Other primitive kinds (packed, patches) and payloads are dropped.

use geode_geo::{AttribClass, GeoError, Geometry, PrimKind};
use rayon::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PolyPathOptions {
    /// Loops with no branch are closed polygons (else open polylines whose
    /// last point is their first).
    pub close_loops: bool,
}

impl Default for PolyPathOptions {
    fn default() -> Self {
        PolyPathOptions { close_loops: true }
    }
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PolyPathError {
    #[error(transparent)]
    Geo(#[from] GeoError),
    #[error("cancelled")]
    Cancelled,
}

/// The distinct edges of the curves, in primitive and vertex order.
struct Edges {
    /// End points (`a` first in the source's direction).
    a: Vec<u32>,
    b: Vec<u32>,
    /// The source vertices at `a` and `b`.
    va: Vec<u32>,
    vb: Vec<u32>,
    prim: Vec<u32>,
}

impl Edges {
    fn len(&self) -> usize {
        self.a.len()
    }

    fn collect(g: &Geometry) -> Edges {
        let mut e = Edges {
            a: Vec::new(),
            b: Vec::new(),
            va: Vec::new(),
            vb: Vec::new(),
            prim: Vec::new(),
        };
        let vp = g.vertex_points();
        for prim in 0..g.num_prims() {
            let closed = match g.prim_kind(prim) {
                PrimKind::Polyline => false,
                PrimKind::Polygon => true,
                PrimKind::Packed(_) | PrimKind::Patch(_) => continue,
            };
            let r = g.prim_vertex_range(prim);
            let n = r.len();
            let segments = if closed { n } else { n.saturating_sub(1) };
            for k in 0..segments {
                let (v0, v1) = (r.start + k, r.start + (k + 1) % n);
                let (p0, p1) = (vp[v0], vp[v1]);
                if p0 == p1 {
                    continue;
                }
                e.a.push(p0);
                e.b.push(p1);
                e.va.push(v0 as u32);
                e.vb.push(v1 as u32);
                e.prim.push(prim as u32);
            }
        }
        e
    }

    /// Keeps the first occurrence of every edge (either direction).
    fn dedup(self) -> Edges {
        let mut keys: Vec<(u64, u32)> = (0..self.len())
            .into_par_iter()
            .map(|i| {
                let (a, b) = (self.a[i], self.b[i]);
                let (lo, hi) = (a.min(b) as u64, a.max(b) as u64);
                ((lo << 32) | hi, i as u32)
            })
            .collect();
        keys.par_sort_unstable();
        let mut keep = vec![false; self.len()];
        for (k, &(key, i)) in keys.iter().enumerate() {
            if k == 0 || keys[k - 1].0 != key {
                keep[i as usize] = true;
            }
        }
        if keep.iter().all(|&k| k) {
            return self;
        }
        let pick = |v: &[u32]| -> Vec<u32> {
            v.iter()
                .zip(&keep)
                .filter_map(|(&x, &k)| k.then_some(x))
                .collect()
        };
        Edges {
            a: pick(&self.a),
            b: pick(&self.b),
            va: pick(&self.va),
            vb: pick(&self.vb),
            prim: pick(&self.prim),
        }
    }
}

/// The paths found so far, flat.
#[derive(Default)]
struct Paths {
    points: Vec<u32>,
    /// The source vertex each output vertex takes its attributes from.
    vertices: Vec<u32>,
    /// Per path: its first element in `points`, whether it is closed, its
    /// lowest source edge.
    start: Vec<usize>,
    closed: Vec<bool>,
    first_edge: Vec<u32>,
}

impl Paths {
    /// Reverses the last path when most of its edges ran the other way
    /// (a closed one keeps its first point first).
    fn settle(&mut self, forward: usize, backward: usize) {
        if backward <= forward {
            return;
        }
        let s = *self.start.last().expect("a path was started");
        let skip = usize::from(*self.closed.last().expect("a path was started"));
        self.points[s + skip..].reverse();
        self.vertices[s + skip..].reverse();
    }
}

/// Polylines joined at shared end points into maximal paths (see the
/// module's comment); `cancel` is polled between phases and every 64k
/// edges walked.
pub fn polypath(
    g: &Geometry,
    opts: &PolyPathOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, PolyPathError> {
    let edges = Edges::collect(g).dedup();
    if cancel() {
        return Err(PolyPathError::Cancelled);
    }
    let n = g.num_points();
    let m = edges.len();
    // Incident edges per point, in edge order (CSR).
    let mut offsets = vec![0u32; n + 1];
    for i in 0..m {
        offsets[edges.a[i] as usize + 1] += 1;
        offsets[edges.b[i] as usize + 1] += 1;
    }
    for p in 0..n {
        offsets[p + 1] += offsets[p];
    }
    let mut fill = offsets.clone();
    let mut adjacent = vec![0u32; 2 * m];
    for i in 0..m {
        for p in [edges.a[i], edges.b[i]] {
            adjacent[fill[p as usize] as usize] = i as u32;
            fill[p as usize] += 1;
        }
    }
    drop(fill);
    let degree = |p: u32| offsets[p as usize + 1] - offsets[p as usize];
    let mut visited = vec![false; m];
    let mut paths = Paths::default();
    let mut walked = 0usize;
    // From `from` along edge `e`: until a point that is not on exactly two
    // edges, or back at `from` (a loop).
    let mut walk =
        |from: u32, mut e: u32, loop_: bool, visited: &mut [bool], paths: &mut Paths| -> bool {
            let at = |e: u32, p: u32| {
                let e = e as usize;
                if edges.a[e] == p {
                    edges.va[e]
                } else {
                    edges.vb[e]
                }
            };
            paths.start.push(paths.points.len());
            paths.closed.push(loop_ && opts.close_loops);
            paths.points.push(from);
            paths.vertices.push(at(e, from));
            let (mut cur, mut lowest, mut forward, mut backward) = (from, e, 0usize, 0usize);
            loop {
                let i = e as usize;
                visited[i] = true;
                lowest = lowest.min(e);
                walked += 1;
                let next = if edges.a[i] == cur {
                    forward += 1;
                    edges.b[i]
                } else {
                    backward += 1;
                    edges.a[i]
                };
                if loop_ && next == from {
                    if !opts.close_loops {
                        paths.points.push(next);
                        paths.vertices.push(at(e, next));
                    }
                    break;
                }
                paths.points.push(next);
                paths.vertices.push(at(e, next));
                if degree(next) != 2 {
                    break;
                }
                let o = offsets[next as usize] as usize;
                let (e1, e2) = (adjacent[o], adjacent[o + 1]);
                let other = if e1 == e { e2 } else { e1 };
                if visited[other as usize] {
                    break;
                }
                cur = next;
                e = other;
            }
            paths.first_edge.push(lowest);
            paths.settle(forward, backward);
            walked < 1 << 16 || {
                walked = 0;
                !cancel()
            }
        };
    // Paths between end and branch points, from each such point in order.
    for p in 0..n as u32 {
        if degree(p) == 2 {
            continue;
        }
        for k in offsets[p as usize]..offsets[p as usize + 1] {
            let e = adjacent[k as usize];
            if !visited[e as usize] && !walk(p, e, false, &mut visited, &mut paths) {
                return Err(PolyPathError::Cancelled);
            }
        }
    }
    // What is left are loops of points on two edges each.
    for e in 0..m {
        if !visited[e] && !walk(edges.a[e], e as u32, true, &mut visited, &mut paths) {
            return Err(PolyPathError::Cancelled);
        }
    }
    if cancel() {
        return Err(PolyPathError::Cancelled);
    }
    build(g, &edges, &paths)
}

/// The output geometry: `g`'s points, the paths in order of their first
/// source edge.
fn build(g: &Geometry, edges: &Edges, paths: &Paths) -> Result<Geometry, PolyPathError> {
    let count = paths.start.len();
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_unstable_by_key(|&k| paths.first_edge[k]);
    let span = |k: usize| {
        paths.start[k]
            ..paths
                .start
                .get(k + 1)
                .copied()
                .unwrap_or(paths.points.len())
    };
    let mut points = Vec::with_capacity(paths.points.len());
    let mut vertices = Vec::with_capacity(paths.points.len());
    let mut counts = Vec::with_capacity(count);
    let mut kinds = Vec::with_capacity(count);
    let mut prims = Vec::with_capacity(count);
    for &k in &order {
        let r = span(k);
        counts.push(r.len() as u32);
        points.extend_from_slice(&paths.points[r.clone()]);
        vertices.extend_from_slice(&paths.vertices[r]);
        kinds.push(if paths.closed[k] {
            PrimKind::Polygon
        } else {
            PrimKind::Polyline
        });
        prims.push(edges.prim[paths.first_edge[k] as usize]);
    }
    let mut out = Geometry::from_prims(g.positions().to_vec(), points, &counts, kinds)?;
    for (name, a) in g.attribs(AttribClass::Point).iter() {
        if name != geode_geo::P {
            out.set_attrib(AttribClass::Point, name, a.clone())?;
        }
    }
    for (name, grp) in g.point_groups() {
        out.set_point_group(name, grp.clone())?;
    }
    for (name, a) in g.attribs(AttribClass::Vertex).iter() {
        out.set_attrib(AttribClass::Vertex, name, a.gather(&vertices))?;
    }
    for (name, a) in g.attribs(AttribClass::Primitive).iter() {
        out.set_attrib(AttribClass::Primitive, name, a.gather(&prims))?;
    }
    for (name, grp) in g.prim_groups() {
        out.set_prim_group(name, grp.gather(&prims))?;
    }
    for (name, a) in g.attribs(AttribClass::Detail).iter() {
        out.set_attrib(AttribClass::Detail, name, a.clone())?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::glam::Vec3;
    use geode_geo::{AttribData, Attribute, Group, TypeInfo};

    fn never() -> bool {
        false
    }

    fn run(g: &Geometry, close_loops: bool) -> Geometry {
        polypath(g, &PolyPathOptions { close_loops }, &never).unwrap()
    }

    fn prims(g: &Geometry) -> Vec<(PrimKind, Vec<u32>)> {
        (0..g.num_prims())
            .map(|p| (g.prim_kind(p), g.prim_points(p).to_vec()))
            .collect()
    }

    /// Points 0..n on a line (positions do not matter to the topology).
    fn with_segments(n: usize, segments: &[[u32; 2]]) -> Geometry {
        let mut g = Geometry::new();
        for i in 0..n {
            g.add_point(Vec3::new(i as f32, 0.0, 0.0));
        }
        for s in segments {
            g.add_polyline(s).unwrap();
        }
        g
    }

    #[test]
    fn a_y_of_three_chains_gives_three_polylines() {
        // Trunk 0-1-2-3 to the fork at 3, arms 3-4-5 and 3-6-7-8, all as
        // two-point segments in growth order (parent first).
        let g = with_segments(
            9,
            &[
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 4],
                [3, 6],
                [4, 5],
                [6, 7],
                [7, 8],
            ],
        );
        let out = run(&g, true);
        assert_eq!(
            prims(&out),
            vec![
                (PrimKind::Polyline, vec![0, 1, 2, 3]),
                (PrimKind::Polyline, vec![3, 4, 5]),
                (PrimKind::Polyline, vec![3, 6, 7, 8]),
            ]
        );
        assert_eq!(out.positions(), g.positions());
    }

    #[test]
    fn paths_run_the_way_their_edges_did() {
        // Segments written tip to root (4-3, 3-2, 2-0, 2-1): the paths
        // keep that direction though each walk starts from its lower end.
        let g = with_segments(5, &[[4, 3], [3, 2], [2, 0], [2, 1]]);
        let out = run(&g, true);
        assert_eq!(
            prims(&out),
            vec![
                (PrimKind::Polyline, vec![4, 3, 2]),
                (PrimKind::Polyline, vec![2, 0]),
                (PrimKind::Polyline, vec![2, 1]),
            ]
        );
    }

    #[test]
    fn longer_polylines_split_at_branches_and_duplicates_count_once() {
        // A polyline 0-1-2-3-4 crossed at 2 by 5-2 and 2-6; the segment 1-2
        // again (reversed) and a self-edge 4-4 change nothing.
        let mut g = with_segments(7, &[[5, 2], [2, 6], [2, 1]]);
        g.add_polyline(&[0, 1, 2, 3, 4, 4]).unwrap();
        let out = run(&g, true);
        assert_eq!(
            prims(&out),
            vec![
                (PrimKind::Polyline, vec![5, 2]),
                (PrimKind::Polyline, vec![2, 6]),
                (PrimKind::Polyline, vec![0, 1, 2]),
                (PrimKind::Polyline, vec![2, 3, 4]),
            ]
        );
    }

    #[test]
    fn an_isolated_loop_closes_or_repeats_its_first_point() {
        let g = with_segments(5, &[[0, 1], [1, 2], [2, 3], [3, 0], [3, 4]]);
        // 3 is on three edges: the loop 3-0-1-2-3 ends there, not closed.
        let out = run(&g, true);
        assert_eq!(
            prims(&out),
            vec![
                (PrimKind::Polyline, vec![3, 0, 1, 2, 3]),
                (PrimKind::Polyline, vec![3, 4]),
            ]
        );
        // A loop nothing touches.
        let g = with_segments(4, &[[0, 1], [1, 2], [2, 3], [3, 0]]);
        assert_eq!(
            prims(&run(&g, true)),
            vec![(PrimKind::Polygon, vec![0, 1, 2, 3])]
        );
        assert_eq!(
            prims(&run(&g, false)),
            vec![(PrimKind::Polyline, vec![0, 1, 2, 3, 0])]
        );
        // A closed polygon in is the same loop.
        let mut g = with_segments(4, &[]);
        g.add_polygon(&[2, 3, 0, 1]).unwrap();
        assert_eq!(
            prims(&run(&g, true)),
            vec![(PrimKind::Polygon, vec![2, 3, 0, 1])]
        );
    }

    #[test]
    fn attributes_and_groups_are_carried() {
        let mut g = with_segments(5, &[[0, 1], [1, 2], [2, 3], [2, 4]]);
        let set = |g: &mut Geometry, class, name: &str, data| {
            g.set_attrib(class, name, Attribute::from_data(data, TypeInfo::None))
                .unwrap()
        };
        set(
            &mut g,
            AttribClass::Point,
            "width",
            AttribData::Float(vec![0.0, 1.0, 2.0, 3.0, 4.0]),
        );
        set(
            &mut g,
            AttribClass::Primitive,
            "branch",
            AttribData::Int(vec![10, 11, 12, 13]),
        );
        // Each vertex remembers its own source vertex number.
        set(
            &mut g,
            AttribClass::Vertex,
            "source",
            AttribData::Int((0..8).collect()),
        );
        set(
            &mut g,
            AttribClass::Detail,
            "seed",
            AttribData::Int(vec![7]),
        );
        g.set_prim_group("late", Group::from_flags([false, false, false, true]))
            .unwrap();
        g.set_point_group("tip", Group::from_flags([false, false, false, true, true]))
            .unwrap();
        let out = run(&g, true);
        assert_eq!(
            prims(&out),
            vec![
                (PrimKind::Polyline, vec![0, 1, 2]),
                (PrimKind::Polyline, vec![2, 3]),
                (PrimKind::Polyline, vec![2, 4]),
            ]
        );
        let a = |class, name| out.attrib(class, name).unwrap().data().clone();
        assert_eq!(
            a(AttribClass::Point, "width"),
            AttribData::Float(vec![0.0, 1.0, 2.0, 3.0, 4.0])
        );
        // Each path's primitive values come from its first source segment.
        assert_eq!(
            a(AttribClass::Primitive, "branch"),
            AttribData::Int(vec![10, 12, 13])
        );
        // Source vertices: segment k has vertices 2k (its start) and 2k+1.
        // Path 0-1-2: 0 from segment 0's start, 1 and 2 from the segments
        // arriving at them; 2-3 and 2-4 from their own segments.
        assert_eq!(
            a(AttribClass::Vertex, "source"),
            AttribData::Int(vec![0, 1, 3, 4, 5, 6, 7])
        );
        assert_eq!(a(AttribClass::Detail, "seed"), AttribData::Int(vec![7]));
        let late = &out.prim_groups()["late"];
        assert_eq!(
            (0..3).map(|p| late.contains(p)).collect::<Vec<_>>(),
            [false, false, true]
        );
        assert_eq!(out.point_groups()["tip"].count(), 2);
    }

    #[test]
    fn nothing_to_join_is_no_primitives_and_cancel_stops() {
        let g = with_segments(3, &[]);
        assert_eq!(run(&g, true).num_prims(), 0);
        let g = with_segments(3, &[[0, 1], [1, 2]]);
        assert_eq!(
            polypath(&g, &PolyPathOptions::default(), &|| true),
            Err(PolyPathError::Cancelled)
        );
    }
}
