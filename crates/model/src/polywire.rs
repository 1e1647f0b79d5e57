//! Tubes around every edge of polylines and polygons (Houdini's PolyWire),
//! joined into one closed surface where edges meet.
//!
//! The skeleton's distinct edges form chains between points where it ends
//! or branches (`graph`). Each chain is one tube (`tube`): a ring of
//! `divisions` points every `1 / segments` of each edge, frames carried
//! along the chain by parallel transport (no twist; a loop spreads its
//! leftover turn evenly), and at a point where two edges meet one mitred
//! ring on the plane bisecting the bend, shared by both (narrowed where its
//! inner side would reach past half of either edge). Where three or
//! more edges meet, each tube stops at a ring some way out and the convex
//! hull of those rings closes the joint (`joint`, which also says how far
//! out and when rings are narrowed, and which nearly parallel twigs it
//! leaves out of the hull, capped inside a kept tube). Free ends are capped with their ring
//! as one polygon when asked. A tree or graph skeleton so gives one closed
//! manifold: every edge of the output in exactly two faces, wound outward.
//!
//! Radius: `radius`, times the point attribute named (Houdini's wire
//! radius is usually `@pscale` written into the parameter), blended along
//! each edge. Ring points blend their edge's two source points (point
//! attributes and groups follow, as `carry` does), vertices their edge's
//! source vertices, faces copy their edge's primitive (a joint's
//! triangles its first tube's). `uv` (optional, per vertex): u around
//! each tube (0 to 1, a seam at the frame's u axis), v by arc length along
//! its chain; a joint's triangles take their points' uv.
//!
//! Twigs a crowded joint leaves out are closed pieces overlapping the kept
//! tubes; with `union` (the default) the pieces are then unioned through
//! the boolean (`boolean::union_pieces`) into one solid of triangles.
//!
//! Unlike Houdini, whose joints are separate tubes overlapping at shared
//! points (not closed), the joints here are closed hulls; a mitre's
//! stretch is bounded at sharp bends (Houdini's is too, differently).

mod graph;
mod joint;
mod tube;

use geode_geo::glam::Vec2;
use geode_geo::{AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, TypeInfo};
use rayon::prelude::*;

use crate::carry::{self, Blend, Plan};
use crate::ModelError;
use graph::Skeleton;
use joint::{End, Joint};
use tube::{Ring, Shape};

#[derive(Clone, Debug)]
pub struct PolywireOptions {
    pub radius: f32,
    /// A float or int point attribute multiplying the radius (None: the
    /// radius alone).
    pub radius_attribute: Option<String>,
    /// Points around each ring (at least 3).
    pub divisions: u32,
    /// Rings across each edge (at least 1).
    pub segments: u32,
    /// Close free ends with their ring.
    pub caps: bool,
    /// Write vertex `uv`.
    pub uv: bool,
    /// Where a crowded joint left twigs out (capped inside a kept tube),
    /// union the overlapping closed pieces into one solid (through the
    /// boolean; the result is then triangles).
    pub union: bool,
}

impl Default for PolywireOptions {
    fn default() -> Self {
        PolywireOptions {
            radius: 0.1,
            radius_attribute: None,
            divisions: 8,
            segments: 1,
            caps: true,
            uv: false,
            union: true,
        }
    }
}

/// Tubes around the edges of `g`'s primitives in `group` (all when None);
/// see the module doc.
pub fn polywire(
    g: &Geometry,
    group: Option<&Group>,
    options: &PolywireOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    carry::polygons_and_polylines(g, "polywire")?;
    let radius = radii(g, options)?;
    if options.divisions < 3 {
        return Err(ModelError::Invalid(format!(
            "polywire needs at least 3 divisions around (got {})",
            options.divisions
        )));
    }
    if options.segments < 1 {
        return Err(ModelError::Invalid(
            "polywire needs at least 1 segment along each edge".into(),
        ));
    }
    let (n, segments) = (options.divisions as usize, options.segments as usize);
    let skeleton = Skeleton::new(g, group, cancel)?;
    let p = g.positions();
    let shapes: Vec<Shape> = skeleton
        .chains
        .par_iter()
        .map(|c| Shape::new(c, &skeleton.edges, p, &|i| radius[i as usize]))
        .collect();
    let joints = joints(&skeleton, &shapes, n, cancel)?;
    // Per chain end: its distance and scale at a joint, and whether the
    // joint leaves it out of its hull (capped there).
    let mut ends = vec![[(0.0, 1.0, false); 2]; shapes.len()];
    for j in &joints {
        for (e, &d) in j.ends.iter().zip(&j.distance) {
            ends[e.chain as usize][usize::from(!e.at_start)] = (d, j.scale, false);
        }
        for &(e, d) in &j.capped {
            ends[e.chain as usize][usize::from(!e.at_start)] = (d, 1.0, true);
        }
    }
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    let pieces: Vec<Piece> = shapes
        .par_iter()
        .zip(&skeleton.chains)
        .zip(&ends)
        .map(|((shape, chain), &[(d0, s0, c0), (d1, s1, c1)])| {
            let free = |p: u32| skeleton.valence(p) == 1;
            let caps = [
                c0 || options.caps && !chain.closed && free(chain.points[0]),
                c1 || options.caps && !chain.closed && free(*chain.points.last().expect("points")),
            ];
            let rings = shape.rings(d0, shape.length() - d1, [s0, s1], n, segments);
            Piece::tube(rings, shape.closed, caps, n)
        })
        .collect();
    let mut out = Output::default();
    let mut first_ring = Vec::with_capacity(pieces.len());
    for (k, piece) in pieces.into_iter().enumerate() {
        if k % 1024 == 0 && cancel() {
            return Err(ModelError::Cancelled);
        }
        first_ring.push(out.append(piece));
    }
    for j in &joints {
        out.joint(j, &first_ring);
    }
    let wire = out.finish(g, options.uv, cancel)?;
    if options.union && joints.iter().any(|j| !j.capped.is_empty()) {
        crate::boolean::union_pieces(&wire, cancel)
    } else {
        Ok(wire)
    }
}

/// Each point's radius: the option times the attribute when named.
fn radii(g: &Geometry, options: &PolywireOptions) -> Result<Vec<f64>, ModelError> {
    let r = options.radius as f64;
    if !r.is_finite() || r <= 0.0 {
        return Err(ModelError::Invalid(format!(
            "the wire radius must be positive (got {})",
            options.radius
        )));
    }
    let Some(name) = options
        .radius_attribute
        .as_deref()
        .filter(|n| !n.is_empty())
    else {
        return Ok(vec![r; g.num_points()]);
    };
    let column = geode_geo::ops::point_scalar(g, name)
        .map_err(|e| ModelError::Invalid(e.to_string()))?
        .ok_or_else(|| {
            ModelError::Invalid(format!(
                "there is no point attribute `{name}` for the radius"
            ))
        })?;
    (0..g.num_points())
        .map(|i| {
            let x = r * column.get(i) as f64;
            if x.is_finite() && x > 0.0 {
                Ok(x)
            } else {
                Err(ModelError::Invalid(format!(
                    "point {i}'s radius ({name} {} x radius {r}) is not positive",
                    column.get(i)
                )))
            }
        })
        .collect()
}

/// Solves every joint (points where three or more edges meet), in point
/// order.
fn joints(
    skeleton: &Skeleton,
    shapes: &[Shape],
    n: usize,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Vec<Joint>, ModelError> {
    let mut at: Vec<Vec<End>> = vec![Vec::new(); skeleton.incident.len()];
    for (c, chain) in skeleton.chains.iter().enumerate() {
        if chain.closed {
            continue;
        }
        let (first, last) = (chain.points[0], *chain.points.last().expect("points"));
        let chain = c as u32;
        at[first as usize].push(End {
            chain,
            at_start: true,
        });
        at[last as usize].push(End {
            chain,
            at_start: false,
        });
    }
    let free_far_end = |c: u32| {
        let ch = &skeleton.chains[c as usize];
        let (a, b) = (ch.points[0], *ch.points.last().expect("points"));
        skeleton.valence(a) == 1 || skeleton.valence(b) == 1
    };
    at.into_par_iter()
        .filter(|ends| ends.len() >= 3)
        .map(|ends| joint::solve(ends, shapes, &free_far_end, n, cancel))
        .collect()
}

/// One chain's tube before numbering: rings, and faces over its own
/// points (ring `i`'s point `j` is `i * n + j`).
struct Piece {
    rings: Vec<Ring>,
    /// Faces: their first vertex, seam flags per vertex, source prim.
    counts: Vec<u32>,
    corners: Vec<u32>,
    seam: Vec<bool>,
    prims: Vec<u32>,
}

impl Piece {
    fn tube(rings: Vec<Ring>, closed: bool, caps: [bool; 2], n: usize) -> Piece {
        let mut piece = Piece {
            rings,
            counts: Vec::new(),
            corners: Vec::new(),
            seam: Vec::new(),
            prims: Vec::new(),
        };
        let count = piece.rings.len();
        let spans = if closed { count } else { count - 1 };
        for i in 0..spans {
            let next = (i + 1) % count;
            // A ring names the edge it starts (a mitre the edge after its
            // point), so the span's faces take its primitive.
            let prim = piece.rings[i].prim;
            for j in 0..n {
                let j1 = (j + 1) % n;
                let quad = [i * n + j, i * n + j1, next * n + j1, next * n + j];
                piece.face(&quad, &[false, j1 == 0, j1 == 0, false], prim);
            }
        }
        if caps[0] {
            let ring: Vec<usize> = (0..n).rev().collect();
            piece.face(&ring, &vec![false; n], piece.rings[0].prim);
        }
        if caps[1] {
            let last = (count - 1) * n;
            let ring: Vec<usize> = (last..last + n).collect();
            piece.face(&ring, &vec![false; n], piece.rings[count - 1].prim);
        }
        piece
    }

    fn face(&mut self, corners: &[usize], seam: &[bool], prim: u32) {
        self.counts.push(corners.len() as u32);
        self.corners.extend(corners.iter().map(|&c| c as u32));
        self.seam.extend_from_slice(seam);
        self.prims.push(prim);
    }
}

/// The output plan, with each point's vertex blend and uv.
#[derive(Default)]
struct Output {
    plan: Plan,
    point_vertex: Vec<Blend>,
    point_uv: Vec<Vec2>,
    vertex_uv: Vec<Vec2>,
    n: usize,
}

impl Output {
    /// Appends a tube; returns the output number of its first point.
    fn append(&mut self, piece: Piece) -> u32 {
        let first = self.plan.positions.len() as u32;
        let n = piece.rings.first().map_or(0, |r| r.pts.len());
        self.n = n;
        for ring in &piece.rings {
            for (j, &x) in ring.pts.iter().enumerate() {
                self.plan.positions.push(x);
                self.plan.point_sources.push(ring.point_blend);
                self.point_vertex.push(ring.vertex_blend);
                self.point_uv.push(tube::uv(ring, j, n, false));
            }
        }
        for (&c, &seam) in piece.corners.iter().zip(&piece.seam) {
            let (ring, j) = (c as usize / n, c as usize % n);
            self.plan.vertex_points.push(first + c);
            self.plan
                .vertex_sources
                .push(piece.rings[ring].vertex_blend);
            self.vertex_uv
                .push(tube::uv(&piece.rings[ring], j, n, seam));
        }
        self.plan.prim_counts.extend_from_slice(&piece.counts);
        self.plan
            .prim_kinds
            .extend(std::iter::repeat_n(PrimKind::Polygon, piece.counts.len()));
        self.plan.prim_sources.extend_from_slice(&piece.prims);
        first
    }

    /// A joint's triangles over its tubes' end rings.
    fn joint(&mut self, joint: &Joint, first_ring: &[u32]) {
        let n = self.n as u32;
        let point = |(end, j): (u32, u32)| {
            let e = joint.ends[end as usize];
            let first = first_ring[e.chain as usize];
            let ring_start = if e.at_start {
                first
            } else {
                // The chain's points run to the next chain's first point.
                let next = first_ring
                    .get(e.chain as usize + 1)
                    .copied()
                    .unwrap_or(self.plan.positions.len() as u32);
                next - n
            };
            ring_start + j
        };
        for t in &joint.triangles {
            for &c in t {
                let p = point(c);
                self.plan.vertex_points.push(p);
                self.plan.vertex_sources.push(self.point_vertex[p as usize]);
                self.vertex_uv.push(self.point_uv[p as usize]);
            }
            self.plan.prim_counts.push(3);
            self.plan.prim_kinds.push(PrimKind::Polygon);
            self.plan.prim_sources.push(joint.prim);
        }
    }

    fn finish(
        mut self,
        g: &Geometry,
        uv: bool,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Geometry, ModelError> {
        self.plan.first_new_prim = usize::MAX;
        let mut out = carry::build(g, self.plan, "polywire", cancel)?;
        if uv {
            // The tubes' uv replaces a carried one of another class (a
            // grid's point uv): one `uv`, as Houdini keeps one per name.
            let failed = |e: geode_geo::GeoError| ModelError::Failed {
                op: "polywire",
                why: e.to_string(),
            };
            for class in [AttribClass::Point, AttribClass::Primitive] {
                out.remove_attrib(class, "uv").map_err(failed)?;
            }
            let column = Attribute::from_data(AttribData::Vec2(self.vertex_uv), TypeInfo::TexCoord);
            out.set_attrib(AttribClass::Vertex, "uv", column)
                .map_err(failed)?;
        }
        Ok(out)
    }
}
