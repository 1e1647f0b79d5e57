//! Curves as geode stores them: an open polyline primitive, or a closed
//! polygon read as a closed curve (Houdini's convention), over shared points.

use geode_geo::{Geometry, PrimKind};

/// One curve of a geometry: its primitive and the points it visits.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Curve {
    pub prim: usize,
    pub points: Vec<u32>,
    pub closed: bool,
}

/// Every polyline (open) and polygon (closed) of `g`, in primitive order;
/// packed primitives are not curves.
pub fn curves(g: &Geometry) -> Vec<Curve> {
    (0..g.num_prims())
        .filter_map(|prim| {
            let closed = match g.prim_kind(prim) {
                PrimKind::Polyline => false,
                PrimKind::Polygon => true,
                PrimKind::Packed(_) | PrimKind::Patch(_) => return None,
            };
            Some(Curve {
                prim,
                points: g.prim_points(prim).to_vec(),
                closed,
            })
        })
        .collect()
}

/// Cumulative length at each point (0 at the first; for a closed curve the
/// closing segment is not included: the total length is returned apart).
pub fn arc_lengths(points: &[glam_d::DVec3], closed: bool) -> (Vec<f64>, f64) {
    let mut acc = Vec::with_capacity(points.len());
    let mut s = 0.0;
    for i in 0..points.len() {
        if i > 0 {
            s += points[i].distance(points[i - 1]);
        }
        acc.push(s);
    }
    let total = if closed && points.len() > 1 {
        s + points[points.len() - 1].distance(points[0])
    } else {
        s
    };
    (acc, total)
}

/// glam's f64 types under a short name (curves are computed in f64 so frames
/// stay orthonormal to 1e-12 and convergence tests see the method, not f32).
pub mod glam_d {
    pub use geode_geo::glam::{DMat3, DQuat, DVec2, DVec3};
}
