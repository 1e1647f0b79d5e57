//! Operations every node needs: merge, transform, bounds, triangulate, normals, fuse, delete, unpack, validate, ray casts, wall thickness, reduction within a distance bound and by vertex clustering.

mod bounds;
mod closest;
mod cluster;
mod collapse;
mod edit;
mod fuse;
mod instance;
mod merge;
mod normals;
mod pieces;
pub mod prim_surface;
mod quadric;
mod raycast;
mod reduce;
mod reorder;
mod thickness;
mod transform;
mod triangulate;
mod unpack;
mod validate;
mod winding;

pub use bounds::{bounds, signed_volume, surface_area, Aabb};
pub use closest::{closest_on_triangle, closest_on_triangle_f64, Closest, Closest64};
pub use cluster::{cluster_triangles, fan_triangle_count};
pub use collapse::reduce_triangles;
pub use edit::{
    append_vertices, compact_points, delete_points, delete_prims, remove_points, reverse_prims,
};
pub use fuse::{fuse_points, FuseStats};
pub use instance::{
    instance_transforms, point_float3, point_float4, point_scalar, unit_quat, InstanceAttribs,
    Scalars,
};
pub use merge::{merge, merge_cancellable};
pub use normals::{point_normals, polygon_normal, prim_normals, vertex_normals};
pub use pieces::{
    connectivity, connectivity_cancellable, extract, same_value, split_by_group, split_pieces,
    split_pieces_cancellable, value_classes, Connect, Pieces,
};
pub use quadric::Quadric;
pub use raycast::{RayHit, TriangleBvh};
pub use reduce::{compact_vertices, renumber_used, Deviation, ReduceOptions, Reduced};
pub use reorder::{reorder_points, reorder_prims};
pub use thickness::{wall_thickness, Cancelled, NO_OPPOSITE_WALL};
pub use transform::{transform, transformed, trs};
pub use triangulate::{triangulate, triangulate_polygon, triangulate_with};
pub use unpack::{unpack, unpack_with, unpacked_bytes};
pub use validate::{validate, ValidationIssue};
pub use winding::{is_closed_soup, WindingBvh};
