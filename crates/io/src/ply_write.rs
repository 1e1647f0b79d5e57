//! PLY writer (binary little-endian): every numeric attribute as properties, polylines as polylines, a header comment per attribute so geode reads its type back.
//!
//! Point attributes are `vertex` properties, primitive attributes
//! properties of the `face` (polygons) and `polyline` (polylines)
//! elements, vertex attributes per-corner lists on those elements. `N`,
//! `Cd` and `uv` take PLY's usual names (`nx ny nz`, `red green blue`,
//! `s t`; a vertex `uv` the `texcoord` list). Other vectors and matrices are
//! one property per component (`orient_x` .. `orient_w`, `xform_0` ..),
//! per-element arrays list properties; a comment
//! `geode attribute CLASS NAME TYPE TYPEINFO` before the elements lets the
//! reader rebuild the attribute. Strings, detail attributes and groups have
//! no PLY form and are reported.

use std::io::Write;
use std::path::Path;

use geode_geo::{AttribClass, AttribData, AttribType, Attribute, Geometry, PrimKind};

use crate::attrib_codec::{component_suffixes, type_token};

use crate::atomic::os_err;
use crate::error::IoError;
use crate::progress::{describe_attrib, report_dropped, Progress, Throttle};

/// How one attribute is laid out in the file.
enum Layout {
    /// A standard PLY name set (`nx ny nz`, `red green blue`, `s t`).
    Standard(&'static [&'static str]),
    /// One scalar property per component, or the attribute's own name for a scalar.
    Components(Vec<String>),
    /// One list property of the attribute's name (arrays; vertex attributes per corner).
    List,
}

struct Column<'a> {
    name: &'a str,
    attrib: &'a Attribute,
    layout: Layout,
    int: bool,
}

impl Column<'_> {
    fn header(&self, out: &mut String, count_type: &str) {
        let scalar = if self.int { "int" } else { "float" };
        match &self.layout {
            Layout::Standard(names) => {
                for n in *names {
                    out.push_str(&format!("property float {n}\n"));
                }
            }
            Layout::Components(sfx) if sfx.is_empty() => {
                out.push_str(&format!("property {scalar} {}\n", self.name))
            }
            Layout::Components(sfx) => {
                for s in sfx {
                    out.push_str(&format!("property {scalar} {}_{s}\n", self.name));
                }
            }
            Layout::List => {
                let name = if self.name == "uv" && self.attrib.attrib_type() == AttribType::Vec2 {
                    "texcoord"
                } else {
                    self.name
                };
                out.push_str(&format!("property list {count_type} {scalar} {name}\n"));
            }
        }
    }

    /// The values of element `i`, little-endian.
    fn put(&self, buf: &mut Vec<u8>, i: usize) {
        match self.attrib.data() {
            AttribData::Int(v) => buf.extend_from_slice(&v[i].to_le_bytes()),
            AttribData::IntArray(v) => put_list(buf, v[i].len(), bytemuck::cast_slice(&v[i])),
            AttribData::FloatArray(v) => put_list(buf, v[i].len(), bytemuck::cast_slice(&v[i])),
            AttribData::Vec3Array(v) => put_list(buf, v[i].len() * 3, bytemuck::cast_slice(&v[i])),
            d => {
                let (flat, k) = d.as_floats().expect("numeric column");
                buf.extend_from_slice(bytemuck::cast_slice(&flat[i * k..(i + 1) * k]));
            }
        }
    }

    /// A prim's corners as one list (vertex attributes).
    fn put_corners(&self, buf: &mut Vec<u8>, corners: std::ops::Range<usize>, big: bool) {
        let per = match self.attrib.data() {
            AttribData::Int(_) => 1,
            d => d.as_floats().map_or(1, |(_, k)| k),
        };
        let n = corners.len() * per;
        if big {
            buf.extend_from_slice(&(n as u32).to_le_bytes());
        } else {
            buf.push(n as u8);
        }
        match self.attrib.data() {
            AttribData::Int(v) => buf.extend_from_slice(bytemuck::cast_slice(&v[corners])),
            d => {
                let (flat, k) = d.as_floats().expect("numeric column");
                buf.extend_from_slice(bytemuck::cast_slice(
                    &flat[corners.start * k..corners.end * k],
                ));
            }
        }
    }
}

/// A list property with a `uint` count.
fn put_list(buf: &mut Vec<u8>, n: usize, bytes: &[u8]) {
    buf.extend_from_slice(&(n as u32).to_le_bytes());
    buf.extend_from_slice(bytes);
}

/// The columns of one class, and what that class cannot carry.
fn columns<'a>(g: &'a Geometry, class: AttribClass, dropped: &mut Vec<String>) -> Vec<Column<'a>> {
    let mut cols = Vec::new();
    for (name, a) in g.attribs(class).iter() {
        if class == AttribClass::Point && name == geode_geo::P {
            continue;
        }
        let ty = a.attrib_type();
        let printable = !name.is_empty() && name.chars().all(|c| c.is_ascii_graphic());
        let standard: Option<&'static [&'static str]> = match (class, name, ty) {
            (AttribClass::Point, "N", AttribType::Vec3) => Some(&["nx", "ny", "nz"]),
            (AttribClass::Point, "Cd", AttribType::Vec3) => Some(&["red", "green", "blue"]),
            (AttribClass::Point, "uv", AttribType::Vec2) => Some(&["s", "t"]),
            _ => None,
        };
        let is_array = matches!(
            ty,
            AttribType::IntArray | AttribType::FloatArray | AttribType::Vec3Array
        );
        let layout = match (class, standard) {
            _ if !printable || type_token(ty).is_none() => None,
            (AttribClass::Detail, _) => None,
            (_, Some(names)) => Some(Layout::Standard(names)),
            (AttribClass::Vertex, _) if is_array => None,
            (AttribClass::Vertex, _) => Some(Layout::List),
            _ if is_array => Some(Layout::List),
            _ => Some(Layout::Components(component_suffixes(ty))),
        };
        match layout {
            Some(layout) => cols.push(Column {
                name,
                attrib: a,
                layout,
                int: matches!(ty, AttribType::Int | AttribType::IntArray),
            }),
            None => dropped.push(describe_attrib(class, name, ty)),
        }
    }
    cols
}

/// Writes binary little-endian PLY (see the module documentation).
/// Packed primitives must be unpacked first.
pub fn write_ply(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    crate::error::refuse_packed(g, path, "PLY")?;
    let e = os_err(path);
    let mut dropped = Vec::new();
    let point_cols = columns(g, AttribClass::Point, &mut dropped);
    let vertex_cols = columns(g, AttribClass::Vertex, &mut dropped);
    let prim_cols = columns(g, AttribClass::Primitive, &mut dropped);
    columns(g, AttribClass::Detail, &mut dropped);
    for (kind, groups) in [("point", g.point_groups()), ("primitive", g.prim_groups())] {
        dropped.extend(groups.keys().map(|n| format!("{kind} group `{n}`")));
    }
    let polys = g.prims_where(|k| k == PrimKind::Polygon);
    let lines = g.prims_where(|k| k == PrimKind::Polyline);
    // One count type per element, wide enough for its longest list.
    let widest = |prims: &[usize]| {
        let corners = prims
            .iter()
            .map(|&i| g.prim_vertex_range(i).len())
            .max()
            .unwrap_or(0);
        let per = vertex_cols
            .iter()
            .filter_map(|c| c.attrib.data().as_floats().map(|(_, k)| k))
            .max()
            .unwrap_or(1);
        corners * per > 255
    };
    let (big_faces, big_lines) = (widest(&polys), widest(&lines));

    let mut head = String::from("ply\nformat binary_little_endian 1.0\n");
    head += &format!("comment written by geode {}\n", env!("CARGO_PKG_VERSION"));
    for (class, cols) in [
        (AttribClass::Point, &point_cols),
        (AttribClass::Vertex, &vertex_cols),
        (AttribClass::Primitive, &prim_cols),
    ] {
        // A vertex `uv` is PLY's usual `texcoord` list: no declaration needed.
        let standard = |c: &Column| {
            matches!(c.layout, Layout::Standard(_))
                || (class == AttribClass::Vertex
                    && c.name == "uv"
                    && c.attrib.attrib_type() == AttribType::Vec2)
        };
        for c in cols.iter().filter(|c| !standard(c)) {
            let ty = type_token(c.attrib.attrib_type()).expect("filtered to PLY types");
            head += &format!(
                "comment geode attribute {class} {} {ty} {}\n",
                c.name, c.attrib.type_info
            );
        }
    }
    head += &format!(
        "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        g.num_points()
    );
    for c in &point_cols {
        c.header(&mut head, "uint");
    }
    for (element, prims, big) in [("face", &polys, big_faces), ("polyline", &lines, big_lines)] {
        if element == "polyline" && prims.is_empty() {
            continue;
        }
        let count_type = if big { "uint" } else { "uchar" };
        head += &format!(
            "element {element} {}\nproperty list {count_type} int vertex_indices\n",
            prims.len()
        );
        for c in &vertex_cols {
            c.header(&mut head, count_type);
        }
        for c in &prim_cols {
            c.header(&mut head, "uint");
        }
    }
    head += "end_header\n";
    w.write_all(head.as_bytes()).map_err(&e)?;

    let total = (g.num_points() + g.num_prims()) as u64;
    let mut throttle = Throttle::new(progress, "writing PLY", total);
    let mut buf: Vec<u8> = Vec::with_capacity(1 << 20);
    let p = g.positions();
    let mut done = 0u64;
    let mut flush = |buf: &mut Vec<u8>, done: u64| -> Result<(), IoError> {
        if buf.len() > 1 << 20 {
            if progress.cancelled() {
                return Err(IoError::Cancelled {
                    path: path.to_owned(),
                });
            }
            w.write_all(buf).map_err(&e)?;
            buf.clear();
            throttle.tick(done);
        }
        Ok(())
    };
    for (i, point) in p.iter().enumerate() {
        buf.extend_from_slice(bytemuck::bytes_of(point));
        for c in &point_cols {
            c.put(&mut buf, i);
        }
        done += 1;
        flush(&mut buf, done)?;
    }
    for (prims, big) in [(&polys, big_faces), (&lines, big_lines)] {
        for &prim in prims.iter() {
            let pts = g.prim_points(prim);
            if big {
                buf.extend_from_slice(&(pts.len() as u32).to_le_bytes());
            } else {
                buf.push(pts.len() as u8);
            }
            buf.extend_from_slice(bytemuck::cast_slice(pts));
            for c in &vertex_cols {
                c.put_corners(&mut buf, g.prim_vertex_range(prim), big);
            }
            for c in &prim_cols {
                c.put(&mut buf, prim);
            }
            done += 1;
            flush(&mut buf, done)?;
        }
    }
    w.write_all(&buf).map_err(os_err(path))?;
    report_dropped(progress, path, "PLY", &dropped);
    throttle.finish();
    Ok(())
}
