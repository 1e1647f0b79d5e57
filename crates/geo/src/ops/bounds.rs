//! Bounding boxes, enclosed volume and surface area.

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use crate::geometry::{Geometry, PrimKind};

/// An axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub fn empty() -> Aabb {
        Aabb {
            min: Vec3::splat(f32::INFINITY),
            max: Vec3::splat(f32::NEG_INFINITY),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    pub fn include(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    pub fn corners(&self) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            )
        })
    }

    /// The box enclosing this box after `m`.
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        let mut b = Aabb::empty();
        if !self.is_empty() {
            for c in self.corners() {
                b.include(m.transform_point3(c));
            }
        }
        b
    }
}

/// Bounds of all points and of every packed instance's transformed source
/// bounds; None when there is nothing.
pub fn bounds(g: &Geometry) -> Option<Aabb> {
    let pts = g
        .positions()
        .par_chunks(1 << 16)
        .map(|c| {
            let mut b = Aabb::empty();
            for &p in c {
                b.include(p);
            }
            b
        })
        .reduce(Aabb::empty, |a, b| a.union(&b));
    let mut b = pts;
    // Distinct sources' bounds computed once.
    let mut cache: std::collections::HashMap<*const Geometry, Option<Aabb>> = Default::default();
    for prim in 0..g.num_prims() {
        if let PrimKind::Packed(i) = g.prim_kind(prim) {
            let src = &g.packed_instances()[i as usize].source;
            let sb = *cache
                .entry(std::sync::Arc::as_ptr(src))
                .or_insert_with(|| bounds(src));
            if let (Some(sb), Some(m)) = (sb, g.packed_world_transform(prim)) {
                b = b.union(&sb.transformed(&m));
            }
        }
    }
    (!b.is_empty()).then_some(b)
}

/// Fan triangles of each polygon (first vertex as apex).
fn polygon_fans(g: &Geometry) -> impl ParallelIterator<Item = [Vec3; 3]> + '_ {
    let p = g.positions();
    (0..g.num_prims())
        .into_par_iter()
        .filter(move |&i| g.prim_kind(i) == PrimKind::Polygon)
        .flat_map_iter(move |i| {
            let pts = g.prim_points(i);
            (1..pts.len() - 1).map(move |k| {
                [
                    p[pts[0] as usize],
                    p[pts[k] as usize],
                    p[pts[k + 1] as usize],
                ]
            })
        })
}

/// Signed volume enclosed by the polygons (divergence theorem; positive for
/// outward, counter-clockwise winding). Accumulated in f64.
pub fn signed_volume(g: &Geometry) -> f32 {
    polygon_fans(g)
        .map(|[a, b, c]| a.as_dvec3().dot(b.as_dvec3().cross(c.as_dvec3())) / 6.0)
        .sum::<f64>() as f32
}

/// Total polygon area (fan triangulation). Accumulated in f64.
pub fn surface_area(g: &Geometry) -> f32 {
    polygon_fans(g)
        .map(|[a, b, c]| 0.5 * (b - a).as_dvec3().cross((c - a).as_dvec3()).length())
        .sum::<f64>() as f32
}
