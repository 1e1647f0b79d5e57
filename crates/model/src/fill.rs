//! Hole filling (Houdini's PolyFill): each boundary loop of a polygon mesh
//! closed by new faces, wound to agree with the faces around it.
//!
//! The loops are the mesh's boundary half-edges (edges of one polygon)
//! reversed and chained: a fill face runs along each boundary edge the
//! other way, so its winding matches its neighbours' and a closed,
//! consistently wound result comes out. Where two holes touch at a point
//! the chain takes the lowest-numbered way on, deterministically.
//!
//! Loops in one plane, one inside another and wound the other way (the
//! two circles a cut leaves in a torus), are filled as one face with holes
//! (`planes` finds them, `nest` bridges the holes in), unless a face along
//! them lies in that plane (a sheet's hole and its border) or the fill is a
//! fan. Houdini's PolyFill fills every loop on its own.
//!
//! Each loop becomes one n-gon, a fan of triangles around a new centre
//! point (the loop's mean), or triangles: the minimum-weight triangulation
//! (summed triangle perimeters, every triangle wound as the loop in its
//! best-fit plane; loops of up to 200 points) or ear clipping in the
//! best-fit plane (Newell normal). Houdini's PolyFill also offers quad
//! fills and smoothing, which geode does not.
//!
//! New faces take the primitive attributes of the face across their
//! loop's first edge and, at each corner, the vertex attributes of the
//! neighbouring face's corner at that point; a fan's centre point and
//! corners take the loop's means. New faces join the `group` only.

pub(crate) mod nest;
mod planes;
pub(crate) mod triangulate;

pub use triangulate::MIN_WEIGHT_MAX;
pub(crate) use triangulate::{
    ear_clip, ear_clip_avoiding, newell_normal, plane_basis, signed_area2,
};

use geode_geo::glam::{DVec2, DVec3};
use geode_geo::{AttribClass, Geometry, Group, HalfEdge, PrimKind};

use crate::carry::{self, copy, Blend, Plan};
use crate::ModelError;
use nest::{nest, Ring};

/// How a hole is closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FillMode {
    /// One polygon over the loop.
    Polygon,
    /// Triangles around a new point at the loop's centre.
    Fan,
    /// Triangles over the loop's own points.
    Triangles,
}

impl FillMode {
    pub const NAMES: &'static [&'static str] = &["triangles", "polygon", "fan"];

    pub fn from_name(name: &str) -> Option<FillMode> {
        Some(match name {
            "polygon" => FillMode::Polygon,
            "fan" => FillMode::Fan,
            "triangles" => FillMode::Triangles,
            _ => return None,
        })
    }
}

/// How [`FillMode::Triangles`] triangulates a loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Triangulation {
    /// Minimum summed perimeter (loops up to [`MIN_WEIGHT_MAX`] points;
    /// longer ones are ear clipped).
    MinWeight,
    /// Ear clipping in the loop's best-fit plane.
    EarClip,
}

impl Triangulation {
    pub const NAMES: &'static [&'static str] = &["min_weight", "ear_clip"];

    pub fn from_name(name: &str) -> Option<Triangulation> {
        Some(match name {
            "min_weight" => Triangulation::MinWeight,
            "ear_clip" => Triangulation::EarClip,
            _ => return None,
        })
    }
}

#[derive(Clone, Debug)]
pub struct FillOptions {
    pub mode: FillMode,
    pub triangulation: Triangulation,
    /// Holes of more points than this stay open (0: no limit).
    pub max_points: usize,
    /// The primitive group of the new faces (empty: none).
    pub group: String,
    /// Loops in one plane inside another, wound the other way (the two
    /// circles a cut leaves in a torus), become holes in its fill (not
    /// with [`FillMode::Fan`]).
    pub holes: bool,
}

impl Default for FillOptions {
    fn default() -> Self {
        FillOptions {
            mode: FillMode::Triangles,
            triangulation: Triangulation::MinWeight,
            max_points: 0,
            group: "polyfill".into(),
            holes: true,
        }
    }
}

/// A filled mesh and what was filled.
#[derive(Debug)]
pub struct Filled {
    pub geometry: Geometry,
    pub holes_filled: usize,
    /// Loops left open: over the size limit, or chains of boundary edges
    /// that do not close (a non-manifold boundary).
    pub holes_skipped: usize,
}

/// One edge of a hole's loop: from `from` to `to`, along a boundary edge
/// of face `face`, whose corner at `from` is vertex `corner`.
#[derive(Clone, Copy)]
struct LoopEdge {
    from: u32,
    to: u32,
    face: u32,
    corner: u32,
}

/// Elements a fan's centre averages, set once the output is built:
/// `(element, the elements averaged)` for points and for vertices.
#[derive(Default)]
struct Means {
    points: Vec<(u32, Vec<u32>)>,
    vertices: Vec<(u32, Vec<u32>)>,
}

/// Fills the holes of `g` (see the module doc).
pub fn polyfill(
    g: &Geometry,
    options: &FillOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Filled, ModelError> {
    carry::polygons_and_polylines(g, "polyfill")?;
    let edges = boundary_edges(g);
    let (loops, open) = chain_loops(
        &edges.iter().map(|e| (e.from, e.to)).collect::<Vec<_>>(),
        |_, candidates| candidates[0],
    );
    let mut plan = copy_of(g);
    let mut means = Means::default();
    let mut skipped = open;
    let rings: Vec<Vec<LoopEdge>> = loops
        .iter()
        .filter_map(|l| {
            let fits = l.len() >= 3 && (options.max_points == 0 || l.len() <= options.max_points);
            if !fits {
                skipped += 1;
            }
            fits.then(|| l.iter().map(|&e| edges[e]).collect())
        })
        .collect();
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    let groups = if options.holes && options.mode != FillMode::Fan {
        let outlines: Vec<(Vec<u32>, Vec<u32>)> = rings
            .iter()
            .map(|r| {
                (
                    r.iter().map(|e| e.from).collect(),
                    r.iter().map(|e| e.face).collect(),
                )
            })
            .collect();
        planes::coplanar_groups(g, &outlines)
    } else {
        Vec::new()
    };
    let mut grouped = vec![false; rings.len()];
    for (k, group) in groups.iter().enumerate() {
        if k % 64 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        let members: Vec<&[LoopEdge]> = group.iter().map(|&r| rings[r].as_slice()).collect();
        fill_nested(g, &members, options, &mut plan, &mut means);
        for &r in group {
            grouped[r] = true;
        }
    }
    for (k, ring) in rings.iter().enumerate() {
        if k % 64 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        if !grouped[k] {
            fill_loop(g, ring, None, options, &mut plan, &mut means);
        }
    }
    let filled = rings.len();
    let new_faces = plan.first_new_prim..plan.prim_kinds.len();
    let mut out = carry::build(g, plan, "polyfill", cancel)?;
    carry::set_means(&mut out, AttribClass::Point, &means.points);
    carry::set_means(&mut out, AttribClass::Vertex, &means.vertices);
    if !options.group.is_empty() {
        let group = Group::from_flags((0..out.num_prims()).map(|p| new_faces.contains(&p)));
        out.set_prim_group(&options.group, group)
            .map_err(|e| ModelError::Failed {
                op: "polyfill",
                why: e.to_string(),
            })?;
    }
    Ok(Filled {
        geometry: out,
        holes_filled: filled,
        holes_skipped: skipped,
    })
}

/// The boundary edges of `g`'s polygons, each reversed (the way a fill
/// face runs along it), in edge order.
fn boundary_edges(g: &Geometry) -> Vec<LoopEdge> {
    let topo = g.topology();
    topo.boundary_edges()
        .into_iter()
        .filter_map(|e| {
            let h: HalfEdge = topo.edge_half_edges(e).next()?;
            let next = topo.next(g, h);
            Some(LoopEdge {
                from: topo.origin(g, next),
                to: topo.origin(g, h),
                face: topo.prim_of(h) as u32,
                corner: next.0,
            })
        })
        .collect()
}

/// How many open chains the edges `stray` make: the points where one
/// starts (a tail no stray edge ends at), at least one if any edge is
/// left.
fn open_chains(edges: &[(u32, u32)], stray: &[usize]) -> usize {
    let mut ends: Vec<u32> = stray.iter().map(|&e| edges[e].1).collect();
    ends.sort_unstable();
    let starts = stray
        .iter()
        .filter(|&&e| ends.binary_search(&edges[e].0).is_err())
        .count();
    if stray.is_empty() {
        0
    } else {
        starts.max(1)
    }
}

/// Chains directed edges `(from, to)` into closed loops of edge indices,
/// each loop starting at its lowest-numbered edge; where several edges
/// leave a point, `choose(incoming, candidates)` picks one. Also returns
/// how many chains did not close (their edges are used up).
pub(crate) fn chain_loops(
    edges: &[(u32, u32)],
    choose: impl Fn(usize, &[usize]) -> usize,
) -> (Vec<Vec<usize>>, usize) {
    let mut by_from: Vec<usize> = (0..edges.len()).collect();
    by_from.sort_unstable_by_key(|&e| (edges[e].0, e));
    let leaving = |p: u32| {
        let lo = by_from.partition_point(|&e| edges[e].0 < p);
        let hi = by_from.partition_point(|&e| edges[e].0 <= p);
        &by_from[lo..hi]
    };
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    // Edges of chains that did not close: counted as chains at the end (a
    // walk can start in the middle of an open chain and meet it in parts).
    let mut stray: Vec<usize> = Vec::new();
    let mut candidates = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        used[first] = true;
        let mut chain = vec![first];
        let mut at = first;
        loop {
            let to = edges[at].1;
            if to == edges[first].0 {
                loops.push(chain);
                break;
            }
            candidates.clear();
            candidates.extend(leaving(to).iter().copied().filter(|&e| !used[e]));
            if candidates.is_empty() {
                stray.extend(chain.iter().copied());
                break;
            }
            let next = if candidates.len() == 1 {
                candidates[0]
            } else {
                choose(at, &candidates)
            };
            used[next] = true;
            chain.push(next);
            at = next;
        }
    }
    (loops, open_chains(edges, &stray))
}

/// The plan that copies `g` whole (new faces are appended to it).
fn copy_of(g: &Geometry) -> Plan {
    let np = g.num_prims();
    Plan {
        positions: g.positions().to_vec(),
        point_sources: (0..g.num_points() as u32).map(copy).collect(),
        vertex_points: g.vertex_points().to_vec(),
        vertex_sources: (0..g.num_vertices() as u32).map(copy).collect(),
        prim_counts: (0..np)
            .map(|p| g.prim_vertex_range(p).len() as u32)
            .collect(),
        prim_kinds: g.prim_kinds().to_vec(),
        prim_sources: (0..np as u32).collect(),
        first_new_prim: np,
    }
}

/// Loops of one plane (the first the largest) filled as faces with holes:
/// nested in the first loop's frame (see [`nest`]).
fn fill_nested(
    g: &Geometry,
    members: &[&[LoopEdge]],
    options: &FillOptions,
    plan: &mut Plan,
    means: &mut Means,
) {
    let point = |e: &LoopEdge| g.positions()[e.from as usize].as_dvec3();
    let lead: Vec<DVec3> = members[0].iter().map(point).collect();
    let centre = lead.iter().sum::<DVec3>() / lead.len() as f64;
    let (u, v) = plane_basis(newell_normal(&lead));
    let rings: Vec<Ring<LoopEdge>> = members
        .iter()
        .map(|m| {
            let q = m
                .iter()
                .map(|e| {
                    let d = point(e) - centre;
                    DVec2::new(d.dot(u), d.dot(v))
                })
                .collect();
            Ring::new(m.to_vec(), q)
        })
        .collect();
    let nested = nest(&rings);
    for ring in &nested.bridged {
        fill_loop(g, &ring.corners, Some(&ring.q), options, plan, means);
    }
    // Holes in no loop, loops no bridge reached and loops with no area in
    // the plane are filled on their own.
    let flat = rings.iter().enumerate().filter(|(_, r)| r.area2 == 0.0);
    for k in nested.alone.into_iter().chain(flat.map(|(k, _)| k)) {
        fill_loop(g, members[k], None, options, plan, means);
    }
}

/// Appends the faces closing `ring` to `plan` (`q`: its corners in the
/// plane, given for a ring with holes bridged in); a fan's centre point and
/// corners go to `means` (points, vertices) to be averaged once built.
fn fill_loop(
    g: &Geometry,
    ring: &[LoopEdge],
    q: Option<&[DVec2]>,
    options: &FillOptions,
    plan: &mut Plan,
    means: &mut Means,
) {
    let source = ring[0].face;
    let corner = |plan: &mut Plan, e: &LoopEdge| {
        plan.vertex_points.push(e.from);
        plan.vertex_sources.push(copy(e.corner));
    };
    let face = |plan: &mut Plan, corners: &[usize]| {
        for &c in corners {
            corner(plan, &ring[c]);
        }
        plan.prim_counts.push(corners.len() as u32);
        plan.prim_kinds.push(PrimKind::Polygon);
        plan.prim_sources.push(source);
    };
    match options.mode {
        FillMode::Polygon => face(plan, &(0..ring.len()).collect::<Vec<_>>()),
        FillMode::Triangles => {
            // A fill triangle over three points of one face of the mesh
            // would lie on it, folded back (a loop turning a sharp corner
            // around a face's corner): avoided.
            let topo = g.topology();
            let avoid = |t: [u32; 3]| {
                let [a, b, c] = t.map(|i| ring[i as usize].from as usize);
                topo.point_prims(a)
                    .iter()
                    .any(|f| topo.point_prims(b).contains(f) && topo.point_prims(c).contains(f))
            };
            let tris = match q {
                Some(q) => ear_clip_avoiding(q, &avoid),
                None => triangles(g, ring, options.triangulation, &avoid),
            };
            for t in tris {
                face(plan, &t.map(|c| c as usize));
            }
        }
        FillMode::Fan => fan(g, ring, source, plan, means),
    }
}

/// Triangles over the loop's corners, wound as the loop, none that
/// `avoid` names where there is another way.
fn triangles(
    g: &Geometry,
    ring: &[LoopEdge],
    how: Triangulation,
    avoid: &dyn Fn([u32; 3]) -> bool,
) -> Vec<[u32; 3]> {
    let p: Vec<DVec3> = ring
        .iter()
        .map(|e| g.positions()[e.from as usize].as_dvec3())
        .collect();
    let centre = p.iter().sum::<DVec3>() / p.len() as f64;
    let (u, v) = plane_basis(newell_normal(&p));
    let q: Vec<DVec2> = p
        .iter()
        .map(|&x| DVec2::new((x - centre).dot(u), (x - centre).dot(v)))
        .collect();
    if how == Triangulation::MinWeight && p.len() <= MIN_WEIGHT_MAX {
        if let Some(t) = triangulate::min_weight(&p, &q, avoid) {
            return t;
        }
    }
    ear_clip_avoiding(&q, avoid)
}

/// A fan around a new centre point.
fn fan(g: &Geometry, ring: &[LoopEdge], source: u32, plan: &mut Plan, means: &mut Means) {
    let points: Vec<u32> = ring.iter().map(|e| e.from).collect();
    let sum: DVec3 = points
        .iter()
        .map(|&p| g.positions()[p as usize].as_dvec3())
        .sum();
    let centre = plan.positions.len() as u32;
    plan.positions.push((sum / points.len() as f64).as_vec3());
    plan.point_sources.push(copy(points[0]));
    means.points.push((centre, points));
    let corners: Vec<u32> = ring.iter().map(|e| e.corner).collect();
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (&ring[i], &ring[(i + 1) % n]);
        for (point, blend) in [
            (a.from, copy(a.corner)),
            (b.from, copy(b.corner)),
            (centre, copy(a.corner)),
        ] {
            plan.vertex_points.push(point);
            plan.vertex_sources.push(blend as Blend);
        }
        // The centre corner is averaged over the loop's corners, which
        // are source vertices: the output keeps them at the same numbers.
        means
            .vertices
            .push((plan.vertex_points.len() as u32 - 1, corners.clone()));
        plan.prim_counts.push(3);
        plan.prim_kinds.push(PrimKind::Polygon);
        plan.prim_sources.push(source);
    }
}
