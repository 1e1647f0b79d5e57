//! The geometry spreadsheet: a window of rows of one element class (points, vertices, primitives, detail) with every attribute and group, as Houdini's shows them.

use geode_geo::{AttribClass, AttribType, AttribValue, Geometry};
use serde::Deserialize;
use serde_json::{json, Value as Json};

/// Rows answered per request at most (the studio asks for what is on screen).
pub const MAX_ROWS: usize = 2000;

#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum Class {
    Point,
    Vertex,
    Primitive,
    Detail,
}

/// A float as the spreadsheet shows it: the shortest text that reads back,
/// in scientific notation when tiny or huge (as Houdini's spreadsheet).
fn float_text(x: f32) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-4..1e7).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn components(v: &AttribValue) -> Vec<String> {
    let f = float_text;
    match v {
        AttribValue::Float(x) => vec![f(*x)],
        AttribValue::Int(i) => vec![i.to_string()],
        AttribValue::Vec2(v) => v.to_array().map(f).to_vec(),
        AttribValue::Vec3(v) => v.to_array().map(f).to_vec(),
        AttribValue::Vec4(v) => v.to_array().map(f).to_vec(),
        AttribValue::Quat(q) => q.to_array().map(f).to_vec(),
        AttribValue::Mat4(m) => m.to_cols_array().map(f).to_vec(),
        AttribValue::Mat3(m) => m.to_cols_array().map(f).to_vec(),
        AttribValue::String(s) => vec![s.clone()],
        AttribValue::IntArray(a) => vec![format!("{a:?}")],
        AttribValue::FloatArray(a) => {
            vec![format!("{:?}", a.iter().map(|x| f(*x)).collect::<Vec<_>>()).replace('"', "")]
        }
        AttribValue::Vec3Array(a) => vec![format!("{a:?}")],
        AttribValue::StringArray(a) => vec![format!("{a:?}")],
    }
}

fn width(t: AttribType) -> usize {
    match t {
        AttribType::Float
        | AttribType::Int
        | AttribType::String
        | AttribType::IntArray
        | AttribType::FloatArray
        | AttribType::Vec3Array
        | AttribType::StringArray => 1,
        AttribType::Vec2 => 2,
        AttribType::Vec3 => 3,
        AttribType::Vec4 | AttribType::Quat => 4,
        AttribType::Mat4 => 16,
        AttribType::Mat3 => 9,
    }
}

const AXES: [&str; 4] = ["x", "y", "z", "w"];

/// Column labels of one attribute: `P[x]`, `P[y]`... for vectors.
fn labels(name: &str, width: usize) -> Vec<String> {
    match width {
        1 => vec![name.to_owned()],
        2..=4 => AXES[..width]
            .iter()
            .map(|a| format!("{name}[{a}]"))
            .collect(),
        _ => (0..width).map(|k| format!("{name}[{k}]")).collect(),
    }
}

/// One column source: an attribute or a group of this class, or a built-in.
enum Column<'g> {
    Builtin(&'static str),
    Attrib(&'g str, &'g geode_geo::Attribute),
    Group(&'g str, &'g geode_geo::Group),
}

fn columns(g: &Geometry, class: Class) -> Vec<Column<'_>> {
    let mut cols = Vec::new();
    let attrib_class = match class {
        Class::Point => AttribClass::Point,
        Class::Vertex => {
            cols.push(Column::Builtin("Point"));
            AttribClass::Vertex
        }
        Class::Primitive => {
            cols.push(Column::Builtin("Type"));
            cols.push(Column::Builtin("Vertices"));
            AttribClass::Primitive
        }
        Class::Detail => AttribClass::Detail,
    };
    // P first, as Houdini's sheet shows it; then attributes by name.
    let mut attribs: Vec<(&str, &geode_geo::Attribute)> = g.attribs(attrib_class).iter().collect();
    attribs.sort_by_key(|(n, _)| (*n != geode_geo::P, *n));
    cols.extend(attribs.into_iter().map(|(n, a)| Column::Attrib(n, a)));
    let groups = match class {
        Class::Point => Some(g.point_groups()),
        Class::Primitive => Some(g.prim_groups()),
        _ => None,
    };
    for (n, grp) in groups.into_iter().flatten() {
        cols.push(Column::Group(n, grp));
    }
    cols
}

fn rows_of(g: &Geometry, class: Class) -> usize {
    match class {
        Class::Point => g.num_points(),
        Class::Vertex => g.num_vertices(),
        Class::Primitive => g.num_prims(),
        Class::Detail => 1,
    }
}

/// Rows `start..start+count` (clamped) of `class`.
pub fn window(g: &Geometry, class: Class, start: usize, count: usize) -> Json {
    let cols = columns(g, class);
    let total = rows_of(g, class);
    let start = start.min(total);
    let end = start.saturating_add(count.min(MAX_ROWS)).min(total);
    let mut header: Vec<String> = Vec::new();
    for c in &cols {
        match c {
            Column::Builtin(n) => header.push((*n).to_owned()),
            Column::Attrib(n, a) => header.extend(labels(n, width(a.attrib_type()))),
            Column::Group(n, _) => header.push(format!("group:{n}")),
        }
    }
    let vertex_points = g.vertex_points();
    let rows: Vec<Vec<String>> = (start..end)
        .map(|i| {
            let mut row = Vec::with_capacity(header.len());
            for c in &cols {
                match c {
                    Column::Builtin("Point") => row.push(vertex_points[i].to_string()),
                    Column::Builtin("Type") => row.push(g.prim_kind(i).name().to_owned()),
                    Column::Builtin(_) => row.push(g.prim_vertex_range(i).len().to_string()),
                    Column::Attrib(_, a) => row.extend(components(&a.data().get(i))),
                    Column::Group(_, grp) => row.push(u8::from(grp.contains(i)).to_string()),
                }
            }
            row
        })
        .collect();
    json!({"columns": header, "total": total, "start": start, "rows": rows})
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::{Attribute, Group, TypeInfo};
    use glam::Vec3;

    #[test]
    fn tiny_and_huge_floats_read_in_scientific_notation() {
        assert_eq!(float_text(-5.6048726e-16), "-5.6048726e-16");
        assert_eq!(float_text(0.25), "0.25");
        assert_eq!(float_text(0.0), "0");
        assert_eq!(float_text(3e9), "3e9");
    }

    #[test]
    fn rows_show_attributes_by_component_and_groups() {
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.5, 2.0, 0.0),
        ];
        let mut g = Geometry::from_polygons(p, vec![0, 1, 2, 0, 2, 3], &[3, 3]).unwrap();
        g.set_attrib(
            AttribClass::Point,
            "pscale",
            Attribute::new(AttribValue::Float(0.5), TypeInfo::None, 4),
        )
        .unwrap();
        g.set_prim_group("top", Group::from_members(2, [1]))
            .unwrap();
        let w = window(&g, Class::Point, 1, 2);
        assert_eq!(w["columns"], json!(["P[x]", "P[y]", "P[z]", "pscale"]));
        assert_eq!(w["total"], 4);
        assert_eq!(
            w["rows"],
            json!([["1", "0", "0", "0.5"], ["1", "1", "0", "0.5"]])
        );
        let w = window(&g, Class::Primitive, 0, 10);
        assert_eq!(w["columns"], json!(["Type", "Vertices", "group:top"]));
        assert_eq!(
            w["rows"],
            json!([["polygon", "3", "0"], ["polygon", "3", "1"]])
        );
        let w = window(&g, Class::Vertex, 4, 100);
        assert_eq!(w["rows"], json!([["2"], ["3"]]));
        assert_eq!(window(&g, Class::Point, 99, 5)["rows"], json!([]));
    }
}
