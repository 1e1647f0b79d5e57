//! The remeshed triangles as a geometry with the source's attributes:
//! point attributes interpolated at each point's place on the original
//! (barycentric in the closest original triangle), each face's primitive
//! attributes and groups from the original triangle closest to its centre
//! (among its corners' triangles), vertex attributes interpolated over
//! that triangle's corners at the vertex's point, so seams of vertex
//! attributes (UVs) stay sharp. Point groups follow the heaviest corner.

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Attribute, Geometry, Group, P};
use rayon::prelude::*;

use super::mesh::Mesh;
use super::surface::Surface;
use crate::ModelError;

/// Where the original triangles came from in the source geometry.
pub(super) struct Origin {
    /// Per original triangle: its source primitive and source vertices.
    pub prim: Vec<u32>,
    pub vertices: Vec<[u32; 3]>,
    /// Per original mesh vertex: its source point.
    pub point: Vec<u32>,
}

pub(super) fn build(
    src: &Geometry,
    m: Mesh,
    s: &Surface,
    origin: &Origin,
) -> Result<Geometry, ModelError> {
    let failed = |e: String| ModelError::Failed {
        op: "remesh",
        why: e,
    };
    // Each table is made only when an attribute or group reads it (a bare
    // mesh's output is its positions and faces).
    let point_attribs = src.attribs(AttribClass::Point).iter().any(|(n, _)| n != P);
    let wants_points = point_attribs || !src.point_groups().is_empty();
    let wants_corners = src.attribs(AttribClass::Vertex).iter().next().is_some();
    let wants_prims = src.attribs(AttribClass::Primitive).iter().next().is_some()
        || !src.prim_groups().is_empty();
    let points: Vec<([u32; 3], [f32; 3])> = if !wants_points {
        Vec::new()
    } else {
        m.proj
            .par_iter()
            .map(|p| {
                (
                    s.tris[p.tri as usize].map(|v| origin.point[v as usize]),
                    p.w,
                )
            })
            .collect()
    };
    let sources = if wants_corners || wants_prims {
        face_sources(&m, s)
    } else {
        Vec::new()
    };
    // A corner whose point lies on a triangle of the face's own source
    // polygon interpolates there; across a seam it takes the face's
    // triangle, clamped, so vertex attributes stay on their side.
    let corners: Vec<([u32; 3], [f32; 3])> = if !wants_corners {
        Vec::new()
    } else {
        m.faces
            .par_iter()
            .zip(&sources)
            .flat_map_iter(|(t, &tri)| {
                t.map(|v| {
                    let p = m.proj[v as usize];
                    if origin.prim[p.tri as usize] == origin.prim[tri as usize] {
                        (origin.vertices[p.tri as usize], p.w)
                    } else {
                        (
                            origin.vertices[tri as usize],
                            s.weights_on(tri, m.pos[v as usize]).0,
                        )
                    }
                })
            })
            .collect()
    };
    let prims: Vec<u32> = sources.iter().map(|&t| origin.prim[t as usize]).collect();
    let mut out = Geometry::from_triangles(m.pos, &m.faces).map_err(|e| failed(e.to_string()))?;
    let set = |out: &mut Geometry, class, name: &str, attr: Attribute| {
        out.set_attrib(class, name, attr)
            .map_err(|e| failed(e.to_string()))
    };
    for (name, attr) in src.attribs(AttribClass::Point).iter() {
        if name != P {
            set(&mut out, AttribClass::Point, name, attr.mix3(&points))?;
        }
    }
    for (name, attr) in src.attribs(AttribClass::Vertex).iter() {
        set(&mut out, AttribClass::Vertex, name, attr.mix3(&corners))?;
    }
    for (name, attr) in src.attribs(AttribClass::Primitive).iter() {
        set(&mut out, AttribClass::Primitive, name, attr.gather(&prims))?;
    }
    for (name, attr) in src.attribs(AttribClass::Detail).iter() {
        set(&mut out, AttribClass::Detail, name, attr.clone())?;
    }
    for (name, group) in src.point_groups() {
        let members = points.iter().map(|(pts, w)| {
            let best = (1..3).fold(0, |b, j| if w[j] > w[b] { j } else { b });
            group.contains(pts[best] as usize)
        });
        out.set_point_group(name, Group::from_flags(members))
            .map_err(|e| failed(e.to_string()))?;
    }
    for (name, group) in src.prim_groups() {
        let members = prims.iter().map(|&p| group.contains(p as usize));
        out.set_prim_group(name, Group::from_flags(members))
            .map_err(|e| failed(e.to_string()))?;
    }
    Ok(out)
}

/// Per face: of its corners' original triangles, the one closest to its
/// centre (ties: the lowest index).
fn face_sources(m: &Mesh, s: &Surface) -> Vec<u32> {
    m.faces
        .par_iter()
        .map(|t| {
            let centre = t.iter().map(|&v| m.pos[v as usize]).sum::<Vec3>() / 3.0;
            let mut best = (f32::INFINITY, u32::MAX);
            for &v in t {
                let tri = m.proj[v as usize].tri;
                let d = s.weights_on(tri, centre).1;
                if d < best.0 || (d == best.0 && tri < best.1) {
                    best = (d, tri);
                }
            }
            best.1
        })
        .collect()
}
