//! PLY reader (ASCII, binary little and big endian); the writer is `ply_write.rs`.

use geode_geo::{AttribClass, AttribType, Geometry, TypeInfo};

use crate::error::{ParseError, ParseResult};
use crate::progress::{Progress, Throttle};
use crate::text::Lines;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Scalar {
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

    pub(crate) fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Debug)]
pub(crate) enum PropKind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
pub(crate) struct Property {
    pub(crate) name: String,
    pub(crate) kind: PropKind,
}

#[derive(Clone, Debug)]
pub(crate) struct Element {
    pub(crate) name: String,
    pub(crate) count: usize,
    pub(crate) props: Vec<Property>,
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// Values of one property over all elements: scalars, or flattened lists.
#[derive(Default)]
pub(crate) struct Column {
    pub(crate) values: Vec<f64>,
    pub(crate) list_counts: Vec<u32>,
}

/// `comment geode attribute CLASS NAME TYPE TYPEINFO`: an attribute geode wrote.
pub(crate) struct Declared {
    pub(crate) class: AttribClass,
    pub(crate) name: String,
    pub(crate) ty: AttribType,
    pub(crate) info: TypeInfo,
}

pub(crate) struct Header {
    encoding: Encoding,
    pub(crate) elements: Vec<Element>,
    pub(crate) declared: Vec<Declared>,
    body_offset: usize,
    body_line: u64,
}

fn parse_header(bytes: &[u8]) -> ParseResult<Header> {
    let mut lines = Lines::new(bytes);
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut declared = Vec::new();
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
            Some("comment") if t.next() == Some("geode") && t.next() == Some("attribute") => {
                let words: Vec<&str> = t.collect();
                let class = match words.first() {
                    Some(&"point") => AttribClass::Point,
                    Some(&"vertex") => AttribClass::Vertex,
                    Some(&"primitive") => AttribClass::Primitive,
                    _ => continue,
                };
                if let [_, name, ty, info] = words[..] {
                    if let Some(ty) = crate::attrib_codec::type_from_token(ty) {
                        let info = crate::attrib_codec::info_from_token(info);
                        declared.push(Declared { class, name: name.to_owned(), ty, info });
                    }
                }
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
                return Ok(Header { encoding, elements, declared, body_offset: lines.offset(), body_line: lines.line() });
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
    crate::ply_build::build(&h, data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;
    use geode_geo::glam::Vec3;

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
