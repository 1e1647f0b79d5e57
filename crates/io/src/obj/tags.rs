//! OpenSubdiv's OBJ tag lines as attributes: reading them onto a geometry and writing them back.

use geode_geo::{AttribClass, AttribData, AttribValue, Attribute, Geometry, TypeInfo};

use super::Tag;
use crate::error::{ParseError, ParseResult};

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

pub(super) fn apply_tags(g: &mut Geometry, tags: &[Tag]) -> ParseResult<()> {
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
pub(super) fn write_tags(g: &Geometry, buf: &mut String) {
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
