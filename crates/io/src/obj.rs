//! Wavefront OBJ reader and writer, including OpenSubdiv's `t` tag lines (creases, corners, boundary, holes).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{
    AttribClass, AttribData, AttribValue, Attribute, Geometry, Group, PrimKind, StringColumn,
    TypeInfo,
};

use crate::atomic::os_err;
use crate::error::{IoError, ParseError, ParseResult};
use crate::progress::{Progress, Throttle};
use crate::text::{parse_f32, parse_i64, Lines};

/// Vertex attribute holding edge crease sharpness (on the vertex that starts the edge).
pub const CREASE: &str = "creaseweight";
/// Point attribute holding corner sharpness.
pub const CORNER: &str = "cornerweight";
/// Primitive attribute flagging holes (1).
pub const HOLE: &str = "subd_hole";
/// Detail attribute: boundary interpolation (0 none, 1 edge and corner, 2 edge only).
pub const BOUNDARY: &str = "subd_boundary";
/// Detail attribute: face-varying boundary interpolation.
pub const FVAR_BOUNDARY: &str = "subd_fvar_boundary";
/// Detail attribute: crease method (`normal` or `chaikin`).
pub const CREASE_METHOD: &str = "subd_creasemethod";
/// Detail attribute: triangle subdivision rule (`catmark` or `smooth`).
pub const TRIANGLE_RULE: &str = "subd_smoothtriangles";
/// Detail attribute: tag lines geode keeps verbatim but does not interpret
/// (OpenSubdiv's legacy hierarchical edits), one per line.
pub const RAW_TAGS: &str = "obj_tags";

const NO_INDEX: u32 = u32::MAX;

/// Statements of the OBJ specification that carry nothing geode uses.
const IGNORED: &[&str] = &[
    "s",
    "mtllib",
    "vp",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "mg",
    "lod",
    "ctech",
    "stech",
    "bevel",
    "c_interp",
    "d_interp",
    "maplib",
    "usemap",
    "shadow_obj",
    "trace_obj",
    "call",
    "csh",
    "p",
];

struct Tag {
    line: u64,
    name: String,
    ints: Vec<i64>,
    floats: Vec<f32>,
    strings: Vec<String>,
    raw: String,
}

#[derive(Default)]
struct ObjData {
    positions: Vec<Vec3>,
    colors: Vec<Vec3>,
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    vertex_points: Vec<u32>,
    vertex_uv: Option<Vec<u32>>,
    vertex_n: Option<Vec<u32>>,
    counts: Vec<u32>,
    kinds: Vec<PrimKind>,
    /// Index into `group_sets` per primitive.
    prim_group_set: Vec<u32>,
    group_sets: Vec<Vec<String>>,
    prim_material: Vec<u32>,
    materials: Vec<String>,
    tags: Vec<Tag>,
}

fn resolve(index: i64, count: usize, what: &str, line: u64) -> ParseResult<u32> {
    let resolved = if index > 0 {
        index - 1
    } else if index < 0 {
        count as i64 + index
    } else {
        return Err(ParseError::line(
            line,
            format!("{what} index 0 is invalid (OBJ indices start at 1)"),
        ));
    };
    if resolved < 0 || resolved as usize >= count {
        return Err(ParseError::line(
            line,
            format!("{what} index {index} out of range ({count} {what}s defined so far)"),
        ));
    }
    Ok(resolved as u32)
}

fn floats<'a>(
    toks: impl Iterator<Item = &'a str>,
    line: u64,
    min: usize,
    max: usize,
    what: &str,
) -> ParseResult<([f32; 7], usize)> {
    let mut out = [0.0f32; 7];
    let mut n = 0;
    for t in toks {
        if n == max {
            return Err(ParseError::line(
                line,
                format!("too many numbers for {what} (at most {max})"),
            ));
        }
        out[n] = parse_f32(t).ok_or_else(|| {
            ParseError::line(line, format!("expected a number in {what}, found `{t}`"))
        })?;
        n += 1;
    }
    if n < min {
        return Err(ParseError::line(
            line,
            format!("{what} needs {min} numbers, found {n}"),
        ));
    }
    Ok((out, n))
}

fn parse(bytes: &[u8], progress: &dyn Progress) -> ParseResult<ObjData> {
    let mut d = ObjData {
        group_sets: vec![Vec::new()],
        materials: vec![String::new()],
        ..Default::default()
    };
    let mut current_set = 0u32;
    let mut current_material = 0u32;
    let mut throttle = Throttle::new(progress, "reading OBJ", bytes.len() as u64);
    let mut corner_buf: Vec<(u32, u32, u32)> = Vec::new();
    for (line_no, offset, line) in Lines::new(bytes) {
        throttle.tick(offset as u64);
        let line = line.map_err(|m| ParseError::line(line_no, m))?;
        let line = match line.find('#') {
            Some(i) => &line[..i],
            None => line,
        };
        let mut toks = line.split_ascii_whitespace();
        let Some(keyword) = toks.next() else { continue };
        match keyword {
            "v" => {
                let (v, n) = floats(toks, line_no, 3, 7, "vertex `v`")?;
                d.positions.push(Vec3::new(v[0], v[1], v[2]));
                if n == 6 || n == 7 {
                    // `v x y z r g b` (the common vertex colour extension).
                    d.colors.resize(d.positions.len() - 1, Vec3::ONE);
                    d.colors.push(Vec3::new(v[3], v[4], v[5]));
                }
            }
            "vt" => {
                let (v, _) = floats(toks, line_no, 1, 3, "texture coordinate `vt`")?;
                d.texcoords.push(Vec2::new(v[0], v[1]));
            }
            "vn" => {
                let (v, _) = floats(toks, line_no, 3, 3, "normal `vn`")?;
                d.normals.push(Vec3::new(v[0], v[1], v[2]));
            }
            "f" | "l" => {
                corner_buf.clear();
                for t in toks {
                    let mut parts = t.split('/');
                    let p = parts.next().unwrap_or("");
                    let idx = parse_i64(p).ok_or_else(|| {
                        ParseError::line(line_no, format!("expected a vertex index, found `{t}`"))
                    })?;
                    let p = resolve(idx, d.positions.len(), "vertex", line_no)?;
                    let uv = match parts.next() {
                        Some("") | None => NO_INDEX,
                        Some(s) => {
                            let i = parse_i64(s).ok_or_else(|| {
                                ParseError::line(
                                    line_no,
                                    format!("expected a texture index, found `{s}`"),
                                )
                            })?;
                            resolve(i, d.texcoords.len(), "texture coordinate", line_no)?
                        }
                    };
                    let n = match parts.next() {
                        Some("") | None => NO_INDEX,
                        Some(s) => {
                            let i = parse_i64(s).ok_or_else(|| {
                                ParseError::line(
                                    line_no,
                                    format!("expected a normal index, found `{s}`"),
                                )
                            })?;
                            resolve(i, d.normals.len(), "normal", line_no)?
                        }
                    };
                    corner_buf.push((p, uv, n));
                }
                let (kind, min) = if keyword == "f" {
                    (PrimKind::Polygon, 3)
                } else {
                    (PrimKind::Polyline, 2)
                };
                if corner_buf.len() < min {
                    return Err(ParseError::line(
                        line_no,
                        format!(
                            "`{keyword}` needs at least {min} vertices, found {}",
                            corner_buf.len()
                        ),
                    ));
                }
                let any_uv = corner_buf.iter().any(|c| c.1 != NO_INDEX);
                let any_n = corner_buf.iter().any(|c| c.2 != NO_INDEX);
                let so_far = d.vertex_points.len();
                if any_uv && d.vertex_uv.is_none() {
                    d.vertex_uv = Some(vec![NO_INDEX; so_far]);
                }
                if any_n && d.vertex_n.is_none() {
                    d.vertex_n = Some(vec![NO_INDEX; so_far]);
                }
                for &(p, uv, n) in &corner_buf {
                    d.vertex_points.push(p);
                    if let Some(v) = d.vertex_uv.as_mut() {
                        v.push(uv);
                    }
                    if let Some(v) = d.vertex_n.as_mut() {
                        v.push(n);
                    }
                }
                d.counts.push(corner_buf.len() as u32);
                d.kinds.push(kind);
                d.prim_group_set.push(current_set);
                d.prim_material.push(current_material);
            }
            "g" | "o" => {
                let names: Vec<String> = toks.map(str::to_owned).collect();
                current_set = match d.group_sets.iter().position(|s| *s == names) {
                    Some(i) => i as u32,
                    None => {
                        d.group_sets.push(names);
                        (d.group_sets.len() - 1) as u32
                    }
                };
            }
            "usemtl" => {
                let name = toks.collect::<Vec<_>>().join(" ");
                current_material = match d.materials.iter().position(|m| *m == name) {
                    Some(i) => i as u32,
                    None => {
                        d.materials.push(name);
                        (d.materials.len() - 1) as u32
                    }
                };
            }
            "t" => d.tags.push(parse_tag(line, line_no, toks)?),
            k if IGNORED.contains(&k) => {}
            other => {
                return Err(ParseError::line(
                    line_no,
                    format!(
                        "unknown OBJ statement `{}`",
                        other.chars().take(32).collect::<String>()
                    ),
                ))
            }
        }
    }
    throttle.finish();
    Ok(d)
}

fn parse_tag<'a>(
    raw: &str,
    line: u64,
    mut toks: impl Iterator<Item = &'a str>,
) -> ParseResult<Tag> {
    let name = toks
        .next()
        .ok_or_else(|| ParseError::line(line, "tag `t` needs a name"))?
        .to_owned();
    let counts = toks.next().ok_or_else(|| {
        ParseError::line(
            line,
            format!("tag `{name}` needs its argument counts `i/f/s`"),
        )
    })?;
    let c: Vec<usize> = counts
        .split('/')
        .map(|x| x.parse().unwrap_or(usize::MAX))
        .collect();
    if c.len() != 3 || c.iter().any(|&x| x > 1 << 20) {
        return Err(ParseError::line(
            line,
            format!("tag `{name}`: expected counts `ints/floats/strings`, found `{counts}`"),
        ));
    }
    let mut tag = Tag {
        line,
        name,
        ints: Vec::new(),
        floats: Vec::new(),
        strings: Vec::new(),
        raw: raw.trim().to_owned(),
    };
    for _ in 0..c[0] {
        let t = toks.next().ok_or_else(|| {
            ParseError::line(
                line,
                format!("tag `{}` expected {} integers", tag.name, c[0]),
            )
        })?;
        tag.ints.push(parse_i64(t).ok_or_else(|| {
            ParseError::line(
                line,
                format!("tag `{}`: expected an integer, found `{t}`", tag.name),
            )
        })?);
    }
    for _ in 0..c[1] {
        let t = toks.next().ok_or_else(|| {
            ParseError::line(
                line,
                format!("tag `{}` expected {} numbers", tag.name, c[1]),
            )
        })?;
        tag.floats.push(parse_f32(t).ok_or_else(|| {
            ParseError::line(
                line,
                format!("tag `{}`: expected a number, found `{t}`", tag.name),
            )
        })?);
    }
    for _ in 0..c[2] {
        let t = toks.next().ok_or_else(|| {
            ParseError::line(
                line,
                format!("tag `{}` expected {} strings", tag.name, c[2]),
            )
        })?;
        tag.strings.push(t.to_owned());
    }
    if let Some(extra) = toks.next() {
        return Err(ParseError::line(
            line,
            format!(
                "tag `{}`: unexpected `{extra}` after its {counts} arguments",
                tag.name
            ),
        ));
    }
    Ok(tag)
}

fn build(d: ObjData) -> ParseResult<Geometry> {
    let n_vertices = d.vertex_points.len();
    let mut g = Geometry::from_prims(d.positions, d.vertex_points, &d.counts, d.kinds)
        .map_err(|e| ParseError::whole(e.to_string()))?;
    let set = |g: &mut Geometry, class, name: &str, a: Attribute| {
        g.set_attrib(class, name, a)
            .expect("lengths match the element counts");
    };
    if !d.colors.is_empty() {
        let mut c = d.colors;
        c.resize(g.num_points(), Vec3::ONE);
        set(
            &mut g,
            AttribClass::Point,
            "Cd",
            Attribute::from_data(AttribData::Vec3(c), TypeInfo::Color),
        );
    }
    if let Some(mut idx) = d.vertex_uv {
        idx.resize(n_vertices, NO_INDEX);
        let uv = idx
            .iter()
            .map(|&i| {
                if i == NO_INDEX {
                    Vec2::ZERO
                } else {
                    d.texcoords[i as usize]
                }
            })
            .collect();
        set(
            &mut g,
            AttribClass::Vertex,
            "uv",
            Attribute::from_data(AttribData::Vec2(uv), TypeInfo::TexCoord),
        );
    }
    if let Some(mut idx) = d.vertex_n {
        idx.resize(n_vertices, NO_INDEX);
        let n = idx
            .iter()
            .map(|&i| {
                if i == NO_INDEX {
                    Vec3::ZERO
                } else {
                    d.normals[i as usize]
                }
            })
            .collect();
        set(
            &mut g,
            AttribClass::Vertex,
            "N",
            Attribute::from_data(AttribData::Vec3(n), TypeInfo::Normal),
        );
    }
    // Groups: one primitive group per name used.
    let mut groups: BTreeMap<&str, Group> = BTreeMap::new();
    for (prim, &s) in d.prim_group_set.iter().enumerate() {
        for name in &d.group_sets[s as usize] {
            groups
                .entry(name)
                .or_insert_with(|| Group::new(g.num_prims()))
                .set(prim, true);
        }
    }
    for (name, grp) in groups {
        g.set_prim_group(name, grp).expect("length matches");
    }
    if d.materials.len() > 1 {
        let col = StringColumn {
            table: d.materials,
            indices: d.prim_material,
        };
        set(
            &mut g,
            AttribClass::Primitive,
            "material",
            Attribute::from_data(AttribData::String(col), TypeInfo::None),
        );
    }
    apply_tags(&mut g, &d.tags)?;
    Ok(g)
}

fn apply_tags(g: &mut Geometry, tags: &[Tag]) -> ParseResult<()> {
    if tags.is_empty() {
        return Ok(());
    }
    let np = g.num_points();
    let point = |i: i64, line: u64| -> ParseResult<u32> {
        if i < 0 || i as usize >= np {
            return Err(ParseError::line(
                line,
                format!("tag refers to vertex {i} but there are {np} vertices (0-based)"),
            ));
        }
        Ok(i as u32)
    };
    let mut creases: Option<Vec<f32>> = None;
    let mut corners: Option<Vec<f32>> = None;
    let mut holes: Option<Vec<i32>> = None;
    let mut raw = Vec::new();
    let topo = g.topology();
    for t in tags {
        let line = t.line;
        let need = |ok: bool, what: &str| -> ParseResult<()> {
            if ok {
                Ok(())
            } else {
                Err(ParseError::line(
                    line,
                    format!("tag `{}` expects {what}", t.name),
                ))
            }
        };
        match t.name.as_str() {
            "crease" => {
                need(
                    t.ints.len() >= 2
                        && (t.floats.len() == 1 || t.floats.len() == t.ints.len() - 1),
                    "a chain of at least 2 vertices and 1 sharpness (or one per edge)",
                )?;
                let c = creases.get_or_insert_with(|| vec![0.0; g.num_vertices()]);
                for k in 0..t.ints.len() - 1 {
                    let (a, b) = (point(t.ints[k], line)?, point(t.ints[k + 1], line)?);
                    let s = if t.floats.len() == 1 {
                        t.floats[0]
                    } else {
                        t.floats[k]
                    };
                    let e = topo.find_edge(a, b).ok_or_else(|| {
                        ParseError::line(
                            line,
                            format!("crease edge {a}-{b} is not an edge of any face"),
                        )
                    })?;
                    for h in topo.edge_half_edges(e) {
                        c[h.0 as usize] = s;
                    }
                }
            }
            "corner" => {
                need(
                    !t.ints.is_empty() && (t.floats.len() == 1 || t.floats.len() == t.ints.len()),
                    "vertices and 1 sharpness (or one per vertex)",
                )?;
                let c = corners.get_or_insert_with(|| vec![0.0; np]);
                for (k, &i) in t.ints.iter().enumerate() {
                    c[point(i, line)? as usize] = if t.floats.len() == 1 {
                        t.floats[0]
                    } else {
                        t.floats[k]
                    };
                }
            }
            "hole" => {
                let h = holes.get_or_insert_with(|| vec![0; g.num_prims()]);
                for &f in &t.ints {
                    if f < 0 || f as usize >= h.len() {
                        return Err(ParseError::line(
                            line,
                            format!(
                                "hole refers to face {f} but there are {} faces (0-based)",
                                h.len()
                            ),
                        ));
                    }
                    h[f as usize] = 1;
                }
            }
            "interpolateboundary" | "facevaryinginterpolateboundary" => {
                need(t.ints.len() == 1, "one integer")?;
                let name = if t.name == "interpolateboundary" {
                    BOUNDARY
                } else {
                    FVAR_BOUNDARY
                };
                g.set_attrib(
                    AttribClass::Detail,
                    name,
                    Attribute::new(AttribValue::Int(t.ints[0] as i32), TypeInfo::None, 1),
                )
                .expect("detail");
            }
            "creasemethod" | "smoothtriangles" => {
                need(t.strings.len() == 1, "one string")?;
                let name = if t.name == "creasemethod" {
                    CREASE_METHOD
                } else {
                    TRIANGLE_RULE
                };
                g.set_attrib(
                    AttribClass::Detail,
                    name,
                    Attribute::new(AttribValue::String(t.strings[0].clone()), TypeInfo::None, 1),
                )
                .expect("detail");
            }
            _ => raw.push(t.raw.as_str()),
        }
    }
    if let Some(c) = creases {
        g.set_attrib(
            AttribClass::Vertex,
            CREASE,
            Attribute::from_data(AttribData::Float(c), TypeInfo::None),
        )
        .expect("len");
    }
    if let Some(c) = corners {
        g.set_attrib(
            AttribClass::Point,
            CORNER,
            Attribute::from_data(AttribData::Float(c), TypeInfo::None),
        )
        .expect("len");
    }
    if let Some(h) = holes {
        g.set_attrib(
            AttribClass::Primitive,
            HOLE,
            Attribute::from_data(AttribData::Int(h), TypeInfo::None),
        )
        .expect("len");
    }
    if !raw.is_empty() {
        g.set_attrib(
            AttribClass::Detail,
            RAW_TAGS,
            Attribute::new(AttribValue::String(raw.join("\n")), TypeInfo::None, 1),
        )
        .expect("detail");
    }
    Ok(())
}

/// Parses OBJ text.
pub fn read_obj(bytes: &[u8], progress: &dyn Progress) -> ParseResult<Geometry> {
    build(parse(bytes, progress)?)
}

/// Writes OBJ text: `v` (with colours from point `Cd`), `vt`/`vn` from vertex
/// or point `uv`/`N`, `f` and `l`, groups as `g`, materials as `usemtl`, and
/// subdivision tags as `t` lines. Packed primitives must be unpacked first.
pub fn write_obj(
    g: &Geometry,
    w: &mut dyn Write,
    path: &Path,
    progress: &dyn Progress,
) -> Result<(), IoError> {
    let e = os_err(path);
    let mut throttle = Throttle::new(progress, "writing OBJ", g.num_prims() as u64);
    writeln!(w, "# written by geode {}", env!("CARGO_PKG_VERSION")).map_err(&e)?;
    let cd = g.attrib(AttribClass::Point, "Cd").and_then(|a| a.as_vec3());
    let mut buf = String::with_capacity(1 << 16);
    use std::fmt::Write as _;
    for (i, p) in g.positions().iter().enumerate() {
        match cd {
            Some(c) => {
                let c = c[i];
                let _ = writeln!(buf, "v {} {} {} {} {} {}", p.x, p.y, p.z, c.x, c.y, c.z);
            }
            None => {
                let _ = writeln!(buf, "v {} {} {}", p.x, p.y, p.z);
            }
        }
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    // Per-vertex indices into the vt/vn lists (point attributes are written per point).
    let uv_of = |class: AttribClass| g.attrib(class, "uv").and_then(|a| a.as_vec2());
    let (uv, uv_by_point) = match (uv_of(AttribClass::Vertex), uv_of(AttribClass::Point)) {
        (Some(v), _) => (Some(v), false),
        (None, Some(p)) => (Some(p), true),
        _ => (None, false),
    };
    let n_of = |class: AttribClass| g.attrib(class, "N").and_then(|a| a.as_vec3());
    let (nrm, n_by_point) = match (n_of(AttribClass::Vertex), n_of(AttribClass::Point)) {
        (Some(v), _) => (Some(v), false),
        (None, Some(p)) => (Some(p), true),
        _ => (None, false),
    };
    for t in uv.iter().flat_map(|v| v.iter()) {
        let _ = writeln!(buf, "vt {} {}", t.x, t.y);
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    for n in nrm.iter().flat_map(|v| v.iter()) {
        let _ = writeln!(buf, "vn {} {} {}", n.x, n.y, n.z);
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    let material = g
        .attrib(AttribClass::Primitive, "material")
        .and_then(|a| a.as_strings());
    let groups: Vec<(&String, &Group)> = g.prim_groups().iter().collect();
    let mut last_groups: Option<Vec<&str>> = None;
    let mut last_material: Option<&str> = None;
    let vp = g.vertex_points();
    for prim in 0..g.num_prims() {
        throttle.tick(prim as u64);
        let kw = match g.prim_kind(prim) {
            PrimKind::Polygon => "f",
            PrimKind::Polyline => "l",
            PrimKind::Packed(_) => {
                return Err(IoError::Unsupported {
                    path: path.to_owned(),
                    message: "OBJ cannot hold packed primitives; unpack them first".into(),
                })
            }
        };
        if !groups.is_empty() {
            let mine: Vec<&str> = groups
                .iter()
                .filter(|(_, grp)| grp.contains(prim))
                .map(|(n, _)| n.as_str())
                .collect();
            if last_groups.as_ref() != Some(&mine) {
                let _ = writeln!(buf, "g {}", mine.join(" ")).map(|_| ());
                last_groups = Some(mine);
            }
        }
        if let Some(m) = material {
            let name = m.get(prim);
            if last_material != Some(name) {
                let _ = writeln!(buf, "usemtl {name}");
                last_material = Some(name);
            }
        }
        buf.push_str(kw);
        for v in g.prim_vertex_range(prim) {
            let p = vp[v] + 1;
            let t = uv.map(|_| if uv_by_point { p } else { v as u32 + 1 });
            let n = nrm.map(|_| if n_by_point { p } else { v as u32 + 1 });
            let _ = match (t, n) {
                (None, None) => write!(buf, " {p}"),
                (Some(t), None) => write!(buf, " {p}/{t}"),
                (None, Some(n)) => write!(buf, " {p}//{n}"),
                (Some(t), Some(n)) => write!(buf, " {p}/{t}/{n}"),
            };
        }
        buf.push('\n');
        if buf.len() > 1 << 16 {
            w.write_all(buf.as_bytes()).map_err(&e)?;
            buf.clear();
        }
    }
    write_tags(g, &mut buf);
    w.write_all(buf.as_bytes()).map_err(&e)?;
    throttle.finish();
    Ok(())
}

fn write_tags(g: &Geometry, buf: &mut String) {
    use std::fmt::Write as _;
    if let Some(c) = g
        .attrib(AttribClass::Vertex, CREASE)
        .and_then(|a| a.as_f32())
    {
        let topo = g.topology();
        for (e, &[a, b]) in topo.edges().iter().enumerate() {
            let s = topo
                .edge_half_edges(e)
                .map(|h| c[h.0 as usize])
                .fold(0.0f32, f32::max);
            if s > 0.0 {
                let _ = writeln!(buf, "t crease 2/1/0 {a} {b} {s}");
            }
        }
    }
    if let Some(c) = g
        .attrib(AttribClass::Point, CORNER)
        .and_then(|a| a.as_f32())
    {
        for (p, &s) in c.iter().enumerate() {
            if s > 0.0 {
                let _ = writeln!(buf, "t corner 1/1/0 {p} {s}");
            }
        }
    }
    if let Some(h) = g
        .attrib(AttribClass::Primitive, HOLE)
        .and_then(|a| a.as_i32())
    {
        let faces: Vec<String> = h
            .iter()
            .enumerate()
            .filter(|(_, &x)| x != 0)
            .map(|(i, _)| i.to_string())
            .collect();
        if !faces.is_empty() {
            let _ = writeln!(buf, "t hole {}/0/0 {}", faces.len(), faces.join(" "));
        }
    }
    for (name, tag) in [
        (BOUNDARY, "interpolateboundary"),
        (FVAR_BOUNDARY, "facevaryinginterpolateboundary"),
    ] {
        if let Some(v) = g.attrib(AttribClass::Detail, name).and_then(|a| a.as_i32()) {
            let _ = writeln!(buf, "t {tag} 1/0/0 {}", v[0]);
        }
    }
    for (name, tag) in [
        (CREASE_METHOD, "creasemethod"),
        (TRIANGLE_RULE, "smoothtriangles"),
    ] {
        if let Some(s) = g
            .attrib(AttribClass::Detail, name)
            .and_then(|a| a.as_strings())
        {
            let _ = writeln!(buf, "t {tag} 0/0/1 {}", s.get(0));
        }
    }
    if let Some(s) = g
        .attrib(AttribClass::Detail, RAW_TAGS)
        .and_then(|a| a.as_strings())
    {
        for l in s.get(0).lines() {
            let _ = writeln!(buf, "{l}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;

    fn read(s: &str) -> ParseResult<Geometry> {
        read_obj(s.as_bytes(), &NoProgress)
    }

    #[test]
    fn faces_uvs_normals_groups_negative_indices() {
        let g = read(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n\
             g a b\nf 1/1/1 2/2/1 3/3/1\ng b\nusemtl red\nf -4 -2 -1\nl 1 2\n",
        )
        .unwrap();
        assert_eq!(g.num_points(), 4);
        assert_eq!(g.num_prims(), 3);
        assert_eq!(g.prim_points(1), &[0, 2, 3]);
        assert_eq!(g.prim_kind(2), PrimKind::Polyline);
        let uv = g
            .attrib(AttribClass::Vertex, "uv")
            .unwrap()
            .as_vec2()
            .unwrap();
        assert_eq!(uv[2], Vec2::new(1.0, 1.0));
        assert_eq!(uv[3], Vec2::ZERO, "faces without vt get the default");
        assert_eq!(g.prim_groups()["a"].members().collect::<Vec<_>>(), vec![0]);
        assert_eq!(
            g.prim_groups()["b"].members().collect::<Vec<_>>(),
            vec![0, 1, 2]
        );
        let m = g
            .attrib(AttribClass::Primitive, "material")
            .unwrap()
            .as_strings()
            .unwrap();
        assert_eq!((m.get(0), m.get(1)), ("", "red"));
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            (
                "v 0 0 0\nf 1 2 3\n",
                "line 2: vertex index 2 out of range (1 vertexs defined so far)",
            ),
            ("v 0 0\n", "line 1: vertex `v` needs 3 numbers, found 2"),
            (
                "v 0 0 x\n",
                "line 1: expected a number in vertex `v`, found `x`",
            ),
            (
                "v 0 0 0\nv 1 0 0\nf 1 2\n",
                "line 3: `f` needs at least 3 vertices, found 2",
            ),
            ("\n\nbogus 1\n", "line 3: unknown OBJ statement `bogus`"),
            (
                "v 0 0 0\nf 0 1 1\n",
                "line 2: vertex index 0 is invalid (OBJ indices start at 1)",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 9 1.0\n",
                "line 5: tag refers to vertex 9 but there are 3 vertices (0-based)",
            ),
            (
                "t crease 2/1/0 0\n",
                "line 1: tag `crease` expected 2 integers",
            ),
        ];
        for (text, expect) in cases {
            let e = read(text).unwrap_err();
            let got = format!("{}: {}", e.pos.unwrap(), e.message);
            assert_eq!(got, expect, "for {text:?}");
        }
    }

    #[test]
    fn tags_become_attributes_and_round_trip() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n\
                    t crease 2/1/0 0 1 2.5\nt corner 1/1/0 2 4.0\nt interpolateboundary 1/0/0 2\n\
                    t hole 1/0/0 0\nt creasemethod 0/0/1 chaikin\nt vertexedit 1/0/1 3 add\n";
        let g = read(text).unwrap();
        let c = g
            .attrib(AttribClass::Vertex, CREASE)
            .unwrap()
            .as_f32()
            .unwrap();
        assert_eq!(c, &[2.5, 0.0, 0.0, 0.0]);
        assert_eq!(
            g.attrib(AttribClass::Point, CORNER)
                .unwrap()
                .as_f32()
                .unwrap()[2],
            4.0
        );
        assert_eq!(
            g.attrib(AttribClass::Detail, BOUNDARY)
                .unwrap()
                .as_i32()
                .unwrap(),
            &[2]
        );
        assert_eq!(
            g.attrib(AttribClass::Primitive, HOLE)
                .unwrap()
                .as_i32()
                .unwrap(),
            &[1]
        );
        assert_eq!(
            g.attrib(AttribClass::Detail, RAW_TAGS)
                .unwrap()
                .as_strings()
                .unwrap()
                .get(0),
            "t vertexedit 1/0/1 3 add"
        );
        let mut out = Vec::new();
        write_obj(&g, &mut out, Path::new("x.obj"), &NoProgress).unwrap();
        let back = read_obj(&out, &NoProgress).unwrap();
        assert_eq!(back.content_hash(), g.content_hash());
    }
}
