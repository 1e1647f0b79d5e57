//! Face-varying data refined as a mesh of its own values, for OpenSubdiv's
//! linear-boundaries option (geode's default). The base faces with each
//! corner's value in place of its vertex form a mesh whose boundaries are
//! the seams and the mesh's own boundary; refining that mesh with the
//! vertex rules (the mesh's creases carried over, its boundary edges and
//! vertices held linear) gives OpenSubdiv's face-varying values at the cost
//! of a vertex refinement. Inside a seam-free region the two are the same
//! rule by construction: a value's neighbourhood is its vertex's. Other
//! options, and topology where that correspondence fails (non-manifold
//! mesh edges, a value inside a region whose faces are not one fan), take
//! the span rules of `fvar.rs`.

use super::fvar::{FVarChannel, FVarLinear};
use super::level::{Level, Rows, INFINITE};
use super::refine::{plan, refine_topology_with, refine_values_cancellable};

/// One level of a channel's value mesh and the values at its vertices.
pub(crate) struct ValueMesh {
    level: Level,
    values: Vec<f64>,
    dim: usize,
}

impl ValueMesh {
    /// The value mesh of `channel` over the base level `mesh`, or None
    /// where it would not follow OpenSubdiv: another option than linear
    /// boundaries, or non-manifold topology.
    pub fn new(mesh: &Level, channel: &FVarChannel, mode: FVarLinear) -> Option<ValueMesh> {
        if mode != FVarLinear::Boundaries || !manifold_edges(mesh) {
            return None;
        }
        let faces = Rows {
            offsets: mesh.faces.offsets.clone(),
            items: channel.corner_value.clone(),
        };
        let num_values = channel.values.len() / channel.dim.max(1);
        let mut level = Level::from_faces(num_values, faces, |_| 0.0);
        // A value belongs to one vertex and an edge of values to one edge:
        // each takes its sharpness from the mesh.
        for (corner, &value) in channel.corner_value.iter().enumerate() {
            let edge = level.face_edges[corner] as usize;
            level.edge_sharpness[edge] = mesh.edge_sharpness[mesh.face_edges[corner] as usize];
            level.vertex_sharpness[value as usize] =
                mesh.vertex_sharpness[mesh.faces.items[corner] as usize];
        }
        hold_boundaries_linear(&mut level);
        if !interior_fans_closed(&level) {
            return None;
        }
        Some(ValueMesh {
            level,
            values: channel.values.clone(),
            dim: channel.dim,
        })
    }

    /// The next level (`adjacency`: whether it will be refined again);
    /// None once `cancel` answers true.
    pub fn refine(
        &self,
        chaikin: bool,
        adjacency: bool,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Option<ValueMesh> {
        let mut child = refine_topology_with(&self.level, chaikin, adjacency, cancel)?;
        let rules = plan(&self.level, &child, chaikin);
        let values =
            refine_values_cancellable(&self.level, &child, &rules, &self.values, self.dim, cancel)?;
        if adjacency {
            // New vertices on a boundary edge are held too (the last level
            // needs no tags: nothing refines it).
            hold_boundaries_linear(&mut child);
        }
        Some(ValueMesh {
            level: child,
            values,
            dim: self.dim,
        })
    }

    /// Each corner's value, `dim` numbers per corner.
    #[cfg(test)]
    pub fn corner_data(&self) -> Vec<f64> {
        self.level
            .faces
            .items
            .iter()
            .flat_map(|&v| &self.values[v as usize * self.dim..(v as usize + 1) * self.dim])
            .copied()
            .collect()
    }

    /// The values as a channel: corners of the mesh's level of the same
    /// depth map to the value mesh's vertices one for one.
    pub fn into_channel(self) -> FVarChannel {
        FVarChannel {
            dim: self.dim,
            values: self.values,
            corner_value: self.level.faces.items,
        }
    }
}

/// Whether every edge has one or two faces and two distinct ends: then a
/// value edge inside a region is a mesh edge with a face on each side.
fn manifold_edges(level: &Level) -> bool {
    (0..level.edge_verts.len()).all(|e| {
        let [a, b] = level.edge_verts[e];
        a != b && level.edge_faces.row(e).len() <= 2
    })
}

/// Whether every value off the boundaries (every edge with two faces) has
/// one closed fan of faces, as its vertex has: values where regions touch
/// at a point or meet in more than two faces are on a boundary, held.
fn interior_fans_closed(level: &Level) -> bool {
    (0..level.num_vertices).all(|v| {
        let (edges, faces) = (level.vertex_edges.row(v), level.vertex_faces.row(v));
        let inside = edges
            .iter()
            .all(|&e| level.edge_faces.row(e as usize).len() == 2);
        !inside || faces.len() == edges.len()
    })
}

/// Boundary edges (fewer or more than two faces) infinitely sharp and
/// their vertices pinned: values on a seam, where regions touch, or on the
/// mesh's boundary interpolate linearly.
fn hold_boundaries_linear(level: &mut Level) {
    for e in 0..level.edge_verts.len() {
        if level.edge_faces.row(e).len() != 2 {
            level.edge_sharpness[e] = INFINITE;
            for v in level.edge_verts[e] {
                level.vertex_sharpness[v as usize] = INFINITE;
            }
        }
    }
}

/// A face-varying channel on its way down the levels: as a value mesh
/// where that follows OpenSubdiv, else by the span rules.
pub(crate) enum FaceVarying {
    Mesh(Box<ValueMesh>),
    Spans(FVarChannel),
}

impl FaceVarying {
    pub fn new(mesh: &Level, channel: FVarChannel, mode: FVarLinear) -> FaceVarying {
        match ValueMesh::new(mesh, &channel, mode) {
            Some(values) => FaceVarying::Mesh(Box::new(values)),
            None => FaceVarying::Spans(channel),
        }
    }

    /// The channel on `child`, the next level of `parent` by `rules`.
    #[allow(clippy::too_many_arguments)]
    pub fn refine(
        &self,
        parent: &Level,
        child: &Level,
        rules: &super::refine::Plan,
        mode: FVarLinear,
        chaikin: bool,
        adjacency: bool,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Option<FaceVarying> {
        Some(match self {
            FaceVarying::Mesh(values) => {
                FaceVarying::Mesh(Box::new(values.refine(chaikin, adjacency, cancel)?))
            }
            FaceVarying::Spans(channel) => {
                FaceVarying::Spans(channel.refine(parent, child, rules, mode))
            }
        })
    }

    pub fn into_channel(self) -> FVarChannel {
        match self {
            FaceVarying::Mesh(values) => (*values).into_channel(),
            FaceVarying::Spans(channel) => channel,
        }
    }
}
