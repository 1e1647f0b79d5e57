//! Mirroring across a plane (Houdini's Mirror SOP): the input reflected,
//! by default beside the original, its winding reversed so normals stay
//! outward, and the seam fused so a half model becomes one closed piece.
//!
//! The reflection `p - 2((p - o)·n) n` is an affine map applied by
//! `geode_geo::ops::transformed`, so every attribute follows its type
//! info: positions (P and any `Position` attribute) reflect about the
//! plane, vectors (`Vector`: v, up) reflect, normals (`Normal`: N) reflect
//! by the inverse transpose (the reflection itself), packed instances turn.
//! Quaternions cannot hold a reflection (it is not a rotation); they take
//! the map's rotation part, as a transform does.
//!
//! The seam: points of the original within `fuse_distance` of the plane
//! are moved onto it and their mirror images dropped, the mirrored faces
//! using the original points instead (a correspondence, not a search: two
//! distinct points of the original near each other are never fused, as a
//! general fuse would). A mirrored face or polyline lying wholly on the
//! seam would repeat the original's, reversed, and is not made; an
//! original face on the seam closed in by other faces on all its edges
//! (a capped half model's cap) would be a wall inside the whole and goes
//! too.

use geode_geo::glam::{DVec3, Mat4, Vec3, Vec4};
use geode_geo::{ops, Geometry, Group};
use rayon::prelude::*;

use crate::carry::{self, copy, Plan};
use crate::ModelError;

#[derive(Clone, Debug)]
pub struct MirrorOptions {
    /// A point of the mirror plane.
    pub origin: Vec3,
    /// The plane's normal.
    pub normal: Vec3,
    /// Keep the input beside its mirror image (else the image alone).
    pub keep_original: bool,
    /// Reverse the mirror image's winding (so its normals face out).
    pub reverse: bool,
    /// Fuse the original's points within `fuse_distance` of the plane
    /// with their images.
    pub fuse: bool,
    pub fuse_distance: f32,
    /// The primitive group of the mirror image (empty: none).
    pub group: String,
}

impl Default for MirrorOptions {
    fn default() -> Self {
        MirrorOptions {
            origin: Vec3::ZERO,
            normal: Vec3::X,
            keep_original: true,
            reverse: true,
            fuse: true,
            fuse_distance: 1e-3,
            group: "mirror".into(),
        }
    }
}

/// A mirrored geometry and how many points its seam fused.
#[derive(Debug)]
pub struct Mirrored {
    pub geometry: Geometry,
    pub seam_points: usize,
}

/// Mirrors `g` (see the module doc).
pub fn mirror(
    g: &Geometry,
    options: &MirrorOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Mirrored, ModelError> {
    let n = options.normal.as_dvec3();
    if !n.is_finite() || n.length() == 0.0 {
        return Err(ModelError::Invalid(
            "the mirror plane's normal has no direction".into(),
        ));
    }
    let n = n.normalize();
    let o = options.origin.as_dvec3();
    let mut image = ops::transformed(g, reflection(o, n));
    if options.reverse {
        ops::reverse_prims(&mut image, None);
    }
    let failed = |e: geode_geo::GeoError| ModelError::Failed {
        op: "mirror",
        why: e.to_string(),
    };
    if !options.group.is_empty() {
        let all = Group::from_flags((0..image.num_prims()).map(|_| true));
        image.set_prim_group(&options.group, all).map_err(failed)?;
    }
    if !options.keep_original {
        return Ok(Mirrored {
            geometry: image,
            seam_points: 0,
        });
    }
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    let seam: Vec<bool> = if options.fuse {
        let d = options.fuse_distance.max(0.0) as f64;
        g.positions()
            .par_iter()
            .map(|p| (p.as_dvec3() - o).dot(n).abs() <= d)
            .collect()
    } else {
        Vec::new()
    };
    let seam_points = seam.iter().filter(|&&s| s).count();
    let mut original = g.clone();
    // A polygon of the original wholly on the seam whose every edge has
    // another polygon (a capped half model's cap) would be a wall inside
    // the mirrored whole, its image the same face reversed: both go, and
    // the whole is closed. A sheet lying on the plane (its edges borders)
    // stays, once.
    if options.fuse {
        let walls = seam_walls(g, &seam);
        if walls.count() > 0 {
            ops::delete_prims(&mut original, &walls, false);
        }
    }
    if !options.group.is_empty() {
        original
            .set_prim_group(&options.group, Group::new(original.num_prims()))
            .map_err(failed)?;
    }
    if seam_points == 0 {
        let geometry = ops::merge(&[&original, &image]).map_err(failed)?;
        return Ok(Mirrored {
            geometry,
            seam_points,
        });
    }
    carry::polygons_and_polylines(g, "a mirror's seam fuse")?;
    let on_seam = Group::from_flags(
        (0..image.num_prims()).map(|p| image.prim_points(p).iter().all(|&q| seam[q as usize])),
    );
    ops::delete_prims(&mut image, &on_seam, false);
    let both = ops::merge(&[&original, &image]).map_err(failed)?;
    if cancel() {
        return Err(ModelError::Cancelled);
    }
    let geometry = carry::build(&both, fused(&both, &seam, o, n), "mirror", cancel)?;
    Ok(Mirrored {
        geometry,
        seam_points,
    })
}

/// The polygons of `g` wholly on the seam with another polygon on each
/// of their edges.
fn seam_walls(g: &Geometry, seam: &[bool]) -> Group {
    let on_seam = |k: usize| {
        g.prim_kinds()[k] == geode_geo::PrimKind::Polygon
            && g.prim_points(k).iter().all(|&q| seam[q as usize])
    };
    if !(0..g.num_prims()).any(on_seam) {
        return Group::new(g.num_prims());
    }
    let topo = g.topology();
    let closed_in = |k: usize| {
        g.prim_vertex_range(k).all(|v| {
            let e = topo.edge_of(geode_geo::HalfEdge(v as u32));
            topo.edge_half_edges(e).nth(1).is_some()
        })
    };
    Group::from_flags((0..g.num_prims()).map(|k| on_seam(k) && closed_in(k)))
}

/// The reflection across the plane through `o` with unit normal `n`.
fn reflection(o: DVec3, n: DVec3) -> Mat4 {
    let column = |axis: DVec3| (axis - 2.0 * axis.dot(n) * n).as_vec3();
    let shift = (2.0 * o.dot(n) * n).as_vec3();
    Mat4::from_cols(
        column(DVec3::X).extend(0.0),
        column(DVec3::Y).extend(0.0),
        column(DVec3::Z).extend(0.0),
        Vec4::new(shift.x, shift.y, shift.z, 1.0),
    )
}

/// The plan that keeps `both` (the original's points, then the image's)
/// with each seam point's image replaced by the seam point, moved onto
/// the plane.
fn fused(both: &Geometry, seam: &[bool], o: DVec3, n: DVec3) -> Plan {
    let np = seam.len();
    let p = both.positions();
    let mut index = vec![0u32; 2 * np];
    let mut plan = Plan::default();
    for (i, &s) in seam.iter().enumerate() {
        index[i] = i as u32;
        let x = p[i].as_dvec3();
        plan.positions.push(if s {
            (x - (x - o).dot(n) * n).as_vec3()
        } else {
            p[i]
        });
        plan.point_sources.push(copy(i as u32));
    }
    for (i, &s) in seam.iter().enumerate() {
        index[np + i] = if s {
            i as u32
        } else {
            plan.positions.push(p[np + i]);
            plan.point_sources.push(copy((np + i) as u32));
            plan.positions.len() as u32 - 1
        };
    }
    plan.vertex_points = both
        .vertex_points()
        .iter()
        .map(|&q| index[q as usize])
        .collect();
    plan.vertex_sources = (0..both.num_vertices() as u32).map(copy).collect();
    let nprims = both.num_prims();
    plan.prim_counts = (0..nprims)
        .map(|k| both.prim_vertex_range(k).len() as u32)
        .collect();
    plan.prim_kinds = both.prim_kinds().to_vec();
    plan.prim_sources = (0..nprims as u32).collect();
    plan.first_new_prim = nprims;
    plan
}
