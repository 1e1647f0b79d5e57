//! glTF 2.0 / GLB reader (through the `gltf` crate): meshes of the default
//! scene, shared meshes (and `EXT_mesh_gpu_instancing` nodes) as packed
//! instances.

use std::path::Path;
use std::sync::Arc;

use base64::Engine;
use geode_geo::glam::{Mat4, Vec2, Vec3};
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, PrimKind, TypeInfo};
use gltf::mesh::Mode;

use crate::error::{ParseError, ParseResult};
use crate::gltf_instancing as instancing;
use crate::progress::Progress;

fn load_buffers(doc: &gltf::Gltf, base: Option<&Path>) -> ParseResult<Vec<Vec<u8>>> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            gltf::buffer::Source::Bin => doc.blob.clone().ok_or_else(|| {
                ParseError::whole(format!(
                    "buffer {} refers to a GLB binary chunk that is missing",
                    b.index()
                ))
            })?,
            gltf::buffer::Source::Uri(uri) => {
                if let Some(rest) = uri.strip_prefix("data:") {
                    let (_, payload) = rest.split_once(";base64,").ok_or_else(|| {
                        ParseError::whole(format!(
                            "buffer {}: only base64 data URIs are supported",
                            b.index()
                        ))
                    })?;
                    base64::engine::general_purpose::STANDARD
                        .decode(payload)
                        .map_err(|e| {
                            ParseError::whole(format!("buffer {}: bad base64 data: {e}", b.index()))
                        })?
                } else {
                    let dir = base.ok_or_else(|| {
                        ParseError::whole(format!(
                            "buffer {} refers to external file `{uri}` but no folder is known",
                            b.index()
                        ))
                    })?;
                    let p = dir.join(uri);
                    crate::read_regular(&p).map_err(|e| {
                        ParseError::whole(format!(
                            "buffer {}: cannot read `{}`: {e}",
                            b.index(),
                            p.display()
                        ))
                    })?
                }
            }
        };
        if data.len() < b.length() {
            return Err(ParseError::whole(format!(
                "buffer {} declares {} bytes but holds {}",
                b.index(),
                b.length(),
                data.len()
            )));
        }
        out.push(data);
    }
    Ok(out)
}

/// gltf-json's validation indexes `accessors[POSITION]` without a bounds check
/// (found by fuzzing): check those references before handing the document over.
fn check_position_accessors(bytes: &[u8]) -> ParseResult<()> {
    let json: &[u8] = if bytes.starts_with(b"glTF") {
        // gltf's GLB reader subtracts its 12-byte header from the length
        // the file declares (found by fuzzing, a panic with overflow checks).
        let declared = bytes
            .get(8..12)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if let Some(n @ 0..12) = declared {
            return Err(ParseError::byte(
                8,
                format!("invalid GLB: the header declares {n} bytes, fewer than the header's 12"),
            ));
        }
        match gltf::Glb::from_slice(bytes) {
            Ok(glb) => return check_position_json(&glb.json),
            Err(e) => return Err(ParseError::whole(format!("invalid GLB: {e}"))),
        }
    } else {
        bytes
    };
    check_position_json(json)
}

fn check_position_json(json: &[u8]) -> ParseResult<()> {
    // Shaped like gltf-json's own parse (unknown fields skipped unvalidated),
    // so whatever it accepts, this reads too.
    #[derive(serde::Deserialize)]
    struct Root {
        #[serde(default)]
        accessors: Vec<serde::de::IgnoredAny>,
        #[serde(default)]
        meshes: Vec<Mesh>,
    }
    #[derive(serde::Deserialize)]
    struct Mesh {
        #[serde(default)]
        primitives: Vec<Primitive>,
    }
    #[derive(serde::Deserialize)]
    struct Primitive {
        #[serde(default)]
        attributes: Attributes,
    }
    #[derive(serde::Deserialize, Default)]
    struct Attributes {
        #[serde(rename = "POSITION")]
        position: Option<u64>,
    }
    let Ok(root) = serde_json::from_slice::<Root>(json) else {
        return Ok(()); // The gltf crate reports malformed JSON with detail.
    };
    let accessors = root.accessors.len();
    for (mi, mesh) in root.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            if let Some(p) = prim.attributes.position {
                if p as usize >= accessors {
                    return Err(ParseError::whole(format!("mesh {mi} primitive {pi}: POSITION refers to accessor {p} but there are {accessors}")));
                }
            }
        }
    }
    Ok(())
}

/// Checks that an accessor's data lies inside its buffer, so reading it cannot
/// go out of bounds.
pub(crate) fn check_accessor(a: &gltf::Accessor, buffers: &[Vec<u8>]) -> ParseResult<()> {
    let elem = a.size();
    let check_view =
        |view: &gltf::buffer::View, offset: usize, count: usize, elem: usize| -> ParseResult<()> {
            let buf = buffers
                .get(view.buffer().index())
                .ok_or_else(|| ParseError::whole("buffer view refers to a missing buffer"))?;
            let stride = view.stride().unwrap_or(elem);
            let need = if count == 0 {
                0
            } else {
                offset
                    .checked_add(
                        stride
                            .checked_mul(count - 1)
                            .and_then(|x| x.checked_add(elem))
                            .ok_or_else(|| ParseError::whole("accessor size overflows"))?,
                    )
                    .ok_or_else(|| ParseError::whole("accessor size overflows"))?
            };
            let end = view
                .offset()
                .checked_add(view.length())
                .ok_or_else(|| ParseError::whole("buffer view overflows"))?;
            if need > view.length() || end > buf.len() || stride < elem {
                return Err(ParseError::whole(format!(
                    "accessor {} reaches past the end of its buffer view {}",
                    a.index(),
                    view.index()
                )));
            }
            Ok(())
        };
    if let Some(view) = a.view() {
        check_view(&view, a.offset(), a.count(), elem)?;
    }
    if let Some(s) = a.sparse() {
        let iv = s.indices().view();
        let isize = match s.indices().index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        check_view(&iv, s.indices().offset(), s.count(), isize)?;
        check_view(&s.values().view(), s.values().offset(), s.count(), elem)?;
    }
    Ok(())
}

/// Rejects attribute layouts the reader (and the glTF specification) does not
/// allow, before the `gltf` crate's readers meet them.
fn check_semantics(prim: &gltf::Primitive) -> ParseResult<()> {
    use gltf::accessor::{DataType as D, Dimensions as Dim};
    use gltf::Semantic as S;
    for (semantic, a) in prim.attributes() {
        let ok = match &semantic {
            S::Positions | S::Normals => a.dimensions() == Dim::Vec3 && a.data_type() == D::F32,
            S::TexCoords(_) => {
                a.dimensions() == Dim::Vec2 && matches!(a.data_type(), D::F32 | D::U8 | D::U16)
            }
            S::Colors(_) => {
                matches!(a.dimensions(), Dim::Vec3 | Dim::Vec4)
                    && matches!(a.data_type(), D::F32 | D::U8 | D::U16)
            }
            _ => true,
        };
        if !ok {
            return Err(ParseError::whole(format!(
                "primitive {}: attribute {semantic:?} has type {:?} {:?}, which glTF does not allow",
                prim.index(),
                a.dimensions(),
                a.data_type()
            )));
        }
    }
    if let Some(i) = prim.indices() {
        if i.dimensions() != Dim::Scalar || !matches!(i.data_type(), D::U8 | D::U16 | D::U32) {
            return Err(ParseError::whole(format!(
                "primitive {}: indices must be unsigned scalars",
                prim.index()
            )));
        }
    }
    Ok(())
}

/// The FLOAT values of an application-specific attribute, flat; `None`
/// for other component types (left unread).
fn custom_floats(a: &gltf::Accessor, buffers: &[Vec<u8>]) -> Option<Vec<f32>> {
    if a.data_type() != gltf::accessor::DataType::F32 {
        return None;
    }
    use gltf::accessor::{Dimensions as D, Iter};
    let get = |b: gltf::Buffer| buffers.get(b.index()).map(|v| v.as_slice());
    let k = a.dimensions().multiplicity();
    // Each element is read whole (its stride is the view's), then flattened.
    let flat: Vec<f32> = match a.dimensions() {
        D::Scalar => Iter::<f32>::new(a.clone(), get)?.collect(),
        D::Vec2 => Iter::<[f32; 2]>::new(a.clone(), get)?.flatten().collect(),
        D::Vec3 => Iter::<[f32; 3]>::new(a.clone(), get)?.flatten().collect(),
        D::Vec4 => Iter::<[f32; 4]>::new(a.clone(), get)?.flatten().collect(),
        D::Mat3 => Iter::<[[f32; 3]; 3]>::new(a.clone(), get)?
            .flatten()
            .flatten()
            .collect(),
        D::Mat4 => Iter::<[[f32; 4]; 4]>::new(a.clone(), get)?
            .flatten()
            .flatten()
            .collect(),
        D::Mat2 => return None,
    };
    (flat.len() == a.count() * k).then_some(flat)
}

fn mesh_geometry(mesh: &gltf::Mesh, buffers: &[Vec<u8>]) -> ParseResult<Geometry> {
    let mut parts = Vec::new();
    for prim in mesh.primitives() {
        check_semantics(&prim)?;
        for (_, a) in prim.attributes() {
            check_accessor(&a, buffers)?;
        }
        if let Some(i) = prim.indices() {
            check_accessor(&i, buffers)?;
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(|v| v.as_slice()));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| {
                ParseError::whole(format!(
                    "mesh {} primitive {} has no POSITION",
                    mesh.index(),
                    prim.index()
                ))
            })?
            .map(Vec3::from)
            .collect();
        let n = positions.len() as u32;
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..n).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
            return Err(ParseError::whole(format!(
                "mesh {} primitive {}: index {bad} out of range ({n} vertices)",
                mesh.index(),
                prim.index()
            )));
        }
        let (vp, counts, kinds): (Vec<u32>, Vec<u32>, Vec<PrimKind>) = match prim.mode() {
            Mode::Triangles => {
                let t = indices.len() / 3;
                (
                    indices[..t * 3].to_vec(),
                    vec![3; t],
                    vec![PrimKind::Polygon; t],
                )
            }
            Mode::TriangleStrip => {
                let mut v = Vec::new();
                for k in 0..indices.len().saturating_sub(2) {
                    let (a, b, c) = (indices[k], indices[k + 1], indices[k + 2]);
                    v.extend(if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
                }
                let t = v.len() / 3;
                (v, vec![3; t], vec![PrimKind::Polygon; t])
            }
            Mode::TriangleFan => {
                let mut v = Vec::new();
                for k in 1..indices.len().saturating_sub(1) {
                    v.extend([indices[0], indices[k], indices[k + 1]]);
                }
                let t = v.len() / 3;
                (v, vec![3; t], vec![PrimKind::Polygon; t])
            }
            Mode::Lines => {
                let s = indices.len() / 2;
                (
                    indices[..s * 2].to_vec(),
                    vec![2; s],
                    vec![PrimKind::Polyline; s],
                )
            }
            Mode::LineStrip | Mode::LineLoop if indices.len() >= 2 => {
                let mut v = indices.clone();
                if prim.mode() == Mode::LineLoop {
                    v.push(indices[0]);
                }
                let c = v.len() as u32;
                (v, vec![c], vec![PrimKind::Polyline])
            }
            _ => (Vec::new(), Vec::new(), Vec::new()),
        };
        // glTF splits vertices wherever an attribute differs; weld them back
        // into shared points so the surface is connected, keeping the
        // attributes per corner (vertex class) when a point was shared.
        let (points, point_of) = crate::weld::weld_positions(&positions);
        let welded = points.len() < positions.len();
        let corner_src: Vec<u32> = vp.clone();
        let vp: Vec<u32> = vp.iter().map(|&i| point_of[i as usize]).collect();
        let mut g = Geometry::from_prims(points, vp, &counts, kinds)
            .map_err(|e| ParseError::whole(e.to_string()))?;
        let n_src = positions.len();
        let mut set = |name: &str, data: AttribData, info| -> ParseResult<()> {
            if data.len() != n_src {
                return Err(ParseError::whole(format!(
                    "mesh {} primitive {}: {name} has {} values for {n_src} vertices",
                    mesh.index(),
                    prim.index(),
                    data.len()
                )));
            }
            let (class, data) = if welded {
                (AttribClass::Vertex, data.gather(&corner_src))
            } else {
                (AttribClass::Point, data)
            };
            g.set_attrib(class, name, Attribute::from_data(data, info))
                .map_err(|e| ParseError::whole(e.to_string()))
        };
        if let Some(n) = reader.read_normals() {
            set(
                "N",
                AttribData::Vec3(n.map(Vec3::from).collect()),
                TypeInfo::Normal,
            )?;
        }
        if let Some(t) = reader.read_tex_coords(0) {
            set(
                "uv",
                AttribData::Vec2(t.into_f32().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect()),
                TypeInfo::TexCoord,
            )?;
        }
        if let Some(c) = reader.read_colors(0) {
            set(
                "Cd",
                AttribData::Vec3(c.into_rgb_f32().map(Vec3::from).collect()),
                TypeInfo::Color,
            )?;
        }
        for (semantic, accessor) in prim.attributes() {
            let gltf::Semantic::Extras(name) = semantic else {
                continue;
            };
            let values = custom_floats(&accessor, buffers);
            if let Some((data, info)) =
                values.and_then(|f| crate::gltf_attribs::read_custom(&accessor, f))
            {
                set(&name, data, info)?;
            }
        }
        parts.push(g);
    }
    let refs: Vec<&Geometry> = parts.iter().collect();
    ops::merge(&refs).map_err(|e| ParseError::whole(e.to_string()))
}

/// The most nodes the walk of a scene visits (a node reached through two
/// parents counts twice); glTF's node hierarchy is a tree, so a real file
/// visits each of its nodes once.
const MAX_NODE_VISITS: usize = 1_000_000;

/// Parses glTF JSON or GLB. Nodes of the default scene (or the first) are
/// walked with their transforms; a mesh used by one node is baked in place,
/// a mesh used by several becomes packed instances of one shared geometry.
/// `base` is the folder external buffer files are read from.
pub fn read_gltf(
    bytes: &[u8],
    base: Option<&Path>,
    progress: &dyn Progress,
) -> ParseResult<Geometry> {
    check_position_accessors(bytes)?;
    let doc = instancing::parse(bytes)?;
    let buffers = load_buffers(&doc, base)?;
    progress.start("reading glTF", doc.meshes().len() as u64);
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    // (mesh, world transform) for every mesh-carrying node.
    let mut placed: Vec<(usize, Mat4)> = Vec::new();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = match &scene {
        Some(s) => s.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect(),
        None => Vec::new(),
    };
    let mut visits = 0usize;
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(ParseError::whole(
                "node hierarchy deeper than 256 levels (a cycle?)",
            ));
        }
        // A node listed as a child twice at each of many levels doubles the
        // walk per level: bounded, so such a file is refused, not a hang.
        visits += 1;
        if visits > MAX_NODE_VISITS {
            return Err(ParseError::whole(format!(
                "node hierarchy reaches more than {MAX_NODE_VISITS} nodes (children shared between parents?)"
            )));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(m) = node.mesh() {
            match instancing::read_instances(&node, &doc, &buffers)? {
                Some(each) => placed.extend(each.into_iter().map(|t| (m.index(), world * t))),
                None => placed.push((m.index(), world)),
            }
        }
        for c in node.children() {
            stack.push((c, world, depth + 1));
        }
    }
    if scene.is_none() {
        placed = doc.meshes().map(|m| (m.index(), Mat4::IDENTITY)).collect();
    }
    placed.sort_by_key(|(m, _)| *m);
    let meshes: Vec<gltf::Mesh> = doc.meshes().collect();
    let mut baked = Vec::new();
    let mut instanced = Geometry::new();
    for (i, group) in placed.chunk_by(|a, b| a.0 == b.0).enumerate() {
        progress.set(i as u64);
        let mesh = &meshes[group[0].0];
        if let [(_, world)] = group {
            let mut g = mesh_geometry(mesh, &buffers)?;
            // The identity leaves values exact (a turned quaternion or matrix would round).
            if *world != Mat4::IDENTITY {
                ops::transform(&mut g, *world);
            }
            baked.push(g);
        } else {
            // A mesh placed more than once: instances of one shared source,
            // each on a point at its translation.
            let source = Arc::new(mesh_geometry(mesh, &buffers)?);
            instanced
                .add_packed_with(&source, group.len(), |k| group[k].1)
                .map_err(|e| ParseError::whole(e.to_string()))?;
        }
    }
    progress.finish();
    if baked.is_empty() {
        return Ok(instanced);
    }
    let mut all: Vec<&Geometry> = baked.iter().collect();
    all.push(&instanced);
    ops::merge(&all).map_err(|e| ParseError::whole(e.to_string()))
}
