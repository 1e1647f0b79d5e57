//! PLY reader (ASCII, binary little and big endian) and binary little-endian writer.

use std::io::Write;
use std::path::Path;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{AttribClass, AttribData, AttribType, Attribute, Geometry, PrimKind, TypeInfo};

use crate::atomic::os_err;
use crate::error::{IoError, ParseError, ParseResult};
use crate::progress::{Progress, Throttle};
use crate::text::Lines;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
enum PropKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: PropKind,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Values of one property over all elements: scalars, or flattened lists.
#[derive(Default)]
struct Column {
    values: Vec<f64>,
    list_counts: Vec<u32>,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    body_offset: usize,
    body_line: u64,
}

fn parse_header(bytes: &[u8]) -> ParseResult<Header> {
    let mut lines = Lines::new(bytes);
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut first = true;
    while let Some((n, _, line)) = lines.next() {
        let line = line.map_err(|m| ParseError::line(n, m))?;
        let err = |m: String| ParseError::line(n, m);
        let mut t = line.split_ascii_whitespace();
        if first {
            if line.trim() != "ply" {
                return Err(err(
                    "not a PLY file: expected `ply` on the first line".into()
                ));
            }
            first = false;
            continue;
        }
        match t.next() {
            Some("format") => {
                encoding = Some(match (t.next(), t.next()) {
                    (Some("ascii"), Some("1.0")) => Encoding::Ascii,
                    (Some("binary_little_endian"), Some("1.0")) => Encoding::Little,
                    (Some("binary_big_endian"), Some("1.0")) => Encoding::Big,
                    _ => return Err(err(format!("unsupported format line `{line}` (expected ascii, binary_little_endian or binary_big_endian 1.0)"))),
                })
            }
            Some("comment") | Some("obj_info") | None => {}
            Some("element") => {
                let name = t.next().ok_or_else(|| err("`element` needs a name and a count".into()))?;
                let count = t
                    .next()
                    .and_then(|c| c.parse::<usize>().ok())
                    .ok_or_else(|| err(format!("element `{name}` needs a non-negative count")))?;
                elements.push(Element { name: name.to_owned(), count, props: Vec::new() });
            }
            Some("property") => {
                let el = elements.last_mut().ok_or_else(|| err("`property` before any `element`".into()))?;
                let ty = t.next().ok_or_else(|| err("`property` needs a type".into()))?;
                let kind = if ty == "list" {
                    let c = t.next().and_then(Scalar::parse).ok_or_else(|| err("list needs a count type".into()))?;
                    let i = t.next().and_then(Scalar::parse).ok_or_else(|| err("list needs an item type".into()))?;
                    if c.is_float() {
                        return Err(err("a list count must be an integer type".into()));
                    }
                    PropKind::List { count: c, item: i }
                } else {
                    PropKind::Scalar(Scalar::parse(ty).ok_or_else(|| err(format!("unknown property type `{ty}`")))?)
                };
                let name = t.next().ok_or_else(|| err("`property` needs a name".into()))?;
                el.props.push(Property { name: name.to_owned(), kind });
            }
            Some("end_header") => {
                let encoding = encoding.ok_or_else(|| err("`end_header` before any `format` line".into()))?;
                return Ok(Header { encoding, elements, body_offset: lines.offset(), body_line: lines.line() });
            }
            Some(other) => return Err(err(format!("unknown header keyword `{}`", other.chars().take(32).collect::<String>()))),
        }
    }
    Err(ParseError::whole(if first {
        "empty file: expected `ply`".to_owned()
    } else {
        "header has no `end_header`".to_owned()
    }))
}

/// Reads values in the body, tracking the position for errors.
trait Source {
    fn value(&mut self, s: Scalar, what: &dyn Fn() -> String) -> ParseResult<f64>;
    fn end_element(&mut self) -> ParseResult<()>;
    /// Bytes left to read: an upper bound on the elements still to come.
    fn remaining_bytes(&self) -> usize;
}

struct BinarySource<'a> {
    bytes: &'a [u8],
    pos: usize,
    big: bool,
}

impl Source for BinarySource<'_> {
    #[inline]
    fn value(&mut self, s: Scalar, what: &dyn Fn() -> String) -> ParseResult<f64> {
        let n = s.size();
        let Some(b) = self.bytes.get(self.pos..self.pos + n) else {
            return Err(ParseError::byte(
                self.pos as u64,
                format!("file ends while reading {}", what()),
            ));
        };
        self.pos += n;
        macro_rules! num {
            ($t:ty) => {{
                let a = b.try_into().expect("sized");
                (if self.big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }};
        }
        Ok(match s {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => num!(i16),
            Scalar::U16 => num!(u16),
            Scalar::I32 => num!(i32),
            Scalar::U32 => num!(u32),
            Scalar::F32 => num!(f32),
            Scalar::F64 => num!(f64),
        })
    }

    fn end_element(&mut self) -> ParseResult<()> {
        Ok(())
    }

    fn remaining_bytes(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }
}

struct AsciiSource<'a> {
    lines: Lines<'a>,
    /// File line of the body's first line minus one.
    base: u64,
    line_no: u64,
    tokens: std::str::SplitAsciiWhitespace<'a>,
}

impl Source for AsciiSource<'_> {
    fn value(&mut self, s: Scalar, what: &dyn Fn() -> String) -> ParseResult<f64> {
        loop {
            if let Some(tok) = self.tokens.next() {
                let v: f64 = tok.parse().map_err(|_| {
                    ParseError::line(
                        self.line_no,
                        format!("expected a number for {}, found `{tok}`", what()),
                    )
                })?;
                if !s.is_float() && v.fract() != 0.0 {
                    return Err(ParseError::line(
                        self.line_no,
                        format!("expected an integer for {}, found `{tok}`", what()),
                    ));
                }
                return Ok(v);
            }
            match self.lines.next() {
                Some((n, _, l)) => {
                    self.line_no = self.base + n;
                    self.tokens = l
                        .map_err(|m| ParseError::line(n, m))?
                        .split_ascii_whitespace();
                }
                None => {
                    return Err(ParseError::line(
                        self.line_no,
                        format!("file ends while reading {}", what()),
                    ))
                }
            }
        }
    }

    fn end_element(&mut self) -> ParseResult<()> {
        // Elements are one per line: leftovers mean the header's properties are wrong.
        if let Some(tok) = self.tokens.next() {
            return Err(ParseError::line(
                self.line_no,
                format!("unexpected `{tok}` after the element's declared properties"),
            ));
        }
        Ok(())
    }

    fn remaining_bytes(&self) -> usize {
        self.lines.remaining()
    }
}

fn read_elements(
    h: &Header,
    src: &mut dyn Source,
    progress: &dyn Progress,
) -> ParseResult<Vec<Vec<Column>>> {
    let total: u64 = h.elements.iter().map(|e| e.count as u64).sum();
    let mut throttle = Throttle::new(progress, "reading PLY", total);
    let mut done = 0u64;
    let mut out = Vec::new();
    for el in &h.elements {
        let mut cols: Vec<Column> = el.props.iter().map(|_| Column::default()).collect();
        if el.props.is_empty() {
            // Nothing to read, however many elements are declared.
            out.push(cols);
            continue;
        }
        // Never reserve more than the file could hold (a declared count is untrusted).
        let plausible = el.count.min(src.remaining_bytes());
        for (c, p) in cols.iter_mut().zip(&el.props) {
            if let PropKind::Scalar(_) = p.kind {
                c.values.reserve(plausible);
            }
        }
        for i in 0..el.count {
            throttle.tick(done);
            done += 1;
            for (c, p) in cols.iter_mut().zip(&el.props) {
                let what = || format!("property `{}` of {} {} of {}", p.name, el.name, i, el.count);
                match p.kind {
                    PropKind::Scalar(s) => c.values.push(src.value(s, &what)?),
                    PropKind::List { count, item } => {
                        let n = src.value(count, &what)?;
                        if !(0.0..=1e6).contains(&n) {
                            return Err(ParseError::whole(format!(
                                "list length {n} of {} is not a sensible count",
                                what()
                            )));
                        }
                        c.list_counts.push(n as u32);
                        for _ in 0..n as usize {
                            c.values.push(src.value(item, &what)?);
                        }
                    }
                }
            }
            src.end_element()?;
        }
        out.push(cols);
    }
    throttle.finish();
    Ok(out)
}

/// Parses PLY: `vertex` (x y z, nx ny nz, red green blue [alpha], s t / u v,
/// and any other scalar as a point attribute), `face` (vertex_indices, an
/// optional `texcoord` list, other scalars as primitive attributes) and `edge`
/// (two-point polylines). Other elements are read and skipped.
pub fn read_ply(bytes: &[u8], progress: &dyn Progress) -> ParseResult<Geometry> {
    let h = parse_header(bytes)?;
    let data = match h.encoding {
        Encoding::Ascii => {
            let mut lines = Lines::new(&bytes[h.body_offset..]);
            let mut src = AsciiSource {
                lines: Lines::new(&[]),
                base: h.body_line,
                line_no: h.body_line,
                tokens: "".split_ascii_whitespace(),
            };
            std::mem::swap(&mut src.lines, &mut lines);
            let data = read_elements(&h, &mut src, progress)?;
            // The source numbers lines from the body: shift to file lines.
            for (n, _, l) in src.lines {
                if l.map(|s| !s.trim().is_empty()).unwrap_or(true) {
                    return Err(ParseError::line(
                        h.body_line + n,
                        "more data than the header declares",
                    ));
                }
            }
            data
        }
        enc => {
            let mut src = BinarySource {
                bytes,
                pos: h.body_offset,
                big: enc == Encoding::Big,
            };
            let data = read_elements(&h, &mut src, progress)?;
            if src.pos != bytes.len() {
                return Err(ParseError::byte(
                    src.pos as u64,
                    format!(
                        "{} bytes of data beyond what the header declares",
                        bytes.len() - src.pos
                    ),
                ));
            }
            data
        }
    };
    build(&h, data)
}

fn build(h: &Header, data: Vec<Vec<Column>>) -> ParseResult<Geometry> {
    let find = |el: &Element, names: &[&str]| {
        names
            .iter()
            .find_map(|n| el.props.iter().position(|p| p.name == *n))
    };
    let mut positions = Vec::new();
    let mut point_attribs: Vec<(String, Attribute)> = Vec::new();
    let mut vertex_points: Vec<u32> = Vec::new();
    let mut counts: Vec<u32> = Vec::new();
    let mut kinds: Vec<PrimKind> = Vec::new();
    let mut prim_attribs: Vec<(String, Vec<f64>, bool)> = Vec::new();
    let mut vertex_uv: Option<Vec<Vec2>> = None;
    let mut n_faces = 0usize;
    for (el, cols) in h.elements.iter().zip(&data) {
        let scalar = |i: usize| &cols[i].values;
        match el.name.as_str() {
            "vertex" => {
                let (Some(x), Some(y), Some(z)) =
                    (find(el, &["x"]), find(el, &["y"]), find(el, &["z"]))
                else {
                    return Err(ParseError::whole("element `vertex` lacks x, y or z"));
                };
                positions = (0..el.count)
                    .map(|i| {
                        Vec3::new(
                            scalar(x)[i] as f32,
                            scalar(y)[i] as f32,
                            scalar(z)[i] as f32,
                        )
                    })
                    .collect();
                let mut used = vec![x, y, z];
                let vec3 = |names: [&str; 3]| -> Option<[usize; 3]> {
                    Some([
                        find(el, &[names[0]])?,
                        find(el, &[names[1]])?,
                        find(el, &[names[2]])?,
                    ])
                };
                if let Some(n) = vec3(["nx", "ny", "nz"]) {
                    used.extend(n);
                    let v = (0..el.count)
                        .map(|i| {
                            Vec3::new(
                                scalar(n[0])[i] as f32,
                                scalar(n[1])[i] as f32,
                                scalar(n[2])[i] as f32,
                            )
                        })
                        .collect();
                    point_attribs.push((
                        "N".into(),
                        Attribute::from_data(AttribData::Vec3(v), TypeInfo::Normal),
                    ));
                }
                if let Some(c) = vec3(["red", "green", "blue"]) {
                    used.extend(c);
                    let scale = |k: usize| match el.props[c[k]].kind {
                        PropKind::Scalar(Scalar::U8) => 1.0 / 255.0,
                        PropKind::Scalar(Scalar::U16) => 1.0 / 65535.0,
                        _ => 1.0,
                    };
                    let s = [scale(0), scale(1), scale(2)];
                    let v = (0..el.count)
                        .map(|i| {
                            Vec3::new(
                                (scalar(c[0])[i] * s[0]) as f32,
                                (scalar(c[1])[i] * s[1]) as f32,
                                (scalar(c[2])[i] * s[2]) as f32,
                            )
                        })
                        .collect();
                    point_attribs.push((
                        "Cd".into(),
                        Attribute::from_data(AttribData::Vec3(v), TypeInfo::Color),
                    ));
                }
                for (un, vn) in [("s", "t"), ("u", "v"), ("texture_u", "texture_v")] {
                    if let (Some(u), Some(v)) = (find(el, &[un]), find(el, &[vn])) {
                        used.extend([u, v]);
                        let uv = (0..el.count)
                            .map(|i| Vec2::new(scalar(u)[i] as f32, scalar(v)[i] as f32))
                            .collect();
                        point_attribs.push((
                            "uv".into(),
                            Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
                        ));
                        break;
                    }
                }
                for (i, p) in el.props.iter().enumerate() {
                    if used.contains(&i) {
                        continue;
                    }
                    if let PropKind::Scalar(s) = p.kind {
                        let data = if s.is_float() {
                            AttribData::Float(cols[i].values.iter().map(|&v| v as f32).collect())
                        } else {
                            AttribData::Int(cols[i].values.iter().map(|&v| v as i32).collect())
                        };
                        point_attribs
                            .push((p.name.clone(), Attribute::from_data(data, TypeInfo::None)));
                    }
                }
            }
            "face" => {
                let Some(vi) = find(el, &["vertex_indices", "vertex_index"]) else {
                    return Err(ParseError::whole(
                        "element `face` lacks a vertex_indices list",
                    ));
                };
                let c = &cols[vi];
                if c.list_counts.is_empty() && el.count > 0 {
                    return Err(ParseError::whole(
                        "face property vertex_indices must be a list",
                    ));
                }
                let mut k = 0;
                for (f, &n) in c.list_counts.iter().enumerate() {
                    if n < 3 {
                        return Err(ParseError::whole(format!(
                            "face {f} has {n} vertices, at least 3 needed"
                        )));
                    }
                    for &v in &c.values[k..k + n as usize] {
                        if v < 0.0 || v as usize >= positions.len() {
                            return Err(ParseError::whole(format!(
                                "face {f} refers to vertex {v} but there are {} vertices",
                                positions.len()
                            )));
                        }
                        vertex_points.push(v as u32);
                    }
                    k += n as usize;
                    counts.push(n);
                    kinds.push(PrimKind::Polygon);
                }
                n_faces = el.count;
                if let Some(ti) = find(el, &["texcoord"]) {
                    let t = &cols[ti];
                    if t.list_counts
                        .iter()
                        .zip(&c.list_counts)
                        .all(|(a, b)| *a == 2 * *b)
                    {
                        vertex_uv = Some(
                            t.values
                                .chunks(2)
                                .map(|p| Vec2::new(p[0] as f32, p[1] as f32))
                                .collect(),
                        );
                    }
                }
                for (i, p) in el.props.iter().enumerate() {
                    if let PropKind::Scalar(s) = p.kind {
                        prim_attribs.push((p.name.clone(), cols[i].values.clone(), s.is_float()));
                    }
                }
            }
            "edge" => {
                if let (Some(a), Some(b)) = (find(el, &["vertex1"]), find(el, &["vertex2"])) {
                    for i in 0..el.count {
                        for v in [cols[a].values[i], cols[b].values[i]] {
                            if v < 0.0 || v as usize >= positions.len() {
                                return Err(ParseError::whole(format!(
                                    "edge {i} refers to vertex {v} but there are {} vertices",
                                    positions.len()
                                )));
                            }
                            vertex_points.push(v as u32);
                        }
                        counts.push(2);
                        kinds.push(PrimKind::Polyline);
                    }
                }
            }
            _ => {}
        }
    }
    let n_vertices = vertex_points.len();
    let mut g = Geometry::from_prims(positions, vertex_points, &counts, kinds)
        .map_err(|e| ParseError::whole(e.to_string()))?;
    for (name, a) in point_attribs {
        g.set_attrib(AttribClass::Point, &name, a)
            .map_err(|e| ParseError::whole(e.to_string()))?;
    }
    let n_prims = g.num_prims();
    for (name, mut vals, float) in prim_attribs {
        vals.resize(n_prims, 0.0);
        let data = if float {
            AttribData::Float(vals.iter().map(|&v| v as f32).collect())
        } else {
            AttribData::Int(vals.iter().map(|&v| v as i32).collect())
        };
        g.set_attrib(
            AttribClass::Primitive,
            &name,
            Attribute::from_data(data, TypeInfo::None),
        )
        .map_err(|e| ParseError::whole(e.to_string()))?;
    }
    if let Some(mut uv) = vertex_uv {
        uv.resize(n_vertices, Vec2::ZERO);
        debug_assert!(n_faces <= n_prims);
        g.set_attrib(
            AttribClass::Vertex,
            "uv",
            Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
        )
        .map_err(|e| ParseError::whole(e.to_string()))?;
    }
    Ok(g)
}

/// Writes binary little-endian PLY: positions, point `N`, `Cd` (as float
/// red/green/blue), point `uv` (as s/t) and every other scalar float or int
/// point attribute; faces with their scalar primitive attributes; polylines as
/// `edge` elements (one per segment). Packed primitives must be unpacked first.
pub fn write_ply(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    crate::error::refuse_packed(g, path, "PLY")?;
    let e = os_err(path);
    let pts = g.attribs(AttribClass::Point);
    let vec3 = |n: &str| pts.get(n).and_then(|a| a.as_vec3());
    let normals = vec3("N");
    let colors = vec3("Cd");
    let uvs = pts.get("uv").and_then(|a| a.as_vec2());
    let scalars: Vec<(&str, &Attribute)> = pts
        .iter()
        .filter(|(n, a)| {
            !["P", "N", "Cd", "uv"].contains(n)
                && matches!(a.attrib_type(), AttribType::Float | AttribType::Int)
        })
        .filter(|(n, _)| n.chars().all(|c| c.is_ascii_graphic()))
        .collect();
    let prim_scalars: Vec<(&str, &Attribute)> = g
        .attribs(AttribClass::Primitive)
        .iter()
        .filter(|(n, a)| {
            matches!(a.attrib_type(), AttribType::Float | AttribType::Int)
                && n.chars().all(|c| c.is_ascii_graphic())
        })
        .collect();
    let polys: Vec<usize> = g.prims_where(|k| k == PrimKind::Polygon);
    let segments: Vec<[u32; 2]> = (0..g.num_prims())
        .filter(|&i| g.prim_kind(i) == PrimKind::Polyline)
        .flat_map(|i| {
            g.prim_points(i)
                .windows(2)
                .map(|w| [w[0], w[1]])
                .collect::<Vec<_>>()
        })
        .collect();
    let big_faces = polys.iter().any(|&i| g.prim_vertex_range(i).len() > 255);
    let mut head = String::from("ply\nformat binary_little_endian 1.0\n");
    head += &format!(
        "comment written by geode {}\nelement vertex {}\n",
        env!("CARGO_PKG_VERSION"),
        g.num_points()
    );
    head += "property float x\nproperty float y\nproperty float z\n";
    if normals.is_some() {
        head += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if colors.is_some() {
        head += "property float red\nproperty float green\nproperty float blue\n";
    }
    if uvs.is_some() {
        head += "property float s\nproperty float t\n";
    }
    let ty = |a: &Attribute| {
        if a.attrib_type() == AttribType::Float {
            "float"
        } else {
            "int"
        }
    };
    for (n, a) in &scalars {
        head += &format!("property {} {n}\n", ty(a));
    }
    head += &format!(
        "element face {}\nproperty list {} int vertex_indices\n",
        polys.len(),
        if big_faces { "uint" } else { "uchar" }
    );
    for (n, a) in &prim_scalars {
        head += &format!("property {} {n}\n", ty(a));
    }
    if !segments.is_empty() {
        head += &format!(
            "element edge {}\nproperty int vertex1\nproperty int vertex2\n",
            segments.len()
        );
    }
    head += "end_header\n";
    w.write_all(head.as_bytes()).map_err(&e)?;
    let mut throttle = Throttle::new(
        progress,
        "writing PLY",
        (g.num_points() + polys.len()) as u64,
    );
    let mut buf: Vec<u8> = Vec::with_capacity(1 << 20);
    let put_scalar = |buf: &mut Vec<u8>, a: &Attribute, i: usize| match a.data() {
        AttribData::Float(v) => buf.extend_from_slice(&v[i].to_le_bytes()),
        AttribData::Int(v) => buf.extend_from_slice(&v[i].to_le_bytes()),
        _ => unreachable!("filtered to scalars"),
    };
    let p = g.positions();
    for i in 0..g.num_points() {
        buf.extend_from_slice(bytemuck::bytes_of(&p[i]));
        if let Some(n) = normals {
            buf.extend_from_slice(bytemuck::bytes_of(&n[i]));
        }
        if let Some(c) = colors {
            buf.extend_from_slice(bytemuck::bytes_of(&c[i]));
        }
        if let Some(t) = uvs {
            buf.extend_from_slice(bytemuck::bytes_of(&t[i]));
        }
        for (_, a) in &scalars {
            put_scalar(&mut buf, a, i);
        }
        if buf.len() > 1 << 20 {
            w.write_all(&buf).map_err(&e)?;
            buf.clear();
            throttle.tick(i as u64);
        }
    }
    for (k, &prim) in polys.iter().enumerate() {
        let pts = g.prim_points(prim);
        if big_faces {
            buf.extend_from_slice(&(pts.len() as u32).to_le_bytes());
        } else {
            buf.push(pts.len() as u8);
        }
        buf.extend_from_slice(bytemuck::cast_slice(pts));
        for (_, a) in &prim_scalars {
            put_scalar(&mut buf, a, prim);
        }
        if buf.len() > 1 << 20 {
            w.write_all(&buf).map_err(&e)?;
            buf.clear();
            throttle.tick((g.num_points() + k) as u64);
        }
    }
    for s in &segments {
        buf.extend_from_slice(bytemuck::cast_slice(s));
    }
    w.write_all(&buf).map_err(&e)?;
    throttle.finish();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
        property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float quality\n\
        element face 1\nproperty list uchar int vertex_indices\nproperty int flag\nend_header\n\
        0 0 0 255 0 0 1.5\n1 0 0 0 255 0 2\n1 1 0 0 0 255 3\n0 1 0 0 0 0 4\n4 0 1 2 3 7\n";

    #[test]
    fn ascii_with_colours_and_extra_properties() {
        let g = read_ply(ASCII.as_bytes(), &NoProgress).unwrap();
        assert_eq!((g.num_points(), g.num_prims()), (4, 1));
        assert_eq!(
            g.attrib(AttribClass::Point, "Cd")
                .unwrap()
                .as_vec3()
                .unwrap()[1],
            Vec3::Y
        );
        assert_eq!(
            g.attrib(AttribClass::Point, "quality")
                .unwrap()
                .as_f32()
                .unwrap(),
            &[1.5, 2.0, 3.0, 4.0]
        );
        assert_eq!(
            g.attrib(AttribClass::Primitive, "flag")
                .unwrap()
                .as_i32()
                .unwrap(),
            &[7]
        );
    }

    #[test]
    fn wrong_counts_are_errors_with_positions() {
        let short = ASCII.replace("element vertex 4", "element vertex 5");
        let e = read_ply(short.as_bytes(), &NoProgress).unwrap_err();
        assert_eq!(e.pos, Some(crate::Position::Line(20)));
        assert_eq!(
            e.message,
            "file ends while reading property `quality` of vertex 4 of 5"
        );
        let long = ASCII.replace("element vertex 4", "element vertex 3");
        let e = read_ply(long.as_bytes(), &NoProgress).unwrap_err();
        assert!(
            e.message
                .contains("after the element's declared properties")
                || e.message.contains("more data"),
            "{}",
            e.message
        );
        let bad_index = ASCII.replace("4 0 1 2 3 7", "4 0 1 2 9 7");
        let e = read_ply(bad_index.as_bytes(), &NoProgress).unwrap_err();
        assert_eq!(
            e.message,
            "face 0 refers to vertex 9 but there are 4 vertices"
        );
    }
}
