//! Geometry for the browser's viewport as one binary message of typed arrays: polygons with their vertex counts (the page makes the fan triangles), polylines, loose points, `N` and `Cd`, packed instances as one prototype plus a matrix per instance.
//!
//! Layout: `GEO1`, a little-endian u32 header length, the JSON header
//! (padded to 4 bytes), then the arrays, each at a 4-byte aligned offset the
//! header names (`[byte offset, element count]`), so the browser views them
//! without copying.

use std::collections::HashMap;
use std::sync::Arc;

use geode_geo::ops::{self, Aabb};
use geode_geo::{AttribClass, AttribData, Geometry, PrimKind};
use geode_op::Value;
use glam::{Mat4, Vec3};
use serde_json::{json, Value as Json};

pub const MAGIC: &[u8; 4] = b"GEO1";

/// The bytes a geometry's viewport encoding may take before it is refused
/// (the browser must hold it too).
pub const MAX_BYTES: usize = 1 << 30;

/// How much the viewport draws at full detail.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Polygon triangles; a larger mesh is drawn reduced by vertex
    /// clustering to this many (a notice says so), never not at all.
    pub triangles: usize,
    /// Points of a point cloud; a larger one is sent as an even sample.
    pub points: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            triangles: 3_000_000,
            points: 20_000_000,
        }
    }
}

/// Pads to a multiple of 4 bytes (typed arrays need aligned offsets).
fn pad4(bytes: &mut Vec<u8>, fill: u8) {
    bytes.resize(bytes.len().next_multiple_of(4), fill);
}

/// Arrays appended at aligned offsets.
#[derive(Default)]
struct Arrays {
    bytes: Vec<u8>,
}

impl Arrays {
    fn push<T: bytemuck::Pod>(&mut self, items: &[T], per_item: usize) -> Json {
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(bytemuck::cast_slice(items));
        pad4(&mut self.bytes, 0);
        debug_assert_eq!(std::mem::size_of_val(items) / 4 % per_item, 0);
        json!([offset, std::mem::size_of_val(items) / 4])
    }
}

/// A vec3 (or the rgb of a vec4) attribute column as `Vec3`s.
fn vec3_column(data: &AttribData) -> Option<Vec<Vec3>> {
    match data {
        AttribData::Vec3(v) => Some(v.clone()),
        AttribData::Vec4(v) => Some(v.iter().map(|c| c.truncate()).collect()),
        _ => None,
    }
}

/// Where a display attribute lives and its values.
struct Source {
    class: AttribClass,
    values: Vec<Vec3>,
}

fn display_attrib(g: &Geometry, name: &str) -> Option<Source> {
    [
        AttribClass::Vertex,
        AttribClass::Point,
        AttribClass::Primitive,
        AttribClass::Detail,
    ]
    .into_iter()
    .find_map(|class| {
        let a = g.attrib(class, name)?;
        Some(Source {
            class,
            values: vec3_column(a.data())?,
        })
    })
}

impl Source {
    /// The value at a corner (vertex `v` of primitive `prim` on point `pt`).
    fn at(&self, prim: usize, v: usize, pt: usize) -> Vec3 {
        let i = match self.class {
            AttribClass::Point => pt,
            AttribClass::Vertex => v,
            AttribClass::Primitive => prim,
            AttribClass::Detail => 0,
        };
        self.values.get(i).copied().unwrap_or(Vec3::ONE)
    }
}

/// Visits the fan triangles of every polygon (first vertex as apex) as
/// corners (prim, vertex, point): the one triangulation the viewport uses.
pub(crate) fn for_each_fan(g: &Geometry, mut f: impl FnMut([(u32, u32, u32); 3])) {
    let vp = g.vertex_points();
    let offsets = g.prim_offsets();
    for (prim, kind) in g.prim_kinds().iter().enumerate() {
        if *kind != PrimKind::Polygon {
            continue;
        }
        let (a, b) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        let c = |v: usize| (prim as u32, v as u32, vp[v]);
        for k in a + 1..b.saturating_sub(1) {
            f([c(a), c(k), c(k + 1)]);
        }
    }
}

/// The corners of every fan triangle.
fn triangle_corners(g: &Geometry) -> Vec<[(u32, u32, u32); 3]> {
    let mut tris = Vec::new();
    for_each_fan(g, |t| tris.push(t));
    tris
}

/// The polygons as the page triangulates them (fans, first vertex as apex,
/// the order `for_each_fan` visits): each polygon's point indices, and the
/// vertex count of each (None when all have the same, which is returned
/// alone). A quad mesh travels in two thirds of the bytes of its triangles.
fn polygon_indices(g: &Geometry) -> (Vec<u32>, Vec<u32>, Option<u32>) {
    let vp = g.vertex_points();
    let offsets = g.prim_offsets();
    let mut points = Vec::with_capacity(g.num_vertices());
    let mut sizes = Vec::new();
    for (prim, kind) in g.prim_kinds().iter().enumerate() {
        let (a, b) = (offsets[prim] as usize, offsets[prim + 1] as usize);
        // Polygons of fewer than three vertices draw nothing.
        if *kind != PrimKind::Polygon || b - a < 3 {
            continue;
        }
        points.extend_from_slice(&vp[a..b]);
        sizes.push((b - a) as u32);
    }
    let uniform = sizes
        .first()
        .copied()
        .filter(|n| sizes.iter().all(|m| m == n));
    (points, sizes, uniform)
}

/// Drawn vertices where values differ per corner: corners on one point with
/// equal normal and colour share a vertex (Houdini splits only at seams).
struct Split {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    colors: Vec<Vec3>,
    triangles: Vec<u32>,
}

fn split_vertices(
    g: &Geometry,
    tris: &[[(u32, u32, u32); 3]],
    normals: Option<&Source>,
    colors: Option<&Source>,
) -> Split {
    const NONE: u32 = u32::MAX;
    let p = g.positions();
    // Drawn vertices of each point as a linked list: head per point, next per vertex.
    let mut head = vec![NONE; g.num_points()];
    let mut next: Vec<u32> = Vec::new();
    let mut out = Split {
        positions: Vec::new(),
        normals: Vec::new(),
        colors: Vec::new(),
        triangles: Vec::with_capacity(tris.len() * 3),
    };
    for &(prim, vertex, point) in tris.iter().flatten() {
        let at = |s: Option<&Source>| {
            s.map_or(Vec3::ZERO, |s| {
                s.at(prim as usize, vertex as usize, point as usize)
            })
        };
        let (n, c) = (at(normals), at(colors));
        let mut i = head[point as usize];
        while i != NONE && (out.normals[i as usize] != n || out.colors[i as usize] != c) {
            i = next[i as usize];
        }
        if i == NONE {
            i = out.positions.len() as u32;
            out.positions.push(p[point as usize]);
            out.normals.push(n);
            out.colors.push(c);
            next.push(head[point as usize]);
            head[point as usize] = i;
        }
        out.triangles.push(i);
    }
    out
}

/// One drawable part of a geometry (packed instances aside).
fn encode_part(g: &Geometry, name: &str, arrays: &mut Arrays) -> Json {
    let mut part = serde_json::Map::new();
    part.insert("name".into(), json!(name));
    let normals = display_attrib(g, "N");
    let colors = display_attrib(g, "Cd");
    let per_corner = |s: &Option<Source>| {
        s.as_ref()
            .is_some_and(|s| matches!(s.class, AttribClass::Vertex | AttribClass::Primitive))
    };
    let p = g.positions();
    if per_corner(&normals) || per_corner(&colors) {
        let split = split_vertices(g, &triangle_corners(g), normals.as_ref(), colors.as_ref());
        part.insert("corners".into(), arrays.push(&split.positions, 3));
        if normals.is_some() {
            part.insert("cornerNormals".into(), arrays.push(&split.normals, 3));
        }
        if colors.is_some() {
            part.insert("cornerColors".into(), arrays.push(&split.colors, 3));
        }
        part.insert("cornerTriangles".into(), arrays.push(&split.triangles, 1));
    } else {
        let (points, sizes, uniform) = polygon_indices(g);
        if !points.is_empty() {
            part.insert("polygons".into(), arrays.push(&points, 1));
            match uniform {
                Some(n) => part.insert("polygonSize".into(), json!(n)),
                None => part.insert("polygonSizes".into(), arrays.push(&sizes, 1)),
            };
        }
    }
    let (lines, loose) = lines_and_loose_points(g);
    if !part.contains_key("polygons")
        && !part.contains_key("cornerTriangles")
        && lines.is_empty()
        && loose.is_empty()
    {
        // Only instances (or nothing): their points travel in the matrices.
        return Json::Object(part);
    }
    part.insert("positions".into(), arrays.push(p, 3));
    for (key, src) in [("normals", &normals), ("colors", &colors)] {
        match src {
            Some(s) if s.class == AttribClass::Point => {
                part.insert(key.into(), arrays.push(&s.values, 3));
            }
            Some(s) if s.class == AttribClass::Detail => {
                let c = s.values.first().copied().unwrap_or(Vec3::ONE);
                part.insert(format!("{key}Uniform"), json!([c.x, c.y, c.z]));
            }
            _ => {}
        }
    }
    if !lines.is_empty() {
        part.insert("lines".into(), arrays.push(&lines, 2));
    }
    if !loose.is_empty() {
        part.insert("points".into(), arrays.push(&loose, 1));
    }
    Json::Object(part)
}

/// Segments of every polyline (and patch hulls), and the points no primitive uses.
fn lines_and_loose_points(g: &Geometry) -> (Vec<u32>, Vec<u32>) {
    let mut used = vec![false; g.num_points()];
    let mut lines = Vec::new();
    for prim in 0..g.num_prims() {
        let pts = g.prim_points(prim);
        for &q in pts {
            used[q as usize] = true;
        }
        if matches!(g.prim_kind(prim), PrimKind::Polyline | PrimKind::Patch(_)) {
            for w in pts.windows(2) {
                lines.extend_from_slice(w);
            }
        }
    }
    let loose = (0..g.num_points() as u32)
        .filter(|&i| !used[i as usize])
        .collect();
    (lines, loose)
}

/// The instances of every distinct prototype (nested packs flattened).
fn collect_instances(
    g: &Geometry,
    parent: Mat4,
    out: &mut Vec<(Arc<Geometry>, Vec<Mat4>)>,
    index: &mut HashMap<*const Geometry, usize>,
) {
    // Runs of instances share a prototype: look the map up only when it changes.
    let mut last: Option<(*const Geometry, usize)> = None;
    for prim in 0..g.num_prims() {
        let (Some(inst), Some(m)) = (g.packed_instance(prim), g.packed_world_transform(prim))
        else {
            continue;
        };
        let world = parent * m;
        let key = Arc::as_ptr(&inst.source);
        let slot = match last {
            Some((k, slot)) if k == key => slot,
            _ => {
                let slot = *index.entry(key).or_insert_with(|| {
                    // Usually one prototype has them all: size its list once.
                    let capacity = if out.is_empty() { g.num_prims() } else { 0 };
                    out.push((inst.source.clone(), Vec::with_capacity(capacity)));
                    out.len() - 1
                });
                last = Some((key, slot));
                slot
            }
        };
        out[slot].1.push(world);
        if inst.source.has_packed() {
            collect_instances(&inst.source, world, out, index);
        }
    }
}

/// Bounds of a geometry's own points (instances are bounded by their prototypes).
fn point_bounds(g: &Geometry) -> Aabb {
    g.positions().iter().fold(Aabb::empty(), |mut b, p| {
        b.include(*p);
        b
    })
}

/// The box enclosing `b` after the affine `m`, from its centre and half extent
/// (Arvo's method: the same box as its eight corners give, in a few operations).
fn transformed(b: &Aabb, m: &Mat4) -> Aabb {
    if b.is_empty() {
        return *b;
    }
    let centre = m.transform_point3(b.center());
    let half = glam::Mat3::from_mat4(*m).abs() * (b.size() * 0.5);
    Aabb {
        min: centre - half,
        max: centre + half,
    }
}

/// Estimated encoding size, to refuse before allocating.
fn estimate(g: &Geometry) -> usize {
    g.num_points() * 40 + g.num_vertices() * 80 + g.packed_instances().len() * 64
}

/// Why a value cannot be shown.
#[derive(Debug, thiserror::Error)]
pub enum ShowError {
    #[error(
        "the result would take {0} for the viewport (limit {1}); view an earlier node or reduce it"
    )]
    TooLarge(String, String),
    #[error("a field has no geometry to draw: mesh it with a polygonise node to see it")]
    Field,
}

/// A value encoded for the viewport.
pub struct Encoded {
    /// The `GEO1` message.
    pub bytes: Vec<u8>,
    /// `[[min], [max]]` of everything drawn, or null.
    pub bounds: Json,
}

/// A geometry as the viewport draws it: polygons beyond the limit reduced
/// by vertex clustering, a point cloud beyond it sampled evenly; with what
/// was reduced (`[drawn, of]` per kind).
fn drawable(g: Arc<Geometry>, limits: &Limits) -> (Arc<Geometry>, Json) {
    let triangles = ops::fan_triangle_count(&g);
    if triangles > limits.triangles {
        let reduced = ops::cluster_triangles(&g, limits.triangles);
        let drawn = ops::fan_triangle_count(&reduced);
        return (Arc::new(reduced), json!({"triangles": [drawn, triangles]}));
    }
    if g.num_prims() == 0 && g.num_points() > limits.points {
        let step = g.num_points().div_ceil(limits.points);
        let keep: Vec<u32> = (0..g.num_points() as u32).step_by(step).collect();
        let mut sample = Geometry::new();
        sample.add_points(
            &keep
                .iter()
                .map(|&i| g.positions()[i as usize])
                .collect::<Vec<_>>(),
        );
        if let Some(cd) = g.attrib(AttribClass::Point, "Cd") {
            let _ = sample.set_attrib(AttribClass::Point, "Cd", cd.gather(&keep));
        }
        let of = g.num_points();
        return (Arc::new(sample), json!({"points": [keep.len(), of]}));
    }
    (g, Json::Null)
}

/// Encodes a value for the viewport (`header_extra` goes into the header).
pub fn encode(value: &Value, header_extra: Json) -> Result<Encoded, ShowError> {
    encode_limited(value, header_extra, &Limits::default())
}

/// [`encode`] with other limits than the default.
pub fn encode_limited(
    value: &Value,
    header_extra: Json,
    limits: &Limits,
) -> Result<Encoded, ShowError> {
    let geos: Vec<(String, Arc<Geometry>)> = match value {
        Value::Geometry(g) => vec![(String::new(), g.clone())],
        Value::Bundle(b) => b
            .entries
            .iter()
            .map(|(n, g)| (n.clone(), g.clone()))
            .collect(),
        _ => return Err(ShowError::Field),
    };
    let geos: Vec<(String, Arc<Geometry>, Json)> = geos
        .into_iter()
        .map(|(n, g)| {
            let (g, reduced) = drawable(g, limits);
            (n, g, reduced)
        })
        .collect();
    let size: usize = geos.iter().map(|(_, g, _)| estimate(g)).sum();
    if size > MAX_BYTES {
        let h = |b: usize| geode_op::human_bytes(b as f64);
        return Err(ShowError::TooLarge(h(size), h(MAX_BYTES)));
    }
    let mut arrays = Arrays {
        bytes: Vec::with_capacity(size + (1 << 16)),
    };
    let mut parts = Vec::new();
    let mut bbox = Aabb::empty();
    for (name, g, reduced) in &geos {
        bbox = bbox.union(&point_bounds(g));
        let mut part = encode_part(g, name, &mut arrays);
        if !reduced.is_null() {
            part["reduced"] = reduced.clone();
        }
        parts.push(part);
        let mut protos = Vec::new();
        collect_instances(g, Mat4::IDENTITY, &mut protos, &mut HashMap::new());
        for (k, (proto, mats)) in protos.iter().enumerate() {
            let mut part = encode_part(proto, &format!("{name}#proto{k}"), &mut arrays);
            part["instances"] = arrays.push(mats, 16);
            let pb = point_bounds(proto);
            bbox = mats.iter().fold(bbox, |b, m| b.union(&transformed(&pb, m)));
            part["protoBounds"] = json!([pb.min.to_array(), pb.max.to_array()]);
            parts.push(part);
        }
    }
    let bounds = if bbox.is_empty() {
        Json::Null
    } else {
        json!([bbox.min.to_array(), bbox.max.to_array()])
    };
    let mut header = header_extra;
    header["parts"] = Json::Array(parts);
    header["bounds"] = bounds.clone();
    let mut head = serde_json::to_vec(&header).expect("headers serialise");
    pad4(&mut head, b' ');
    let mut prefix = Vec::with_capacity(8 + head.len());
    prefix.extend_from_slice(MAGIC);
    prefix.extend_from_slice(&(head.len() as u32).to_le_bytes());
    prefix.extend_from_slice(&head);
    // The header goes in front of the arrays in place (one move, no second buffer).
    let mut bytes = arrays.bytes;
    bytes.splice(0..0, prefix);
    Ok(Encoded { bytes, bounds })
}

/// Counts and memory of a value (the viewport's readout; bounds come with the geometry).
pub fn stats(value: &Value) -> Json {
    match value {
        Value::Geometry(g) => geometry_stats(g),
        Value::Bundle(b) => json!({
            "bundle": b.entries.iter().map(|(n, g)| (n.clone(), geometry_stats(g))).collect::<serde_json::Map<_, _>>(),
        }),
        _ => json!({"field": true}),
    }
}

pub fn geometry_stats(g: &Geometry) -> Json {
    let mut kinds: HashMap<&str, usize> = HashMap::new();
    for k in g.prim_kinds() {
        *kinds.entry(k.name()).or_default() += 1;
    }
    json!({
        "points": g.num_points(),
        "vertices": g.num_vertices(),
        "primitives": g.num_prims(),
        "kinds": kinds,
        "memory": g.memory_bytes(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::{AttribValue, Attribute, TypeInfo};
    use glam::Vec3;

    /// The header and the arrays of an encoded message.
    fn decode(bytes: &[u8]) -> (Json, &[u8]) {
        assert_eq!(&bytes[..4], MAGIC);
        let n = u32::from_le_bytes(bytes[4..8].try_into().unwrap()) as usize;
        assert_eq!(n % 4, 0);
        (
            serde_json::from_slice(&bytes[8..8 + n]).unwrap(),
            &bytes[8 + n..],
        )
    }

    fn floats(body: &[u8], at: &Json) -> Vec<f32> {
        let (off, len) = (
            at[0].as_u64().unwrap() as usize,
            at[1].as_u64().unwrap() as usize,
        );
        assert_eq!(off % 4, 0);
        bytemuck::cast_slice::<u8, f32>(&body[off..off + len * 4]).to_vec()
    }

    fn uints(body: &[u8], at: &Json) -> Vec<u32> {
        let (off, len) = (
            at[0].as_u64().unwrap() as usize,
            at[1].as_u64().unwrap() as usize,
        );
        bytemuck::cast_slice::<u8, u32>(&body[off..off + len * 4]).to_vec()
    }

    /// The fan triangles the page makes of a part's polygons.
    fn triangles(body: &[u8], part: &Json) -> Vec<u32> {
        let pts = uints(body, &part["polygons"]);
        let sizes = match part.get("polygonSizes") {
            Some(at) => uints(body, at),
            None => {
                let n = part["polygonSize"].as_u64().unwrap() as u32;
                vec![n; pts.len() / n as usize]
            }
        };
        let (mut out, mut at) = (Vec::new(), 0usize);
        for n in sizes {
            for k in 1..n as usize - 1 {
                out.extend_from_slice(&[pts[at], pts[at + k], pts[at + k + 1]]);
            }
            at += n as usize;
        }
        out
    }

    fn quad() -> Geometry {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        Geometry::from_polygons(p, vec![0, 1, 2, 3], &[4]).unwrap()
    }

    #[test]
    fn polygons_become_fan_triangles_over_shared_points() {
        let bytes = encode(&Value::Geometry(Arc::new(quad())), json!({"generation": 3}))
            .unwrap()
            .bytes;
        let (h, body) = decode(&bytes);
        assert_eq!(h["generation"], 3);
        let part = &h["parts"][0];
        assert_eq!(uints(body, &part["polygons"]), vec![0, 1, 2, 3]);
        assert_eq!(part["polygonSize"], 4);
        assert_eq!(triangles(body, part), vec![0, 1, 2, 0, 2, 3]);
        assert_eq!(floats(body, &part["positions"])[3..6], [1.0, 0.0, 0.0]);
        assert_eq!(h["bounds"], json!([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]]));
        assert!(part.get("corners").is_none());
    }

    #[test]
    fn primitive_colours_are_expanded_per_corner() {
        let mut g = quad();
        g.set_attrib(
            AttribClass::Primitive,
            "Cd",
            Attribute::new(
                AttribValue::Vec3(Vec3::new(1.0, 0.0, 0.0)),
                TypeInfo::Color,
                1,
            ),
        )
        .unwrap();
        let bytes = encode(&Value::Geometry(Arc::new(g)), json!({}))
            .unwrap()
            .bytes;
        let (h, body) = decode(&bytes);
        let part = &h["parts"][0];
        // One colour for the whole quad: its four corners stay four vertices.
        assert_eq!(floats(body, &part["corners"]).len(), 4 * 3);
        assert_eq!(
            floats(body, &part["cornerColors"]),
            [1.0, 0.0, 0.0].repeat(4)
        );
        assert_eq!(
            uints(body, &part["cornerTriangles"]),
            vec![0, 1, 2, 0, 2, 3]
        );
    }

    #[test]
    fn corners_split_where_their_values_differ() {
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::Y,
            Vec3::new(2.0, 0.0, 0.0),
        ];
        let mut g = Geometry::from_polygons(p, vec![0, 1, 2, 3, 1, 4, 2], &[4, 3]).unwrap();
        let red = AttribValue::Vec3(Vec3::X);
        let mut cd = Attribute::new(red, TypeInfo::Color, 2);
        cd.values_mut().set(1, &AttribValue::Vec3(Vec3::Y)).unwrap();
        g.set_attrib(AttribClass::Primitive, "Cd", cd).unwrap();
        let bytes = encode(&Value::Geometry(Arc::new(g)), json!({}))
            .unwrap()
            .bytes;
        let (h, body) = decode(&bytes);
        let part = &h["parts"][0];
        // Points 1 and 2 are on both faces, of different colours: 4 + 3 vertices.
        assert_eq!(floats(body, &part["corners"]).len(), 7 * 3);
        assert_eq!(
            uints(body, &part["cornerTriangles"]),
            vec![0, 1, 2, 0, 2, 3, 4, 5, 6]
        );
    }

    #[test]
    fn packed_instances_are_one_prototype_and_a_matrix_each() {
        let proto = Arc::new(quad());
        let mut g = Geometry::new();
        for x in 0..3 {
            let pt = g.add_point(Vec3::new(x as f32 * 2.0, 0.0, 0.0));
            g.add_packed(pt, proto.clone(), glam::Mat4::IDENTITY)
                .unwrap();
        }
        let bytes = encode(&Value::Geometry(Arc::new(g)), json!({}))
            .unwrap()
            .bytes;
        let (h, body) = decode(&bytes);
        let parts = h["parts"].as_array().unwrap();
        assert_eq!(parts.len(), 2, "the host part and one prototype");
        let m = floats(body, &parts[1]["instances"]);
        assert_eq!(m.len(), 3 * 16);
        assert_eq!(m[16 + 12], 2.0, "the second instance's translation x");
        assert_eq!(triangles(body, &parts[1]).len(), 6);
        assert_eq!(h["bounds"][1][0], 5.0);
    }

    #[test]
    fn beyond_the_limits_a_mesh_is_drawn_reduced_and_a_cloud_sampled() {
        let mut g = Geometry::new();
        let n = 60u32;
        let pts: Vec<Vec3> = (0..n * n)
            .map(|i| Vec3::new((i % n) as f32, (i / n) as f32, 0.0))
            .collect();
        g.add_points(&pts);
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let i = y * n + x;
                g.add_polygon(&[i, i + 1, i + n + 1, i + n]).unwrap();
            }
        }
        let limits = Limits {
            triangles: 1000,
            points: 100,
        };
        let (h, body) = decode_owned(
            &encode_limited(&Value::Geometry(Arc::new(g)), json!({}), &limits)
                .unwrap()
                .bytes,
        );
        let part = &h["parts"][0];
        let [drawn, of] = [
            &part["reduced"]["triangles"][0],
            &part["reduced"]["triangles"][1],
        ];
        assert_eq!(of, 59 * 59 * 2);
        assert!(
            drawn.as_u64().unwrap() <= 1000 && drawn.as_u64().unwrap() > 300,
            "{part}"
        );
        assert_eq!(
            triangles(&body, part).len() as u64,
            drawn.as_u64().unwrap() * 3
        );
        // A cloud of 1000 points over a limit of 100: every tenth.
        let mut cloud = Geometry::new();
        cloud.add_points(&(0..1000).map(|i| Vec3::splat(i as f32)).collect::<Vec<_>>());
        let (h, body) = decode_owned(
            &encode_limited(&Value::Geometry(Arc::new(cloud)), json!({}), &limits)
                .unwrap()
                .bytes,
        );
        let part = &h["parts"][0];
        assert_eq!(part["reduced"]["points"], json!([100, 1000]));
        assert_eq!(floats(&body, &part["positions"])[3..6], [10.0, 10.0, 10.0]);
    }

    fn decode_owned(bytes: &[u8]) -> (Json, Vec<u8>) {
        let (h, body) = decode(bytes);
        (h, body.to_vec())
    }

    #[test]
    fn polylines_and_loose_points() {
        let mut g = Geometry::new();
        let a = g.add_point(Vec3::ZERO);
        let b = g.add_point(Vec3::X);
        let c = g.add_point(Vec3::Y);
        g.add_point(Vec3::Z);
        g.add_polyline(&[a, b, c]).unwrap();
        let bytes = encode(&Value::Geometry(Arc::new(g)), json!({}))
            .unwrap()
            .bytes;
        let (h, body) = decode(&bytes);
        let part = &h["parts"][0];
        assert_eq!(uints(body, &part["lines"]), vec![0, 1, 1, 2]);
        assert_eq!(uints(body, &part["points"]), vec![3]);
    }
}
