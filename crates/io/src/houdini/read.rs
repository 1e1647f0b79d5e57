//! Houdini's geometry schema (`.geo`, `.bgeo`) read into a `Geometry`: topology, polygons, polylines and packed geometry, attributes of every class, groups.

use glam::Vec3;

use geode_geo::attrib::AttribClass;
use geode_geo::{Geometry, PrimKind};

use std::sync::Arc;

use super::attribs::{attribute, decode_values};
use super::bad;
use super::groups::groups;
use super::houdini_order;
use super::json::Json;
use super::packed::{self, PackedPrim};
use crate::error::{ParseError, ParseResult};

/// Reads a parsed document. `file_bytes` bounds the element counts the
/// header may claim, and `budget` the bytes they may need, before anything
/// is allocated for them.
pub fn geometry(doc: &Json, file_bytes: usize, budget: u64) -> ParseResult<Geometry> {
    if doc.items().is_none() {
        return Err(ParseError::whole(
            "not a Houdini geometry file: expected a top-level list of keys and values (`[\"fileversion\", ...]`)",
        ));
    }
    let counts = Counts::read(doc, file_bytes, budget)?;
    let pointref = pointref(doc, &counts)?;
    let prims = primitives(doc, &counts)?;
    let positions = positions(doc, counts.points, budget)?;
    let (prim_order, vertex_order) = prims.layout();
    let flat: Vec<usize> = (0..prims.kinds.len())
        .filter(|&p| !matches!(prims.kinds[p], PrimKind::Packed(_)))
        .collect();
    let n_flat_vertices: usize = flat.iter().map(|&p| prims.counts[p] as usize).sum();
    let vertex_points: Vec<u32> = vertex_order[..n_flat_vertices]
        .iter()
        .map(|&v| pointref[v as usize])
        .collect();
    let mut g = Geometry::from_prims(
        positions,
        vertex_points,
        &flat.iter().map(|&p| prims.counts[p]).collect::<Vec<_>>(),
        flat.iter().map(|&p| prims.kinds[p]).collect(),
    )
    .map_err(|e| ParseError::whole(format!("primitives: {e}")))?;
    if !prims.packed.is_empty() {
        let shared = packed::read_shared(doc, &|d| geometry(d, file_bytes, budget))?;
        for (_, p) in &prims.packed {
            let source = shared.get(&p.key).ok_or_else(|| {
                bad(
                    "primitives",
                    format!(
                        "the embedded detail `{}` is not in sharedprimitivedata",
                        p.key
                    ),
                )
            })?;
            g.add_packed(pointref[p.vertex as usize], Arc::clone(source), p.transform)
                .map_err(|e| bad("primitives", e))?;
        }
    }
    let attribs = doc.get("attributes");
    for (key, class, n) in [
        ("pointattributes", AttribClass::Point, counts.points),
        ("vertexattributes", AttribClass::Vertex, counts.vertices),
        ("primitiveattributes", AttribClass::Primitive, counts.prims),
        ("globalattributes", AttribClass::Detail, 1),
    ] {
        let Some(list) = attribs.and_then(|a| a.get(key)).and_then(Json::items) else {
            continue;
        };
        for entry in list {
            let Some((name, attrib)) = attribute(entry, key, n, budget)? else {
                continue;
            };
            if class == AttribClass::Point && name == geode_geo::P {
                continue;
            }
            let attrib = match class {
                AttribClass::Vertex => attrib.gather(&vertex_order),
                AttribClass::Primitive => attrib.gather(&prim_order),
                _ => attrib,
            };
            g.set_attrib(class, &name, attrib)
                .map_err(|e| bad(format!("{key} `{name}`"), e))?;
        }
    }
    for (key, n, point) in [
        ("pointgroups", counts.points, true),
        ("primitivegroups", counts.prims, false),
    ] {
        for (name, group) in groups(doc, key, n)? {
            let r = if point {
                g.set_point_group(&name, group)
            } else {
                g.set_prim_group(&name, group.gather(&prim_order))
            };
            r.map_err(|e| bad(format!("{key} `{name}`"), e))?;
        }
    }
    Ok(g)
}

struct Counts {
    points: usize,
    vertices: usize,
    prims: usize,
}

impl Counts {
    fn read(doc: &Json, file_bytes: usize, budget: u64) -> ParseResult<Counts> {
        // A vertex costs at least a byte of `pointref`; a point or a primitive
        // at least a byte per page of 1024 (constant pages).
        let limit = |key: &str, per_byte: usize| -> ParseResult<usize> {
            let n = doc.get(key).and_then(Json::as_i64).unwrap_or(0);
            let bound = (file_bytes.saturating_mul(per_byte) + 1024).min(u32::MAX as usize);
            match usize::try_from(n) {
                Ok(n) if n <= bound => Ok(n),
                _ => Err(bad(
                    key,
                    format!(
                        "{n} is not a count this {file_bytes}-byte file can hold (at most {bound})"
                    ),
                )),
            }
        };
        let counts = Counts {
            points: limit("pointcount", 1024)?,
            vertices: limit("vertexcount", 1)?,
            prims: limit("primitivecount", 1024)?,
        };
        // Positions, a point per vertex and a primitive's kind and first
        // vertex: the least the geometry will hold.
        let bytes = (counts.points as u64 * 12)
            .saturating_add(counts.vertices as u64 * 4)
            .saturating_add(counts.prims as u64 * 16);
        if bytes > budget {
            return Err(ParseError::over_budget(format!(
                "pointcount: {} points, {} vertices and {} primitives would need {}, more than the memory budget of {} (GEODE_MEMORY_MB)",
                counts.points,
                counts.vertices,
                counts.prims,
                geode_geo::human_bytes(bytes as f64),
                geode_geo::human_bytes(budget as f64)
            )));
        }
        Ok(counts)
    }
}

fn pointref(doc: &Json, counts: &Counts) -> ParseResult<Vec<u32>> {
    let indices = doc
        .get("topology")
        .and_then(|t| t.get("pointref"))
        .and_then(|p| p.get("indices"));
    let Some(indices) = indices else {
        return if counts.vertices == 0 {
            Ok(Vec::new())
        } else {
            Err(bad("topology", "missing `pointref` `indices`"))
        };
    };
    let check = |p: i64| -> ParseResult<u32> {
        u32::try_from(p)
            .ok()
            .filter(|&p| (p as usize) < counts.points)
            .ok_or_else(|| {
                bad(
                    "topology.pointref.indices",
                    format!("point {p} out of range (pointcount {})", counts.points),
                )
            })
    };
    let points: Vec<u32> = match indices {
        // Binary files hold the indices packed as int32: no widening copy.
        Json::I32s(v) => v
            .iter()
            .map(|&p| check(p as i64))
            .collect::<ParseResult<_>>()?,
        other => other
            .integers()
            .ok_or_else(|| {
                bad(
                    "topology.pointref.indices",
                    "expected a list of point numbers",
                )
            })?
            .into_iter()
            .map(check)
            .collect::<ParseResult<_>>()?,
    };
    if points.len() != counts.vertices {
        return Err(bad(
            "topology.pointref.indices",
            format!(
                "{} entries for a vertexcount of {}",
                points.len(),
                counts.vertices
            ),
        ));
    }
    Ok(points)
}

/// Primitives in file order: kinds, vertex counts, and the Houdini vertex of
/// each geode vertex (polygons turned from Houdini's clockwise order).
struct Prims {
    kinds: Vec<PrimKind>,
    counts: Vec<u32>,
    vertices: Vec<u32>,
    /// Packed primitives (their kinds above are placeholders), in file order.
    packed: Vec<(usize, PackedPrim)>,
}

impl Prims {
    /// Whether another primitive with these vertices fits the header's counts.
    fn check(&self, verts: &[u32], counts: &Counts) -> ParseResult<()> {
        if self.kinds.len() == counts.prims {
            return Err(bad(
                "primitives",
                format!(
                    "more primitives than the primitivecount of {}",
                    counts.prims
                ),
            ));
        }
        if let Some(&v) = verts.iter().find(|&&v| v as usize >= counts.vertices) {
            return Err(bad(
                "primitives",
                format!("vertex {v} out of range (vertexcount {})", counts.vertices),
            ));
        }
        Ok(())
    }

    fn push_packed(&mut self, p: PackedPrim, counts: &Counts) -> ParseResult<()> {
        self.check(&[p.vertex], counts)?;
        self.kinds.push(PrimKind::Packed(0));
        self.counts.push(1);
        self.vertices.push(p.vertex);
        self.packed.push((self.kinds.len() - 1, p));
        Ok(())
    }

    /// Polygons and polylines first, packed primitives after (geode adds
    /// those one by one): the primitive order and each geode vertex's
    /// Houdini vertex in that order.
    fn layout(&self) -> (Vec<u32>, Vec<u32>) {
        let mut starts = Vec::with_capacity(self.counts.len());
        let mut at = 0usize;
        for &c in &self.counts {
            starts.push(at);
            at += c as usize;
        }
        let packed = |p: usize| matches!(self.kinds[p], PrimKind::Packed(_));
        let order: Vec<u32> = (0..self.kinds.len())
            .filter(|&p| !packed(p))
            .chain((0..self.kinds.len()).filter(|&p| packed(p)))
            .map(|p| p as u32)
            .collect();
        let vertices = order
            .iter()
            .flat_map(|&p| {
                let p = p as usize;
                self.vertices[starts[p]..starts[p] + self.counts[p] as usize]
                    .iter()
                    .copied()
            })
            .collect();
        (order, vertices)
    }

    fn push(&mut self, closed: bool, verts: &[u32], counts: &Counts) -> ParseResult<()> {
        self.check(verts, counts)?;
        self.kinds.push(if closed {
            PrimKind::Polygon
        } else {
            PrimKind::Polyline
        });
        self.counts.push(verts.len() as u32);
        let start = self.vertices.len();
        self.vertices.extend_from_slice(verts);
        if closed {
            houdini_order(&mut self.vertices[start..]);
        }
        Ok(())
    }
}

fn primitives(doc: &Json, counts: &Counts) -> ParseResult<Prims> {
    let mut prims = Prims {
        kinds: Vec::new(),
        counts: Vec::new(),
        vertices: Vec::with_capacity(counts.vertices),
        packed: Vec::new(),
    };
    let Some(list) = doc.get("primitives").and_then(Json::items) else {
        return Ok(prims);
    };
    for (i, entry) in list.iter().enumerate() {
        let (header, body) = match entry.items() {
            Some([h, b]) => (h, b),
            _ => return Err(bad(format!("primitives[{i}]"), "expected [header, body]")),
        };
        let ty = header.get("type").and_then(Json::as_str).unwrap_or("");
        match ty {
            "Polygon_run" | "p_r" | "PolygonCurve_run" | "c_r" => poly_run(
                body,
                ty.starts_with("Polygon_") || ty == "p_r",
                &mut prims,
                counts,
            )
            .map_err(|e| bad(format!("primitives[{i}] ({ty})"), e.message))?,
            "Poly" => {
                let verts = vertex_list(body.get("vertex"))
                    .ok_or_else(|| bad(format!("primitives[{i}] (Poly)"), "expected `vertex`"))?;
                let closed = body.get("closed").and_then(Json::as_bool).unwrap_or(true);
                prims.push(closed, &verts, counts)?;
            }
            "run" if header.get("runtype").and_then(Json::as_str) == Some("Poly") => {
                classic_run(header, body, &mut prims, counts)
                    .map_err(|e| bad(format!("primitives[{i}] (run of Poly)"), e.message))?
            }
            "PackedGeometry" => {
                let p = packed::read_prim(&|name| body.get(name).cloned())
                    .map_err(|e| bad(format!("primitives[{i}] (PackedGeometry)"), e.message))?;
                prims.push_packed(p, counts)?;
            }
            "run" if header.get("runtype").and_then(Json::as_str) == Some("PackedGeometry") => {
                let run = packed::read_run(header, body).map_err(|e| {
                    bad(
                        format!("primitives[{i}] (run of PackedGeometry)"),
                        e.message,
                    )
                })?;
                for p in run {
                    prims.push_packed(p, counts)?;
                }
            }
            other => {
                let name = if other == "run" {
                    header.get("runtype").and_then(Json::as_str).unwrap_or("?")
                } else {
                    other
                };
                return Err(bad(
                    format!("primitives[{i}]"),
                    format!("primitive type `{name}` is not supported: geode reads polygons, polylines and embedded packed geometry (in Houdini, unpack or convert to polygons before saving)"),
                ));
            }
        }
    }
    if prims.kinds.len() != counts.prims {
        return Err(bad(
            "primitives",
            format!(
                "{} primitives for a primitivecount of {}",
                prims.kinds.len(),
                counts.prims
            ),
        ));
    }
    Ok(prims)
}

fn vertex_list(v: Option<&Json>) -> Option<Vec<u32>> {
    v?.integers()?
        .into_iter()
        .map(|x| u32::try_from(x).ok())
        .collect()
}

/// `Polygon_run`: consecutive vertices from `startvertex`, sizes listed or run-length encoded.
fn poly_run(body: &Json, closed: bool, prims: &mut Prims, counts: &Counts) -> ParseResult<()> {
    let start = body
        .get_any(&["startvertex", "s_v"])
        .and_then(Json::as_i64)
        .ok_or_else(|| ParseError::whole("missing `startvertex`"))?;
    let n = body
        .get_any(&["nprimitives", "n_p"])
        .and_then(Json::as_i64)
        .ok_or_else(|| ParseError::whole("missing `nprimitives`"))?;
    // Checked before any list is built from it.
    let room = counts.prims - prims.kinds.len();
    if n < 0 || n as u64 > room as u64 {
        return Err(ParseError::whole(format!(
            "{n} primitives where the primitivecount of {} leaves room for {room}",
            counts.prims
        )));
    }
    let sizes: Vec<i64> = if let Some(rle) = body.get_any(&["nvertices_rle", "r_v"]) {
        let pairs = rle
            .integers()
            .ok_or_else(|| ParseError::whole("`nvertices_rle` is not a list of integers"))?;
        let mut sizes = Vec::new();
        for pair in pairs.chunks(2) {
            let [size, repeat] = pair else {
                return Err(ParseError::whole("`nvertices_rle` has an odd length"));
            };
            // `n` is checked against the header above; the repeat is compared
            // with what is left of it, never added to, so it cannot overflow.
            let left = n as usize - sizes.len();
            let repeat = usize::try_from(*repeat)
                .ok()
                .filter(|&r| r <= left)
                .ok_or_else(|| {
                    ParseError::whole(format!(
                        "`nvertices_rle` repeats a size {repeat} times where {left} of `nprimitives` {n} are left"
                    ))
                })?;
            sizes.extend(std::iter::repeat_n(*size, repeat));
        }
        sizes
    } else {
        body.get_any(&["nvertices", "n_v"])
            .and_then(Json::integers)
            .ok_or_else(|| ParseError::whole("missing `nvertices` or `nvertices_rle`"))?
    };
    if sizes.len() as i64 != n {
        return Err(ParseError::whole(format!(
            "{} sizes for {n} primitives",
            sizes.len()
        )));
    }
    let mut at = start;
    let mut verts = Vec::new();
    for size in sizes {
        // Checked arithmetic: `startvertex` and the sizes are the file's.
        let end = at.checked_add(size);
        if at < 0 || size < 0 || end.is_none_or(|end| end > counts.vertices as i64) {
            return Err(ParseError::whole(format!(
                "a primitive of {size} vertices from vertex {at} runs past vertexcount {}",
                counts.vertices
            )));
        }
        verts.clear();
        verts.extend((at..at + size).map(|v| v as u32));
        prims.push(closed, &verts, counts)?;
        at += size;
    }
    Ok(())
}

/// The run form of Houdini 12-15: uniform fields in the header, each
/// primitive's varying fields (`vertex`, maybe `closed`) in the body.
fn classic_run(header: &Json, body: &Json, prims: &mut Prims, counts: &Counts) -> ParseResult<()> {
    let varying: Vec<&str> = header
        .get("varyingfields")
        .and_then(Json::items)
        .map(|f| f.iter().filter_map(Json::as_str).collect())
        .unwrap_or_default();
    let uniform_closed = header
        .get("uniformfields")
        .and_then(|u| u.get("closed"))
        .and_then(Json::as_bool)
        .unwrap_or(true);
    let vertex_at = varying
        .iter()
        .position(|&f| f == "vertex")
        .ok_or_else(|| ParseError::whole("`varyingfields` lacks `vertex`"))?;
    let closed_at = varying.iter().position(|&f| f == "closed");
    for prim in body.items().unwrap_or_default() {
        let fields = prim
            .items()
            .ok_or_else(|| ParseError::whole("expected a list of fields per primitive"))?;
        let verts = vertex_list(fields.get(vertex_at))
            .ok_or_else(|| ParseError::whole("expected a vertex list"))?;
        let closed = closed_at
            .and_then(|c| fields.get(c))
            .and_then(Json::as_bool)
            .unwrap_or(uniform_closed);
        prims.push(closed, &verts, counts)?;
    }
    Ok(())
}

fn positions(doc: &Json, n: usize, budget: u64) -> ParseResult<Vec<Vec3>> {
    let list = doc
        .get("attributes")
        .and_then(|a| a.get("pointattributes"))
        .and_then(Json::items)
        .unwrap_or_default();
    for entry in list {
        let Some([header, body]) = entry.items() else {
            continue;
        };
        if header.get("name").and_then(Json::as_str) != Some(geode_geo::P) {
            continue;
        }
        let values = body
            .get("values")
            .ok_or_else(|| bad("pointattributes `P`", "missing `values`"))?;
        let size = values.get("size").and_then(Json::as_i64).unwrap_or(3) as usize;
        if !(3..=4).contains(&size) {
            return Err(bad(
                "pointattributes `P`",
                format!("tuple size {size}, expected 3 (or 4)"),
            ));
        }
        let flat =
            decode_values(values, n, size, budget).map_err(|e| e.within("pointattributes `P`"))?;
        return Ok(flat
            .chunks_exact(size)
            .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
            .collect());
    }
    if n == 0 {
        Ok(Vec::new())
    } else {
        Err(bad("pointattributes", "no `P` attribute"))
    }
}
