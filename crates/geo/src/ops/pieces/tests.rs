//! Connectivity counted on shapes whose pieces are known by construction,
//! and pieces cut out and merged back to the very same geometry.

use super::*;
use crate::ops::merge;
use crate::primitives::{box_mesh, grid, torus, uv_sphere};
use crate::{AttribValue, Attribute, TypeInfo};
use glam::{Vec2, Vec3};

fn shifted(mut g: Geometry, by: Vec3) -> Geometry {
    for p in g.positions_mut() {
        *p += by;
    }
    g
}

#[test]
fn merged_shapes_are_one_piece_each() {
    let b = box_mesh(Vec3::ONE, [3, 3, 3]);
    let s = shifted(uv_sphere(1.0, 16, 8), Vec3::X * 3.0);
    let t = shifted(torus(1.0, 0.25, 24, 12), Vec3::X * 6.0);
    let g = merge(&[&b, &s, &t, &b]).unwrap();
    for connect in [Connect::SharedPoint, Connect::SharedEdge] {
        let pieces = connectivity(&g, connect, None);
        assert_eq!(pieces.count, 4, "{connect:?}");
        let sizes: Vec<usize> = pieces.members().iter().map(|m| m.0.len()).collect();
        assert_eq!(
            sizes,
            [b.num_prims(), s.num_prims(), t.num_prims(), b.num_prims()]
        );
        // Numbered by first primitive: piece k starts where shape k does.
        assert_eq!(pieces.of_prim[0], 0);
        assert_eq!(pieces.of_prim[b.num_prims()], 1);
        assert_eq!(*pieces.of_prim.last().unwrap(), 3);
        assert_eq!(pieces.of_point[b.num_points()], 1);
    }
}

#[test]
fn a_shared_point_joins_by_point_not_by_edge() {
    // Two triangles touching at point 2 only.
    let g = Geometry::from_triangles(
        vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(-1.0, 2.0, 0.0),
        ],
        &[[0, 1, 2], [2, 3, 4]],
    )
    .unwrap();
    assert_eq!(connectivity(&g, Connect::SharedPoint, None).count, 1);
    assert_eq!(connectivity(&g, Connect::SharedEdge, None).count, 2);
}

#[test]
fn loose_points_are_pieces_after_the_primitives() {
    let mut g = grid(Vec2::ONE, 3, 3);
    let a = g.add_point(Vec3::splat(5.0));
    let b = g.add_point(Vec3::splat(6.0));
    let pieces = connectivity(&g, Connect::SharedPoint, None);
    assert_eq!((pieces.prim_pieces, pieces.count), (1, 3));
    assert_eq!(pieces.of_point[a as usize], 1);
    assert_eq!(pieces.of_point[b as usize], 2);
    let parts = split_pieces(&g, &pieces);
    assert_eq!(parts[2].num_points(), 1);
    assert_eq!(parts[2].num_prims(), 0);
}

#[test]
fn a_primitive_attribute_splits_where_it_changes() {
    // A 4x1 strip of quads labelled 0 0 1 1: two pieces.
    let mut g = grid(Vec2::new(4.0, 1.0), 4, 1);
    assert_eq!(g.num_prims(), 4);
    let labels = AttribData::Int(vec![0, 0, 1, 1]);
    g.set_attrib(
        AttribClass::Primitive,
        "label",
        Attribute::from_data(labels.clone(), TypeInfo::None),
    )
    .unwrap();
    for connect in [Connect::SharedPoint, Connect::SharedEdge] {
        let p = connectivity(&g, connect, Some((AttribClass::Primitive, &labels)));
        assert_eq!(p.of_prim, [0, 0, 1, 1], "{connect:?}");
    }
}

#[test]
fn a_uv_seam_splits_islands() {
    // Two quads side by side whose shared edge has different uvs on each side.
    let mut g = grid(Vec2::new(2.0, 1.0), 2, 1);
    assert_eq!(g.num_prims(), 2);
    let n = g.num_vertices();
    let mut uv = Attribute::new(AttribValue::Vec3(Vec3::ZERO), TypeInfo::None, n);
    // Every vertex of the second quad is shifted in uv.
    for v in g.prim_vertex_range(1) {
        uv.values_mut()
            .set(v, &AttribValue::Vec3(Vec3::new(5.0, 0.0, 0.0)))
            .unwrap();
    }
    g.set_attrib(AttribClass::Vertex, "uv", uv).unwrap();
    let uv = g.attrib(AttribClass::Vertex, "uv").unwrap().data().clone();
    for connect in [Connect::SharedPoint, Connect::SharedEdge] {
        assert_eq!(
            connectivity(&g, connect, Some((AttribClass::Vertex, &uv))).count,
            2
        );
        assert_eq!(connectivity(&g, connect, None).count, 1);
    }
}

#[test]
fn pieces_merged_in_order_give_the_input_back() {
    let mut b = box_mesh(Vec3::ONE, [2, 2, 2]);
    b.set_prim_group("top", crate::Group::from_members(b.num_prims(), [0, 3]))
        .unwrap();
    let s = shifted(uv_sphere(1.0, 8, 4), Vec3::X * 3.0);
    let mut g = merge(&[&b, &s]).unwrap();
    let names = crate::StringColumn {
        table: (0..g.num_prims())
            .map(|i| format!("piece{}", i % 7))
            .collect(),
        indices: (0..g.num_prims() as u32).map(|i| i % 7).collect(),
    };
    g.set_attrib(
        AttribClass::Primitive,
        "name",
        Attribute::from_data(AttribData::String(names), TypeInfo::None),
    )
    .unwrap();
    let parts = split_pieces(&g, &connectivity(&g, Connect::SharedEdge, None));
    let refs: Vec<&Geometry> = parts.iter().collect();
    let back = merge(&refs).unwrap();
    assert_eq!(back.positions(), g.positions());
    assert_eq!(back.vertex_points(), g.vertex_points());
    let name = |x: &Geometry, i| {
        x.attrib(AttribClass::Primitive, "name")
            .unwrap()
            .as_strings()
            .unwrap()
            .get(i)
            .to_owned()
    };
    for i in 0..g.num_prims() {
        assert_eq!(name(&back, i), name(&g, i));
    }
    assert_eq!(back.prim_groups()["top"], g.prim_groups()["top"]);
}

#[test]
fn split_by_group_keeps_both_sides() {
    let g = box_mesh(Vec3::ONE, [1, 1, 1]);
    let grp = crate::Group::from_members(g.num_prims(), [1, 4]);
    let (inside, outside) = split_by_group(&g, &grp);
    assert_eq!((inside.num_prims(), outside.num_prims()), (2, 4));
    assert_eq!(inside.num_points(), 8.min(inside.num_points()));
    assert_eq!(outside.num_points(), 8);
}
