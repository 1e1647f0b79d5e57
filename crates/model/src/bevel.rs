//! Bevel of polygon meshes (Houdini's PolyBevel, Blender's Bevel): edges
//! (all, those between two points of a group, or those whose faces meet
//! at more than an angle) or points are cut back by an offset measured
//! along the faces, the cut filled by strips of `segments` quads along
//! each bevelled edge following a profile (Blender's superellipse: 0.5 a
//! circular arc, 0.25 a straight chamfer, 1 a square corner) and patches
//! over the corners.
//!
//! Each bevelled point is worked out on its own (`corner`): its fan of
//! faces, where its new points go for an offset of 1, how far they reach
//! along each edge. Clamping ("Clamp Overlap") then lowers the offset to
//! the largest for which no edge's two ends reach past each other, so
//! new points never pass the far end of an edge or cross a neighbouring
//! bevel's (one offset for the whole mesh, as Blender's clamp, so the
//! bevel stays even). Then every point's new points, chains, profiles
//! and patches are made at that offset (in parallel, each point alone)
//! and joined in point order (`assemble`), so the output is the same on
//! any thread count. A closed manifold input stays closed and keeps its
//! Euler characteristic. Boundary edges are never bevelled (they have
//! one face, as in Blender); at a boundary point the bevel's outline
//! becomes the boundary.

mod assemble;
mod corner;
mod mesh;
mod patch;

use geode_geo::glam::Vec3;
use geode_geo::{ops, Geometry, Group};
use rayon::prelude::*;

use crate::ModelError;
use corner::{Layout, Mesh};
use mesh::{HalfEdges, NONE};

/// What is bevelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Affect {
    /// Edges: a strip along each, patches where they meet.
    Edges,
    /// Points (Blender's Vertices): each corner cut off, a patch over it.
    Points,
}

impl Affect {
    pub const NAMES: &'static [&'static str] = &["edges", "points"];

    pub fn from_name(name: &str) -> Option<Affect> {
        match name {
            "edges" => Some(Affect::Edges),
            "points" => Some(Affect::Points),
            _ => None,
        }
    }
}

/// How to bevel.
#[derive(Clone, Debug)]
pub struct Bevel {
    pub affect: Affect,
    /// Distance along the faces from the edge (or along the edges from
    /// the point) to the cut.
    pub offset: f32,
    /// Segments across each bevel (at least 1).
    pub segments: u32,
    /// Blender's profile shape, 0..1 (0.5 circular).
    pub profile: f32,
    /// Lower the offset where bevels would overlap.
    pub clamp: bool,
    /// Edges mode: skip edges whose faces' normals are within this many
    /// degrees (Houdini's Ignore Flat Edges); `None` bevels them all.
    pub flat_angle: Option<f32>,
    /// Names of the groups of the edge strips and of the corner patches
    /// (empty: no group).
    pub edge_group: String,
    pub corner_group: String,
}

pub const EDGE_GROUP: &str = "bevelEdges";
pub const CORNER_GROUP: &str = "bevelCorners";

impl Default for Bevel {
    fn default() -> Bevel {
        Bevel {
            affect: Affect::Edges,
            offset: 0.1,
            segments: 1,
            profile: 0.5,
            clamp: true,
            flat_angle: None,
            edge_group: EDGE_GROUP.into(),
            corner_group: CORNER_GROUP.into(),
        }
    }
}

/// What a bevel did besides its geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// The offset used (lower than asked where clamping lowered it).
    pub offset: f32,
    /// The largest offset at which no two bevels overlap (the clamp's
    /// limit, reported with clamping off too).
    pub limit: f32,
}

/// Bevels `g`: in edges mode the edges between two points of `group`
/// (all when `None`), in points mode the points of `group`.
pub fn bevel(
    g: &Geometry,
    group: Option<&Group>,
    how: &Bevel,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Geometry, Report), ModelError> {
    check(how)?;
    let stop = || ModelError::unless_cancelled(cancel);
    let he = HalfEdges::new(g)?;
    stop()?;
    let normals: Vec<Vec3> = (0..g.num_prims())
        .into_par_iter()
        .map(|k| ops::polygon_normal(g.positions(), g.prim_points(k)).normalize_or_zero())
        .collect();
    let in_group = |p: u32| group.is_none_or(|s| s.contains(p as usize));
    let points_mode = how.affect == Affect::Points;
    let mut bevelled = if points_mode {
        vec![false; g.num_vertices()]
    } else {
        select_edges(g, &he, &normals, &in_group, how.flat_angle)
    };
    stop()?;
    let mut affected = vec![false; g.num_points()];
    for h in 0..g.num_vertices() {
        let p = g.vertex_points()[h] as usize;
        affected[p] |= if points_mode {
            in_group(p as u32)
        } else {
            bevelled[h] || bevelled[he.prev(g, h as u32) as usize]
        };
    }
    // No width, no bevel: the input's faces come back as they were (with
    // the new faces' groups, empty), as Houdini's PolyBevel at distance 0.
    if how.offset == 0.0 {
        affected.iter_mut().for_each(|a| *a = false);
        bevelled.iter_mut().for_each(|b| *b = false);
    }
    let list: Vec<u32> = (0..g.num_points() as u32)
        .filter(|&p| affected[p as usize])
        .collect();
    let mesh = Mesh {
        g,
        he: &he,
        bevelled: &bevelled,
        normals: &normals,
        points_mode,
    };
    let layouts: Vec<Layout> = in_chunks(&list, cancel, |&p| {
        let (fan, closed) = he.fan(g, p)?;
        Ok(Layout::new(&mesh, p, fan, closed))
    })?;
    let most = limit(&layouts);
    let offset = if how.clamp {
        how.offset.min(most)
    } else {
        how.offset
    };
    stop()?;
    let e = patch::exponent(how.profile);
    let corners = in_chunks(&layouts, cancel, |l| {
        Ok(l.build(&mesh, offset, how.segments, e))
    })?;
    stop()?;
    let out = assemble::assemble(
        g,
        &he,
        &bevelled,
        &corners,
        &affected,
        (&how.edge_group, &how.corner_group),
        cancel,
    )?;
    Ok((
        out,
        Report {
            offset,
            limit: most,
        },
    ))
}

fn check(how: &Bevel) -> Result<(), ModelError> {
    let bad = |why: String| Err(ModelError::Invalid(why));
    if !how.offset.is_finite() || how.offset < 0.0 {
        return bad(format!("offset must be zero or more, not {}", how.offset));
    }
    if how.segments == 0 || how.segments > 1024 {
        return bad(format!(
            "segments must be between 1 and 1024, not {}",
            how.segments
        ));
    }
    if !(0.0..=1.0).contains(&how.profile) {
        return bad(format!(
            "profile must be between 0 and 1, not {}",
            how.profile
        ));
    }
    if let Some(a) = how.flat_angle {
        if !(0.0..=180.0).contains(&a) {
            return bad(format!(
                "the flat angle must be between 0 and 180 degrees, not {a}"
            ));
        }
    }
    if !how.edge_group.is_empty() && how.edge_group == how.corner_group {
        return bad(format!(
            "the edge and corner groups need different names (both `{}`)",
            how.edge_group
        ));
    }
    Ok(())
}

/// Per half-edge: whether its edge is bevelled (two faces, both ends in
/// the group, and sharper than the flat angle).
fn select_edges(
    g: &Geometry,
    he: &HalfEdges,
    normals: &[Vec3],
    in_group: &(dyn Fn(u32) -> bool + Sync),
    flat_angle: Option<f32>,
) -> Vec<bool> {
    let cos_flat = flat_angle.map(|a| a.to_radians().cos());
    (0..g.num_vertices() as u32)
        .into_par_iter()
        .map(|h| {
            let t = he.twin[h as usize];
            if t == NONE || !in_group(he.origin(g, h)) || !in_group(he.dest(g, h)) {
                return false;
            }
            cos_flat.is_none_or(|c| {
                let (a, b) = (he.face[h as usize], he.face[t as usize]);
                normals[a as usize].dot(normals[b as usize]) < c
            })
        })
        .collect()
}

/// The largest offset for which no edge's two ends reach past each other:
/// the ends' reaches (at offset 1) summed per edge, sorted so the sum is
/// the same on any thread count.
fn limit(layouts: &[Layout]) -> f32 {
    let mut reach: Vec<(u32, u32, f32, f32)> = layouts
        .par_iter()
        .flat_map_iter(|l| {
            l.reaches()
                .map(move |(far, r, len)| (l.v.min(far), l.v.max(far), r, len))
        })
        .collect();
    reach.par_sort_unstable_by(|a, b| (a.0, a.1, a.2.to_bits()).cmp(&(b.0, b.1, b.2.to_bits())));
    let mut best = f32::INFINITY;
    let mut k = 0;
    while k < reach.len() {
        // Both ends of an edge report it; their reaches add up.
        let mut e = k;
        let mut sum = 0.0;
        while e < reach.len() && (reach[e].0, reach[e].1) == (reach[k].0, reach[k].1) {
            sum += reach[e].2;
            e += 1;
        }
        if sum > 0.0 {
            best = best.min(reach[k].3 / sum);
        }
        k = e;
    }
    best
}

/// `f` over `items` in parallel, in order, cancellable every 512 items
/// (the first error ends the collect).
fn in_chunks<T: Sync, R: Send>(
    items: &[T],
    cancel: &(dyn Fn() -> bool + Sync),
    f: impl Fn(&T) -> Result<R, ModelError> + Sync,
) -> Result<Vec<R>, ModelError> {
    let parts: Vec<Vec<R>> = items
        .par_chunks(512)
        .map(|chunk| {
            if cancel() {
                return Err(ModelError::Cancelled);
            }
            chunk.iter().map(&f).collect()
        })
        .collect::<Result<_, _>>()?;
    let mut out = Vec::with_capacity(items.len());
    for part in parts {
        out.extend(part);
    }
    Ok(out)
}
