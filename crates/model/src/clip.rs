//! Clipping by a plane (Houdini's Clip SOP): polygons and polylines cut
//! where they cross the plane, the part above it, below it or both kept,
//! and each cut loop optionally closed by a cap.
//!
//! Phases, each parallel over primitives in fixed chunks (so the result is
//! the same on any thread count):
//!
//! 1. Signed distances in f64; a point within a few f32 roundings of the
//!    plane counts as on it (no sliver is cut off next to it).
//! 2. The edges that cross (one end strictly above, the other strictly
//!    below) are gathered, sorted and deduplicated: one cut point per
//!    edge, computed from the edge's lower-numbered end, so both faces of
//!    an edge share it and the result stays welded.
//! 3. Each crossing polygon's ring, with its cut points inserted, is split
//!    per side into arcs (runs of corners not strictly on the other side).
//!    One arc is one piece, closed along the plane. Several arcs (a
//!    concave polygon crossing more than twice) are joined as the plane
//!    meets the polygon: their ends sorted along the cut line pair up into
//!    the segments inside it (so no piece bridges across a notch; when the
//!    pairs do not alternate, as in a polygon that twists, they are joined
//!    in ring order as Sutherland-Hodgman would). A polygon lying in the
//!    plane goes with the side its normal points away from (it bounds a
//!    solid on the other side). Polylines split into their runs.
//! 4. Caps. Every piece edge lying in the plane (the chords closing a cut
//!    piece, and the existing edges of faces that touch the plane) is
//!    counted per undirected edge; one used once on the capped side and at
//!    least once on the other bounds the cap (an input boundary edge lying
//!    in the plane does not). Reversed, those edges chain into loops (at a
//!    point where loops touch, the leftmost turn, keeping each loop
//!    simple). In the plane's 2D frame, seen from the cap's outside,
//!    outer loops wind anticlockwise and holes clockwise (a torus cut
//!    through its ring gives an annulus): each hole is bridged into the
//!    smallest outer loop holding it (the keyhole of earcut: a ray from
//!    the hole's rightmost point to a visible outer corner), and the ring
//!    is ear clipped or kept as one polygon. The caps' winding comes from
//!    the edges they close, so a consistently wound closed mesh gives a
//!    closed, consistently wound result.
//! 5. Assembly (`carry`): points and vertices on cuts blend their edge's
//!    two ends by the cut's parameter; pieces copy their source's
//!    primitive attributes and groups; caps take the attributes of the
//!    face across their first edge and, per corner, of that face's corner
//!    there, with vertex normals (type info `Normal`) set to the cap's.
//!
//! With both sides kept, cut points (and points on the plane) are shared
//! by the two sides unless `split_points` gives the side below its own
//! copies. Houdini's Clip leaves caps to a PolyCap or PolyFill after it;
//! here they are made in the same pass, with groups for each side and the
//! caps.

mod assemble;
mod caps;
mod pieces;

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{Geometry, PrimKind};
use rayon::prelude::*;

use crate::carry::{self, Blend};
use crate::ModelError;

/// What a clip keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Keep {
    Above,
    Below,
    Both,
}

impl Keep {
    pub const NAMES: &'static [&'static str] = &["above", "below", "both"];

    pub fn from_name(name: &str) -> Option<Keep> {
        Some(match name {
            "above" => Keep::Above,
            "below" => Keep::Below,
            "both" => Keep::Both,
            _ => return None,
        })
    }
}

/// How cut loops are closed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cap {
    /// Left open.
    None,
    /// One polygon per loop (holes joined to it by a keyhole bridge).
    Polygon,
    /// Ear-clipped triangles.
    Triangles,
}

impl Cap {
    pub const NAMES: &'static [&'static str] = &["none", "polygon", "triangles"];

    pub fn from_name(name: &str) -> Option<Cap> {
        Some(match name {
            "none" => Cap::None,
            "polygon" => Cap::Polygon,
            "triangles" => Cap::Triangles,
            _ => return None,
        })
    }
}

#[derive(Clone, Debug)]
pub struct ClipOptions {
    /// A point of the plane (before `distance`).
    pub origin: Vec3,
    /// The plane's normal: "above" is the side it points to.
    pub normal: Vec3,
    /// The plane moved this far along its normal.
    pub distance: f32,
    pub keep: Keep,
    pub cap: Cap,
    /// With both sides kept: the side below gets its own copies of the
    /// points on the cut.
    pub split_points: bool,
    /// Primitive groups of each side's faces (caps included) and of the
    /// caps; empty names make no group.
    pub above_group: String,
    pub below_group: String,
    pub cap_group: String,
}

impl Default for ClipOptions {
    fn default() -> Self {
        ClipOptions {
            origin: Vec3::ZERO,
            normal: Vec3::Y,
            distance: 0.0,
            keep: Keep::Above,
            cap: Cap::None,
            split_points: false,
            above_group: "above".into(),
            below_group: "below".into(),
            cap_group: "cap".into(),
        }
    }
}

/// A clipped geometry and what its caps did.
#[derive(Debug)]
pub struct Clipped {
    pub geometry: Geometry,
    /// Cap faces made.
    pub caps: usize,
    /// Chains of cut edges that did not close (an open or non-manifold
    /// input), left uncapped.
    pub open_loops: usize,
}

const ABOVE: u8 = 0;
const BELOW: u8 = 1;
const CHUNK: usize = 1 << 12;

/// Clips `g` by the plane of `options` (see the module doc).
pub fn clip(
    g: &Geometry,
    options: &ClipOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Clipped, ModelError> {
    carry::polygons_and_polylines(g, "clip")?;
    let normal = options.normal.as_dvec3();
    if !normal.is_finite() || normal.length() == 0.0 {
        return Err(ModelError::Invalid(
            "the clip plane's normal has no direction".into(),
        ));
    }
    let field = Field::new(g, options);
    let cuts = Cuts::new(g, &field, cancel)?;
    let split = Splitter {
        g,
        field: &field,
        cuts: &cuts,
        keep: options.keep,
        capping: options.cap != Cap::None,
        split_points: options.split_points && options.keep == Keep::Both,
    };
    let mut parts = split.run(cancel)?;
    let first_cap = parts.pieces.len();
    let mut open_loops = 0;
    if options.cap != Cap::None {
        for side in [ABOVE, BELOW] {
            if split.kept(side) {
                open_loops += split.caps(&mut parts, side, options.cap, cancel)?;
            }
        }
    }
    let caps = parts.pieces.len() - first_cap;
    let out = split.assemble(parts, first_cap, options, cancel)?;
    Ok(Clipped {
        geometry: out,
        caps,
        open_loops,
    })
}

/// Signed distances to the plane and each point's side: 1 above, -1
/// below, 0 on the plane.
struct Field {
    normal: DVec3,
    distance: Vec<f64>,
    class: Vec<i8>,
}

impl Field {
    fn new(g: &Geometry, options: &ClipOptions) -> Field {
        let n = options.normal.as_dvec3().normalize();
        let o = options.origin.as_dvec3() + n * options.distance as f64;
        let p = g.positions();
        let distance: Vec<f64> = p
            .par_iter()
            .with_min_len(CHUNK)
            .map(|x| (x.as_dvec3() - o).dot(n))
            .collect();
        let extent = p
            .par_iter()
            .with_min_len(CHUNK)
            .map(|x| x.abs().max_element())
            .reduce(|| 0.0, f32::max) as f64;
        let scale = extent
            .max(o.abs().max_element())
            .max(f32::MIN_POSITIVE as f64);
        let eps = 4.0 * f32::EPSILON as f64 * scale;
        let class = distance
            .par_iter()
            .with_min_len(CHUNK)
            .map(|&s| {
                if s > eps {
                    1
                } else if s < -eps {
                    -1
                } else {
                    0
                }
            })
            .collect();
        Field {
            normal: n,
            distance,
            class,
        }
    }
}

/// The cut points: one per crossing edge `(lo, hi)`, at parameter `t`
/// from `lo` to `hi`.
struct Cuts {
    keys: Vec<u64>,
    t: Vec<f64>,
    positions: Vec<DVec3>,
}

fn edge_key(a: u32, b: u32) -> u64 {
    (a.min(b) as u64) << 32 | a.max(b) as u64
}

impl Cuts {
    fn new(
        g: &Geometry,
        field: &Field,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<Cuts, ModelError> {
        let cls = &field.class;
        let chunks: Option<Vec<Vec<u64>>> = (0..g.num_prims().div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                if cancel() {
                    return None;
                }
                let mut keys = Vec::new();
                for prim in c * CHUNK..((c + 1) * CHUNK).min(g.num_prims()) {
                    let pts = g.prim_points(prim);
                    let segments = match g.prim_kind(prim) {
                        PrimKind::Polygon => pts.len(),
                        _ => pts.len().saturating_sub(1),
                    };
                    for k in 0..segments {
                        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
                        if cls[a as usize] * cls[b as usize] < 0 {
                            keys.push(edge_key(a, b));
                        }
                    }
                }
                Some(keys)
            })
            .collect();
        let mut keys: Vec<u64> = chunks.ok_or(ModelError::Cancelled)?.concat();
        keys.par_sort_unstable();
        keys.dedup();
        let p = g.positions();
        let (t, positions) = keys
            .par_iter()
            .map(|&k| {
                let (lo, hi) = ((k >> 32) as usize, k as u32 as usize);
                let (sa, sb) = (field.distance[lo], field.distance[hi]);
                let t = sa / (sa - sb);
                let (a, b) = (p[lo].as_dvec3(), p[hi].as_dvec3());
                (t, a + (b - a) * t)
            })
            .unzip();
        Ok(Cuts { keys, t, positions })
    }

    /// The cut on edge `a`-`b`: its number and its parameter from `a`.
    fn find(&self, a: u32, b: u32) -> (u32, f64) {
        let j = self
            .keys
            .binary_search(&edge_key(a, b))
            .expect("every crossing edge has a cut");
        let t = self.t[j];
        (j as u32, if a < b { t } else { 1.0 - t })
    }

    fn len(&self) -> usize {
        self.keys.len()
    }
}

/// An output primitive: a piece of a source primitive, or a cap.
#[derive(Clone, Copy)]
struct Piece {
    closed: bool,
    count: u32,
    source: u32,
    side: u8,
}

/// A corner of an output primitive: its point (a reference: source point,
/// cut, or a copy of either for the side below) and vertex blend.
#[derive(Clone, Copy)]
struct Corner {
    r: u32,
    vb: Blend,
}

/// An edge of a piece lying in the plane (references before copies).
#[derive(Clone, Copy)]
struct PlaneEdge {
    key: u64,
    from: u32,
    to: u32,
    side: u8,
    face: u32,
    /// The piece's vertex at `to` (where a cap's corner starts).
    to_vb: Blend,
}

/// A corner of a split ring: reference, side class, vertex blend.
#[derive(Clone, Copy)]
struct Entry {
    r: u32,
    c: i8,
    vb: Blend,
}

#[derive(Default)]
struct Parts {
    pieces: Vec<Piece>,
    corners: Vec<Corner>,
    plane_edges: Vec<PlaneEdge>,
}

impl Parts {
    fn extend(&mut self, other: Parts) {
        self.pieces.extend(other.pieces);
        self.corners.extend(other.corners);
        self.plane_edges.extend(other.plane_edges);
    }
}

struct Splitter<'a> {
    g: &'a Geometry,
    field: &'a Field,
    cuts: &'a Cuts,
    keep: Keep,
    capping: bool,
    split_points: bool,
}
