//! GLB writer: meshes with positions, normals, UVs, colours and every other
//! point or vertex attribute as `_NAME` (`gltf_attribs.rs`); packed
//! instances as shared meshes, instanced on one node per source
//! (`EXT_mesh_gpu_instancing`) or on a node each.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;
use std::sync::Arc;

use geode_geo::glam::{Mat4, Vec2, Vec3};
use geode_geo::{ops, AttribClass, Geometry, PrimKind};
use serde_json::{json, Value};

use crate::atomic::os_err;
use crate::error::IoError;
use crate::gltf_attribs;
use crate::gltf_instancing as instancing;
use crate::progress::{report_dropped, Progress};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
/// The material of meshes with texture coordinates: white, rough, not metal.
const DEFAULT_MATERIAL: usize = 0;

struct Builder<'c> {
    /// Polled while instances are laid out (a million take seconds).
    cancelled: &'c (dyn Fn() -> bool + Sync),
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    /// Mesh index (or none) per distinct source geometry, by pointer.
    mesh_of: HashMap<*const Geometry, Option<usize>>,
    /// Whether a node uses `EXT_mesh_gpu_instancing`.
    instanced: bool,
    /// Whether a mesh has texture coordinates: they get the default
    /// material (readers such as trimesh keep coordinates only for a
    /// primitive with a material).
    textured: bool,
    /// What glTF could not carry, reported once.
    dropped: Vec<String>,
}

impl Builder<'_> {
    /// A buffer view over `bytes` appended to the binary chunk; `target`
    /// names the GPU buffer it feeds (none for per-instance columns).
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        let mut view = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.views.push(view);
        self.views.len() - 1
    }

    fn vec_accessor<T: bytemuck::Pod>(
        &mut self,
        data: &[T],
        ty: &str,
        min_max: Option<(Vec3, Vec3)>,
    ) -> usize {
        self.float_accessor(data, ty, Some(ARRAY_BUFFER), min_max)
    }

    /// An accessor over per-instance values (not vertex attributes).
    fn instance_accessor<T: bytemuck::Pod>(&mut self, data: &[T], ty: &str) -> usize {
        self.float_accessor(data, ty, None, None)
    }

    fn float_accessor<T: bytemuck::Pod>(
        &mut self,
        data: &[T],
        ty: &str,
        target: Option<u32>,
        min_max: Option<(Vec3, Vec3)>,
    ) -> usize {
        let view = self.view(bytemuck::cast_slice(data), target);
        let mut a =
            json!({"bufferView": view, "componentType": FLOAT, "count": data.len(), "type": ty});
        if let Some((lo, hi)) = min_max {
            a["min"] = json!([lo.x, lo.y, lo.z]);
            a["max"] = json!([hi.x, hi.y, hi.z]);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn index_accessor(&mut self, idx: &[u32]) -> usize {
        let view = self.view(bytemuck::cast_slice(idx), Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({"bufferView": view, "componentType": UNSIGNED_INT, "count": idx.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// The mesh for a geometry's polygons, polylines and loose points.
    fn mesh(&mut self, g: &Geometry) -> Option<usize> {
        let key = g as *const Geometry;
        if let Some(m) = self.mesh_of.get(&key) {
            return *m;
        }
        let m = self.build_mesh(g);
        self.mesh_of.insert(key, m);
        m
    }

    fn build_mesh(&mut self, g: &Geometry) -> Option<usize> {
        let has_polys = g.prim_kinds().contains(&PrimKind::Polygon);
        let has_lines = g.prim_kinds().contains(&PrimKind::Polyline);
        let only_points = g.num_prims() == 0 && g.num_points() > 0;
        if !has_polys && !has_lines && !only_points {
            return None;
        }
        // Instance anchors are not part of the mesh: drop packed primitives and
        // the points only they used.
        let packed: Vec<usize> = g.prims_where(Geometry::is_packed);
        let own;
        let g = if packed.is_empty() {
            g
        } else {
            let mut c = g.clone();
            ops::delete_prims(
                &mut c,
                &geode_geo::Group::from_members(g.num_prims(), packed),
                true,
            );
            own = c;
            &own
        };
        let tri = ops::triangulate_with(g, None, &|| (self.cancelled)())?;
        if (self.cancelled)() {
            return None;
        }
        let pos = tri.positions();
        let (customs, dropped) = gltf_attribs::custom_columns(&tri);
        for d in dropped {
            if !self.dropped.contains(&d) {
                self.dropped.push(d);
            }
        }
        let per_corner = ["N", "uv", "Cd"]
            .iter()
            .any(|n| tri.attrib(AttribClass::Vertex, n).is_some())
            || customs.iter().any(|c| c.class == AttribClass::Vertex);
        // glTF vertices: one per point, or one per polygon corner when any
        // attribute lives on vertices.
        let vertex_source: Vec<(u32, Option<u32>)> = if per_corner {
            (0..tri.num_prims())
                .filter(|&p| tri.prim_kind(p) == PrimKind::Polygon)
                .flat_map(|p| {
                    tri.prim_vertex_range(p)
                        .map(|v| (tri.vertex_points()[v], Some(v as u32)))
                })
                .collect()
        } else {
            (0..tri.num_points() as u32).map(|p| (p, None)).collect()
        };
        let fetch3 = |name: &str| -> Option<Vec<Vec3>> {
            let v = tri
                .attrib(AttribClass::Vertex, name)
                .and_then(|a| a.as_vec3());
            let p = tri
                .attrib(AttribClass::Point, name)
                .and_then(|a| a.as_vec3());
            if v.is_none() && p.is_none() {
                return None;
            }
            Some(
                vertex_source
                    .iter()
                    .map(|&(pt, vx)| match (v, vx) {
                        (Some(v), Some(i)) => v[i as usize],
                        _ => p.map_or(Vec3::ZERO, |p| p[pt as usize]),
                    })
                    .collect(),
            )
        };
        let mut attrs = serde_json::Map::new();
        let positions: Vec<Vec3> = vertex_source
            .iter()
            .map(|&(p, _)| pos[p as usize])
            .collect();
        if positions.is_empty() {
            return None;
        }
        let (lo, hi) = positions
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
                (a.min(*p), b.max(*p))
            });
        attrs.insert(
            "POSITION".into(),
            json!(self.vec_accessor(&positions, "VEC3", Some((lo, hi)))),
        );
        if let Some(mut n) = fetch3("N") {
            // glTF requires unit normals: fall back to the computed ones where
            // the attribute is zero or not finite.
            let computed: Option<Vec<Vec3>> = n
                .iter()
                .any(|x| !x.is_finite() || x.length_squared() < 1e-12)
                .then(|| {
                    let pn = ops::point_normals(&tri);
                    vertex_source.iter().map(|&(p, _)| pn[p as usize]).collect()
                });
            for (i, x) in n.iter_mut().enumerate() {
                let u = x.normalize_or_zero();
                *x = if u.is_finite() && u != Vec3::ZERO {
                    u
                } else {
                    computed
                        .as_ref()
                        .map_or(Vec3::Y, |c| c[i])
                        .try_normalize()
                        .unwrap_or(Vec3::Y)
                };
            }
            attrs.insert("NORMAL".into(), json!(self.vec_accessor(&n, "VEC3", None)));
        }
        if (self.cancelled)() {
            return None;
        }
        let uv_v = crate::texcoords(&tri, AttribClass::Vertex);
        let uv_p = crate::texcoords(&tri, AttribClass::Point);
        if uv_v.is_some() || uv_p.is_some() {
            // glTF's texture origin is the top left: v is flipped.
            let uv: Vec<Vec2> = vertex_source
                .iter()
                .map(|&(pt, vx)| {
                    let t = match (&uv_v, vx) {
                        (Some(v), Some(i)) => v[i as usize],
                        _ => uv_p.as_ref().map_or(Vec2::ZERO, |p| p[pt as usize]),
                    };
                    Vec2::new(t.x, 1.0 - t.y)
                })
                .collect();
            attrs.insert(
                "TEXCOORD_0".into(),
                json!(self.vec_accessor(&uv, "VEC2", None)),
            );
        }
        if let Some(mut c) = fetch3("Cd") {
            for x in c.iter_mut() {
                *x = x.clamp(Vec3::ZERO, Vec3::ONE);
            }
            attrs.insert("COLOR_0".into(), json!(self.vec_accessor(&c, "VEC3", None)));
        }
        for c in &customs {
            if let Some((flat, ty, extras)) = c.gather(&vertex_source) {
                let k = flat.len() / vertex_source.len().max(1);
                let view = self.view(bytemuck::cast_slice(&flat), Some(ARRAY_BUFFER));
                self.accessors
                    .push(json!({"bufferView": view, "componentType": FLOAT,
                    "count": flat.len() / k.max(1), "type": ty, "extras": extras}));
                attrs.insert(c.semantic(), json!(self.accessors.len() - 1));
            }
        }
        if (self.cancelled)() {
            return None;
        }
        let mut prims = Vec::new();
        if only_points {
            prims.push(json!({"attributes": attrs.clone(), "mode": 0}));
        }
        let tri_idx: Vec<u32> = if per_corner {
            (0..vertex_source.len() as u32).collect()
        } else {
            (0..tri.num_prims())
                .filter(|&p| tri.prim_kind(p) == PrimKind::Polygon)
                .flat_map(|p| tri.prim_points(p).iter().copied())
                .collect()
        };
        if !tri_idx.is_empty() {
            let idx = self.index_accessor(&tri_idx);
            prims.push(json!({"attributes": attrs.clone(), "indices": idx, "mode": 4}));
        }
        if has_lines {
            // Line vertices are points; with per-corner layout they need their own positions.
            let segs: Vec<[u32; 2]> = (0..tri.num_prims())
                .filter(|&p| tri.prim_kind(p) == PrimKind::Polyline)
                .flat_map(|p| {
                    tri.prim_points(p)
                        .windows(2)
                        .map(|w| [w[0], w[1]])
                        .collect::<Vec<_>>()
                })
                .collect();
            if per_corner {
                let pts: Vec<Vec3> = segs
                    .iter()
                    .flat_map(|s| [pos[s[0] as usize], pos[s[1] as usize]])
                    .collect();
                let (lo, hi) = pts
                    .iter()
                    .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
                        (a.min(*p), b.max(*p))
                    });
                let acc = self.vec_accessor(&pts, "VEC3", Some((lo, hi)));
                prims.push(json!({"attributes": {"POSITION": acc}, "mode": 1}));
            } else {
                let flat: Vec<u32> = segs.iter().flatten().copied().collect();
                let idx = self.index_accessor(&flat);
                prims.push(json!({"attributes": attrs.clone(), "indices": idx, "mode": 1}));
            }
        }
        if prims.is_empty() {
            return None;
        }
        if attrs.contains_key("TEXCOORD_0") {
            self.textured = true;
            for p in &mut prims {
                p["material"] = json!(DEFAULT_MATERIAL);
            }
        }
        self.meshes.push(json!({"primitives": prims}));
        Some(self.meshes.len() - 1)
    }

    /// Nodes for `g`: returns the indices of nodes to place under a parent.
    /// Instances of a source with no instances of its own whose transform
    /// is a translation, rotation and scale share one node per source with
    /// `EXT_mesh_gpu_instancing` (three columns for a million instances);
    /// the rest (shears, nested instancing) get a node each.
    fn nodes_for(&mut self, g: &Geometry, own_mesh: bool, depth: usize) -> Vec<usize> {
        let mut out = Vec::new();
        if own_mesh {
            if let Some(m) = self.mesh(g) {
                self.nodes.push(json!({"mesh": m}));
                out.push(self.nodes.len() - 1);
            }
        }
        if depth > 64 {
            return out;
        }
        let packed: Vec<usize> = g.prims_where(Geometry::is_packed);
        let Some(placed) = instancing::place(g, &packed, self.cancelled) else {
            return out;
        };
        for group in &placed.groups {
            let source = &g.packed_instance(group.first_prim).expect("packed").source;
            let Some(mesh) = self.mesh(source) else {
                continue;
            };
            let attributes = json!({
                "TRANSLATION": self.instance_accessor(&group.translations, "VEC3"),
                "ROTATION": self.instance_accessor(&group.rotations, "VEC4"),
                "SCALE": self.instance_accessor(&group.scales, "VEC3"),
            });
            self.instanced = true;
            self.nodes.push(json!({
                "mesh": mesh,
                "extensions": {instancing::EXTENSION: {"attributes": attributes}},
            }));
            out.push(self.nodes.len() - 1);
        }
        for (k, &prim) in placed.one_by_one.iter().enumerate() {
            if k % 4096 == 4095 && (self.cancelled)() {
                return out;
            }
            let inst = g.packed_instance(prim).expect("packed");
            let world = g.packed_world_transform(prim).expect("packed has a point");
            let src: Arc<Geometry> = Arc::clone(&inst.source);
            let mesh = self.mesh(&src);
            // The source's own mesh sits on this node; its instances become children.
            let children = if src.has_packed() {
                self.nodes_for(&src, false, depth + 1)
            } else {
                Vec::new()
            };
            let mut node = json!({"matrix": matrix(&world)});
            if let Some(m) = mesh {
                node["mesh"] = json!(m);
            }
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            self.nodes.push(node);
            out.push(self.nodes.len() - 1);
        }
        out
    }
}

fn matrix(m: &Mat4) -> Vec<f32> {
    m.to_cols_array().to_vec()
}

/// Writes GLB. Packed instances become nodes sharing one mesh per distinct
/// source (instances are not expanded).
pub fn write_glb(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    progress.start("writing GLB", 1);
    let cancelled = || progress.cancelled();
    let mut b = Builder {
        cancelled: &cancelled,
        bin: Vec::new(),
        views: Vec::new(),
        accessors: Vec::new(),
        meshes: Vec::new(),
        nodes: Vec::new(),
        mesh_of: HashMap::new(),
        instanced: false,
        textured: false,
        dropped: Vec::new(),
    };
    let roots = b.nodes_for(g, true, 0);
    if progress.cancelled() {
        return Err(IoError::Cancelled {
            path: path.to_owned(),
        });
    }
    while !b.bin.len().is_multiple_of(4) {
        b.bin.push(0);
    }
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": format!("geode {}", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{}],
    });
    // An empty node list is invalid glTF: a scene without geometry has none.
    if !roots.is_empty() {
        doc["scenes"][0]["nodes"] = json!(roots);
    }
    if !b.nodes.is_empty() {
        doc["nodes"] = json!(b.nodes);
    }
    if b.instanced {
        // Required: a viewer without it would show one copy where there are many.
        doc["extensionsUsed"] = json!([instancing::EXTENSION]);
        doc["extensionsRequired"] = json!([instancing::EXTENSION]);
    }
    if b.textured {
        doc["materials"] = json!([{
            "name": "geode_default",
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8},
        }]);
    }
    if !b.meshes.is_empty() {
        doc["meshes"] = json!(b.meshes);
        doc["accessors"] = json!(b.accessors);
        doc["bufferViews"] = json!(b.views);
        doc["buffers"] = json!([{"byteLength": b.bin.len()}]);
    }
    let mut json_bytes = serde_json::to_vec(&doc).map_err(|e| IoError::Unsupported {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    while json_bytes.len() % 4 != 0 {
        json_bytes.push(b' ');
    }
    let has_bin = !b.meshes.is_empty();
    let total = 12 + 8 + json_bytes.len() + if has_bin { 8 + b.bin.len() } else { 0 };
    let total = u32::try_from(total).map_err(|_| IoError::Unsupported {
        path: path.to_owned(),
        message: "GLB larger than 4 GiB".into(),
    })?;
    let e = os_err(path);
    w.write_all(b"glTF").map_err(&e)?;
    w.write_all(&2u32.to_le_bytes()).map_err(&e)?;
    w.write_all(&total.to_le_bytes()).map_err(&e)?;
    w.write_all(&(json_bytes.len() as u32).to_le_bytes())
        .map_err(&e)?;
    w.write_all(b"JSON").map_err(&e)?;
    w.write_all(&json_bytes).map_err(&e)?;
    if has_bin {
        w.write_all(&(b.bin.len() as u32).to_le_bytes())
            .map_err(&e)?;
        w.write_all(b"BIN\0").map_err(&e)?;
        w.write_all(&b.bin).map_err(&e)?;
    }
    for (kind, groups) in [("point", g.point_groups()), ("primitive", g.prim_groups())] {
        b.dropped
            .extend(groups.keys().map(|n| format!("{kind} group `{n}`")));
    }
    report_dropped(progress, path, "GLB", &b.dropped);
    progress.finish();
    Ok(())
}
