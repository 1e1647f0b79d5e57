//! Wavefront OBJ reader and writer, including OpenSubdiv's `t` tag lines (creases, corners, boundary, holes).

mod tags;
mod write;

use std::collections::BTreeMap;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{
    AttribClass, AttribData, Attribute, Geometry, Group, PrimKind, StringColumn, TypeInfo,
};

use crate::error::{ParseError, ParseResult};
use crate::progress::{Progress, Throttle};
use crate::text::{parse_f32, parse_i64, Lines};

pub use tags::{
    BOUNDARY, CORNER, CREASE, CREASE_METHOD, FVAR_BOUNDARY, HOLE, RAW_TAGS, TRIANGLE_RULE,
};
pub use write::write_obj;

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

pub(crate) struct Tag {
    pub line: u64,
    pub name: String,
    pub ints: Vec<i64>,
    pub floats: Vec<f32>,
    pub strings: Vec<String>,
    pub raw: String,
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
    tags::apply_tags(&mut g, &d.tags)?;
    Ok(g)
}

pub fn read_obj(bytes: &[u8], progress: &dyn Progress) -> ParseResult<Geometry> {
    build(parse(bytes, progress)?)
}

/// Writes OBJ text: `v` (with colours from point `Cd`), `vt`/`vn` from vertex
/// or point `uv`/`N`, `f` and `l`, groups as `g`, materials as `usemtl`, and
/// subdivision tags as `t` lines. Packed primitives must be unpacked first.
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
        write_obj(&g, &mut out, std::path::Path::new("x.obj"), &NoProgress).unwrap();
        let back = read_obj(&out, &NoProgress).unwrap();
        assert_eq!(back.content_hash(), g.content_hash());
    }
}
