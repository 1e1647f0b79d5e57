//! Bounds of point sets: the axis-aligned box, the oriented box and the
//! smallest enclosing sphere, as measures and as meshes; and Match Size,
//! which moves one geometry's bounds onto another's.
//!
//! - Axis-aligned: per-axis least and greatest coordinates (a parallel
//!   min/max, exact and order-free).
//! - Oriented (`oriented.rs`): the smallest box with a face on a face of
//!   the convex hull (`hull.rs`, quickhull), among the hull's largest
//!   face directions and its principal axes, then refined by rotating
//!   calipers about each axis of the best box.
//! - Sphere (`sphere.rs`): the exact minimum by Welzl's algorithm.
//!
//! Every bound is measured over the points only (a packed primitive
//! counts by its point; unpack first to bound its contents).

mod hull;
mod match_size;
mod oriented;
mod sphere;

use geode_geo::glam::Vec3;
use geode_geo::ops::Aabb;
use geode_geo::{primitives, Geometry};
use rayon::prelude::*;

pub use match_size::{match_size, match_transform, Justify, ScaleMode};
pub use oriented::{oriented_box, OrientedBox};
pub use sphere::{bounding_sphere, BoundingSphere};

/// The axis-aligned box of the points; None when there are none.
pub fn axis_aligned_box(points: &[Vec3]) -> Option<Aabb> {
    let b = points
        .par_chunks(1 << 16)
        .map(|c| {
            let mut b = Aabb::empty();
            for &p in c {
                b.include(p);
            }
            b
        })
        .reduce(Aabb::empty, |a, b| a.union(&b));
    (!b.is_empty()).then_some(b)
}

impl OrientedBox {
    /// An axis-aligned box as an oriented one (the world axes).
    pub fn from_aabb(b: &Aabb) -> OrientedBox {
        OrientedBox {
            center: b.center(),
            axes: [Vec3::X, Vec3::Y, Vec3::Z],
            half_size: b.size() * 0.5,
        }
    }

    /// The box grown by `padding` on every side.
    pub fn padded(&self, padding: f32) -> OrientedBox {
        OrientedBox {
            half_size: (self.half_size + Vec3::splat(padding)).max(Vec3::ZERO),
            ..*self
        }
    }
}

impl BoundingSphere {
    pub fn padded(&self, padding: f32) -> BoundingSphere {
        BoundingSphere {
            radius: (self.radius + padding).max(0.0),
            ..*self
        }
    }
}

/// A box as a closed mesh: 8 points, 6 outward quads.
pub fn box_geometry(b: &OrientedBox) -> Geometry {
    // Corner index bits pick the side along each axis (right-handed axes,
    // so each quad runs counter-clockwise seen from outside).
    const QUADS: [u32; 24] = [
        0, 4, 6, 2, // -axis 0
        1, 3, 7, 5, // +axis 0
        0, 1, 5, 4, // -axis 1
        2, 6, 7, 3, // +axis 1
        0, 2, 3, 1, // -axis 2
        4, 5, 7, 6, // +axis 2
    ];
    Geometry::from_polygons(b.corners().to_vec(), QUADS.to_vec(), &[4; 6])
        .expect("a box's quads are valid")
}

/// A sphere as a closed UV-sphere mesh whose points lie on it.
pub fn sphere_geometry(s: &BoundingSphere, columns: u32, rows: u32) -> Geometry {
    let mut g = primitives::uv_sphere(s.radius, columns, rows);
    for p in g.positions_mut() {
        *p += s.center;
    }
    g
}
