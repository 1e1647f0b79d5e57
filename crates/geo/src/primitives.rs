//! Polygon mesh primitives (box, grid, sphere, torus, tube), outward-facing, counter-clockwise.

use glam::{Vec2, Vec3};
use std::f64::consts::TAU;

use crate::attrib::{AttribClass, AttribData, Attribute, TypeInfo};
use crate::geometry::Geometry;

fn build(positions: Vec<Vec3>, faces: Vec<u32>, counts: Vec<u32>) -> Geometry {
    Geometry::from_polygons(positions, faces, &counts).expect("primitive indices are in range")
}

/// An axis-aligned cube of edge `size` centred at the origin: 8 points, 6 quads.
pub fn cube(size: f32) -> Geometry {
    box_mesh(Vec3::splat(size), [1, 1, 1])
}

/// A box of the given size centred at the origin, each face divided into a
/// grid; points on shared edges are shared (the result is closed).
pub fn box_mesh(size: Vec3, divisions: [u32; 3]) -> Geometry {
    let [nx, ny, nz] = divisions.map(|d| d.max(1));
    let h = size * 0.5;
    let mut positions = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut id = |i: u32, j: u32, k: u32, positions: &mut Vec<Vec3>| -> u32 {
        *index.entry((i, j, k)).or_insert_with(|| {
            positions.push(Vec3::new(
                -h.x + size.x * i as f32 / nx as f32,
                -h.y + size.y * j as f32 / ny as f32,
                -h.z + size.z * k as f32 / nz as f32,
            ));
            (positions.len() - 1) as u32
        })
    };
    let mut faces = Vec::new();
    // Each face: fixed axis and side, two running axes ordered so the normal points out.
    let sides: [(usize, u32, usize, usize); 6] = [
        (0, 0, 2, 1),
        (0, nx, 1, 2),
        (1, 0, 0, 2),
        (1, ny, 2, 0),
        (2, 0, 1, 0),
        (2, nz, 0, 1),
    ];
    let n = [nx, ny, nz];
    for (axis, side, ua, va) in sides {
        for a in 0..n[ua] {
            for b in 0..n[va] {
                let mut corner = |da: u32, db: u32, positions: &mut Vec<Vec3>| {
                    let mut c = [0u32; 3];
                    c[axis] = side;
                    c[ua] = a + da;
                    c[va] = b + db;
                    id(c[0], c[1], c[2], positions)
                };
                let q = [
                    corner(0, 0, &mut positions),
                    corner(1, 0, &mut positions),
                    corner(1, 1, &mut positions),
                    corner(0, 1, &mut positions),
                ];
                faces.extend_from_slice(&q);
            }
        }
    }
    let counts = vec![4; faces.len() / 4];
    build(positions, faces, counts)
}

/// A grid of `cols` x `rows` quads in the XZ plane, facing +Y, with `uv`.
pub fn grid(size: Vec2, cols: u32, rows: u32) -> Geometry {
    let (cols, rows) = (cols.max(1), rows.max(1));
    let mut positions = Vec::new();
    let mut uvs = Vec::new();
    for j in 0..=rows {
        for i in 0..=cols {
            let u = i as f32 / cols as f32;
            let v = j as f32 / rows as f32;
            positions.push(Vec3::new((u - 0.5) * size.x, 0.0, (0.5 - v) * size.y));
            uvs.push(Vec2::new(u, v));
        }
    }
    let w = cols + 1;
    let mut faces = Vec::new();
    for j in 0..rows {
        for i in 0..cols {
            let a = j * w + i;
            faces.extend_from_slice(&[a, a + 1, a + 1 + w, a + w]);
        }
    }
    let counts = vec![4; (cols * rows) as usize];
    let mut g = build(positions, faces, counts);
    g.set_attrib(
        AttribClass::Point,
        "uv",
        Attribute::from_data(AttribData::Vec2(uvs), TypeInfo::TexCoord),
    )
    .expect("one uv per point");
    g
}

/// A UV sphere: `rows` latitude bands, `cols` longitude segments, triangle
/// fans at the poles, quads elsewhere. Closed.
/// The cosine and sine of `i / n` of a full turn, worked in double
/// precision and rounded once, with the quarter turns exact: single
/// precision put a sphere's equator at y = -4.4e-8 (cos of a rounded
/// pi/2), which exact booleans and cuts then met as slivers.
fn turn(i: u32, n: u32) -> (f32, f32) {
    let (s, c) = (TAU * i as f64 / n as f64).sin_cos();
    let snap = |v: f64| if v.abs() < 1e-12 { 0.0 } else { v as f32 };
    (snap(c), snap(s))
}

pub fn uv_sphere(radius: f32, cols: u32, rows: u32) -> Geometry {
    let (cols, rows) = (cols.max(3), rows.max(2));
    let mut positions = vec![Vec3::new(0.0, radius, 0.0)];
    for j in 1..rows {
        // Half a turn from pole to pole.
        let (cos_theta, sin_theta) = turn(j, 2 * rows);
        for i in 0..cols {
            let (cos_phi, sin_phi) = turn(i, cols);
            positions
                .push(radius * Vec3::new(sin_theta * cos_phi, cos_theta, -sin_theta * sin_phi));
        }
    }
    positions.push(Vec3::new(0.0, -radius, 0.0));
    let south = positions.len() as u32 - 1;
    let ring = |j: u32, i: u32| 1 + (j - 1) * cols + i % cols;
    let (mut faces, mut counts) = (Vec::new(), Vec::new());
    for i in 0..cols {
        faces.extend_from_slice(&[0, ring(1, i), ring(1, i + 1)]);
        counts.push(3);
    }
    for j in 1..rows - 1 {
        for i in 0..cols {
            faces.extend_from_slice(&[
                ring(j, i),
                ring(j + 1, i),
                ring(j + 1, i + 1),
                ring(j, i + 1),
            ]);
            counts.push(4);
        }
    }
    for i in 0..cols {
        faces.extend_from_slice(&[south, ring(rows - 1, i + 1), ring(rows - 1, i)]);
        counts.push(3);
    }
    build(positions, faces, counts)
}

/// A torus around the Y axis: `cols` segments around the ring, `rows` around the tube.
pub fn torus(major: f32, minor: f32, cols: u32, rows: u32) -> Geometry {
    let (cols, rows) = (cols.max(3), rows.max(3));
    let mut positions = Vec::with_capacity((cols * rows) as usize);
    for i in 0..cols {
        let (cos_phi, sin_phi) = turn(i, cols);
        for j in 0..rows {
            let (cos_theta, sin_theta) = turn(j, rows);
            let r = major + minor * cos_theta;
            positions.push(Vec3::new(r * cos_phi, minor * sin_theta, -r * sin_phi));
        }
    }
    let id = |i: u32, j: u32| (i % cols) * rows + j % rows;
    let mut faces = Vec::with_capacity((cols * rows * 4) as usize);
    for i in 0..cols {
        for j in 0..rows {
            faces.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(positions, faces, vec![4; (cols * rows) as usize])
}

/// An open or capped tube along Y from 0 to `height`.
pub fn tube(radius: f32, height: f32, cols: u32, rows: u32, caps: bool) -> Geometry {
    let (cols, rows) = (cols.max(3), rows.max(1));
    let mut positions = Vec::new();
    for j in 0..=rows {
        let y = height * j as f32 / rows as f32;
        for i in 0..cols {
            let (cos_phi, sin_phi) = turn(i, cols);
            positions.push(Vec3::new(radius * cos_phi, y, -radius * sin_phi));
        }
    }
    let id = |j: u32, i: u32| j * cols + i % cols;
    let (mut faces, mut counts) = (Vec::new(), Vec::new());
    for j in 0..rows {
        for i in 0..cols {
            faces.extend_from_slice(&[id(j, i), id(j, i + 1), id(j + 1, i + 1), id(j + 1, i)]);
            counts.push(4);
        }
    }
    if caps {
        faces.extend((0..cols).rev().map(|i| id(0, i)));
        counts.push(cols);
        faces.extend((0..cols).map(|i| id(rows, i)));
        counts.push(cols);
    }
    build(positions, faces, counts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ops::signed_volume;

    /// The equator, the axis planes and the poles exactly where they
    /// belong, so exact operations meet no rounding slivers there.
    #[test]
    fn quarter_turns_are_exact() {
        let s = uv_sphere(1.0, 32, 16);
        let on = |f: fn(&Vec3) -> f32| s.positions().iter().filter(|p| f(p) == 0.0).count();
        assert_eq!(on(|p| p.y), 32, "the equator at y = 0");
        // The x = 0 and z = 0 meridians: two columns each, rows - 1 points.
        assert_eq!(on(|p| p.x), 2 * 15 + 2);
        assert_eq!(on(|p| p.z), 2 * 15 + 2);
        assert!(s.positions().iter().all(|p| p.length() <= 1.0 + 1e-6));
        let t = torus(2.0, 0.5, 8, 4);
        assert!(t.positions().iter().any(|p| *p == Vec3::new(2.5, 0.0, 0.0)));
        assert!(t
            .positions()
            .iter()
            .any(|p| *p == Vec3::new(0.0, 0.5, -2.0)));
    }

    #[test]
    fn primitives_are_closed_and_outward() {
        for (g, expect) in [
            (cube(2.0), 8.0),
            (box_mesh(Vec3::new(1.0, 2.0, 3.0), [2, 3, 4]), 6.0),
            (uv_sphere(1.0, 64, 32), 4.0 / 3.0 * std::f32::consts::PI),
            (
                torus(2.0, 0.5, 96, 48),
                2.0 * std::f32::consts::PI.powi(2) * 2.0 * 0.25,
            ),
            (tube(1.0, 2.0, 128, 2, true), std::f32::consts::PI * 2.0),
        ] {
            let r = g.topology().manifold_report(&g);
            assert!(r.is_closed_manifold(), "{r:?}");
            let v = signed_volume(&g);
            assert!((v - expect).abs() / expect < 0.01, "volume {v} vs {expect}");
        }
        let gr = grid(Vec2::splat(2.0), 4, 3);
        assert_eq!(gr.num_prims(), 12);
        assert_eq!(gr.topology().boundary_edges().len(), 14);
    }
}
