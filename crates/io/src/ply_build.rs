//! PLY elements read into a `Geometry`: points with PLY's usual names, faces and polylines, and the attributes geode declared in the header.

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::{AttribClass, AttribData, AttribType, Attribute, Geometry, PrimKind, TypeInfo};

use crate::error::{ParseError, ParseResult};
use crate::ply::{Column, Declared, Element, Header, PropKind, Scalar};

fn find(el: &Element, names: &[&str]) -> Option<usize> {
    names
        .iter()
        .find_map(|n| el.props.iter().position(|p| p.name == *n))
}

/// A declared attribute's column from its properties (one per component, or
/// one list), the properties it used marked.
fn declared_column(
    d: &Declared,
    el: &Element,
    cols: &[Column],
    used: &mut Vec<usize>,
) -> ParseResult<Option<AttribData>> {
    let bad = |m: String| ParseError::whole(format!("{} attribute `{}`: {m}", d.class, d.name));
    let ints = |v: &[f64]| v.iter().map(|&x| x as i32).collect::<Vec<_>>();
    let floats = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<_>>();
    let as_list = matches!(
        d.ty,
        AttribType::IntArray | AttribType::FloatArray | AttribType::Vec3Array
    ) || d.class == AttribClass::Vertex;
    if as_list {
        let Some(i) = find(el, &[d.name.as_str()]) else {
            return Ok(None);
        };
        used.push(i);
        let c = &cols[i];
        let mut rows = Vec::with_capacity(c.list_counts.len());
        let mut at = 0;
        for &n in &c.list_counts {
            rows.push(&c.values[at..at + n as usize]);
            at += n as usize;
        }
        return Ok(Some(match d.ty {
            AttribType::IntArray => AttribData::IntArray(rows.iter().map(|r| ints(r)).collect()),
            AttribType::FloatArray => {
                AttribData::FloatArray(rows.iter().map(|r| floats(r)).collect())
            }
            AttribType::Vec3Array => AttribData::Vec3Array(
                rows.iter()
                    .map(|r| {
                        r.chunks_exact(3)
                            .map(|v| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
                            .collect()
                    })
                    .collect(),
            ),
            // A vertex attribute: each list holds the prim's corners in turn.
            ty => {
                let flat: Vec<f64> = rows.concat();
                column_from_flat(ty, &flat)
                    .ok_or_else(|| bad("corner lists do not hold whole values".into()))?
            }
        }));
    }
    let suffixes = crate::attrib_codec::component_suffixes(d.ty);
    let names: Vec<String> = if suffixes.is_empty() {
        vec![d.name.clone()]
    } else {
        suffixes.iter().map(|s| format!("{}_{s}", d.name)).collect()
    };
    let mut idx = Vec::new();
    for n in &names {
        match find(el, &[n.as_str()]) {
            Some(i) => idx.push(i),
            None if idx.is_empty() => return Ok(None),
            None => return Err(bad(format!("property `{n}` is missing"))),
        }
    }
    used.extend(&idx);
    let flat: Vec<f64> = (0..el.count)
        .flat_map(|e| idx.iter().map(move |&i| (i, e)))
        .map(|(i, e)| cols[i].values[e])
        .collect();
    Ok(column_from_flat(d.ty, &flat))
}

/// A column of `ty` from its values in element order, components together.
fn column_from_flat(ty: AttribType, flat: &[f64]) -> Option<AttribData> {
    if ty == AttribType::Int {
        // Ints straight from the file's doubles: exact beyond 2^24.
        return Some(AttribData::Int(flat.iter().map(|&x| x as i32).collect()));
    }
    let f: Vec<f32> = flat.iter().map(|&x| x as f32).collect();
    crate::attrib_codec::column_from_floats(ty, &f)
}

/// Columns of one class gathered element by element, padded with zeros
/// where an element lacks them.
#[derive(Default)]
struct Gathered {
    columns: Vec<(String, Attribute)>,
}

impl Gathered {
    fn add(
        &mut self,
        name: &str,
        data: AttribData,
        info: TypeInfo,
        at: usize,
        total: usize,
    ) -> ParseResult<()> {
        let ty = data.attrib_type();
        let i = match self.columns.iter().position(|(n, _)| n == name) {
            Some(i) => i,
            None => {
                let zero = Attribute::new(geode_geo::AttribValue::zero(ty), info, total);
                self.columns.push((name.to_owned(), zero));
                self.columns.len() - 1
            }
        };
        let (_, a) = &mut self.columns[i];
        a.values_mut().write(at, &data).map_err(|found| {
            ParseError::whole(format!(
                "attribute `{name}` is {ty} in one element and {found} in another"
            ))
        })
    }
}

pub(crate) fn build(h: &Header, data: Vec<Vec<Column>>) -> ParseResult<Geometry> {
    // Counts first: every element's prims and corners, so gathered columns know their length.
    let prim_elements = ["face", "polyline", "edge"];
    let n_prims: usize = h
        .elements
        .iter()
        .filter(|e| prim_elements.contains(&e.name.as_str()))
        .map(|e| e.count)
        .sum();
    // Every face's and polyline's corners, then two per edge.
    let n_vertices: usize = h
        .elements
        .iter()
        .zip(&data)
        .map(|(el, cols)| match el.name.as_str() {
            "face" | "polyline" => find(el, &["vertex_indices", "vertex_index"])
                .map_or(0, |i| cols[i].list_counts.iter().map(|&n| n as usize).sum()),
            "edge" => 2 * el.count,
            _ => 0,
        })
        .sum();
    let mut positions = Vec::new();
    let mut points = Gathered::default();
    let mut prims = PrimLists::default();
    let mut prim_cols = Gathered::default();
    let mut vertex_cols = Gathered::default();
    for (el, cols) in h.elements.iter().zip(&data) {
        match el.name.as_str() {
            "vertex" => {
                positions = read_points(h, el, cols, &mut points)?;
            }
            "face" | "polyline" => {
                let first_prim = prims.counts.len();
                let first_vertex = prims.vertex_points.len();
                read_prims(el, cols, positions.len(), &mut prims)?;
                let mut used =
                    vec![find(el, &["vertex_indices", "vertex_index"]).unwrap_or(usize::MAX)];
                for d in h.declared.iter().filter(|d| d.class != AttribClass::Point) {
                    if let Some(col) = declared_column(d, el, cols, &mut used)? {
                        if d.class == AttribClass::Vertex {
                            vertex_cols.add(&d.name, col, d.info, first_vertex, n_vertices)?;
                        } else {
                            prim_cols.add(&d.name, col, d.info, first_prim, n_prims)?;
                        }
                    }
                }
                if let Some(ti) = find(el, &["texcoord"]).filter(|i| !used.contains(i)) {
                    used.push(ti);
                    let t = &cols[ti];
                    let corners = &cols[used[0]].list_counts;
                    if t.list_counts.iter().zip(corners).all(|(a, b)| *a == 2 * *b) {
                        let uv = t
                            .values
                            .chunks(2)
                            .map(|p| Vec2::new(p[0] as f32, p[1] as f32))
                            .collect();
                        vertex_cols.add(
                            "uv",
                            AttribData::Vec2(uv),
                            TypeInfo::TexCoord,
                            first_vertex,
                            n_vertices,
                        )?;
                    }
                }
                for (i, p) in el.props.iter().enumerate() {
                    if let (false, &PropKind::Scalar(s)) = (used.contains(&i), &p.kind) {
                        let data = scalar_column(&cols[i].values, s.is_float());
                        prim_cols.add(&p.name, data, TypeInfo::None, first_prim, n_prims)?;
                    }
                }
            }
            "edge" => read_edges(el, cols, positions.len(), &mut prims)?,
            _ => {}
        }
    }
    let mut g = Geometry::from_prims(positions, prims.vertex_points, &prims.counts, prims.kinds)
        .map_err(|e| ParseError::whole(e.to_string()))?;
    let set = |g: &mut Geometry, class, name: &str, a| {
        g.set_attrib(class, name, a)
            .map_err(|e| ParseError::whole(e.to_string()))
    };
    for (name, a) in points.columns {
        set(&mut g, AttribClass::Point, &name, a)?;
    }
    // Columns were gathered at the full primitive count: they fit as they are.
    for (name, a) in prim_cols.columns {
        set(&mut g, AttribClass::Primitive, &name, a)?;
    }
    for (name, a) in vertex_cols.columns {
        set(&mut g, AttribClass::Vertex, &name, a)?;
    }
    Ok(g)
}

fn scalar_column(values: &[f64], float: bool) -> AttribData {
    if float {
        AttribData::Float(values.iter().map(|&v| v as f32).collect())
    } else {
        AttribData::Int(values.iter().map(|&v| v as i32).collect())
    }
}

/// The `vertex` element: positions; `nx ny nz`, `red green blue`, `s t`;
/// declared attributes; every other scalar as a point attribute.
fn read_points(
    h: &Header,
    el: &Element,
    cols: &[Column],
    out: &mut Gathered,
) -> ParseResult<Vec<Vec3>> {
    let scalar = |i: usize| &cols[i].values;
    let (Some(x), Some(y), Some(z)) = (find(el, &["x"]), find(el, &["y"]), find(el, &["z"])) else {
        return Err(ParseError::whole("element `vertex` lacks x, y or z"));
    };
    let n = el.count;
    let positions = (0..n)
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
    if let Some(c) = vec3(["nx", "ny", "nz"]) {
        used.extend(c);
        let v = (0..n)
            .map(|i| {
                Vec3::new(
                    scalar(c[0])[i] as f32,
                    scalar(c[1])[i] as f32,
                    scalar(c[2])[i] as f32,
                )
            })
            .collect();
        out.add("N", AttribData::Vec3(v), TypeInfo::Normal, 0, n)?;
    }
    if let Some(c) = vec3(["red", "green", "blue"]) {
        used.extend(c);
        let scale = |k: usize| match el.props[c[k]].kind {
            PropKind::Scalar(Scalar::U8) => 1.0 / 255.0,
            PropKind::Scalar(Scalar::U16) => 1.0 / 65535.0,
            _ => 1.0,
        };
        let s = [scale(0), scale(1), scale(2)];
        let v = (0..n)
            .map(|i| {
                Vec3::new(
                    (scalar(c[0])[i] * s[0]) as f32,
                    (scalar(c[1])[i] * s[1]) as f32,
                    (scalar(c[2])[i] * s[2]) as f32,
                )
            })
            .collect();
        out.add("Cd", AttribData::Vec3(v), TypeInfo::Color, 0, n)?;
    }
    for (un, vn) in [("s", "t"), ("u", "v"), ("texture_u", "texture_v")] {
        if let (Some(u), Some(v)) = (find(el, &[un]), find(el, &[vn])) {
            used.extend([u, v]);
            let uv = (0..n)
                .map(|i| Vec2::new(scalar(u)[i] as f32, scalar(v)[i] as f32))
                .collect();
            out.add("uv", AttribData::Vec2(uv), TypeInfo::TexCoord, 0, n)?;
            break;
        }
    }
    for d in h.declared.iter().filter(|d| d.class == AttribClass::Point) {
        if let Some(col) = declared_column(d, el, cols, &mut used)? {
            out.add(&d.name, col, d.info, 0, n)?;
        }
    }
    for (i, p) in el.props.iter().enumerate() {
        if let (false, &PropKind::Scalar(s)) = (used.contains(&i), &p.kind) {
            out.add(
                &p.name,
                scalar_column(&cols[i].values, s.is_float()),
                TypeInfo::None,
                0,
                n,
            )?;
        }
    }
    Ok(positions)
}

/// The primitives read so far, each checked as it is added.
#[derive(Default)]
struct PrimLists {
    vertex_points: Vec<u32>,
    counts: Vec<u32>,
    kinds: Vec<PrimKind>,
}

impl PrimLists {
    /// Adds primitive `index` of element `what`, its points checked against `n_points`.
    fn push(
        &mut self,
        what: &str,
        index: usize,
        points: &[f64],
        n_points: usize,
        kind: PrimKind,
    ) -> ParseResult<()> {
        for &v in points {
            if v < 0.0 || v as usize >= n_points {
                return Err(ParseError::whole(format!(
                    "{what} {index} refers to vertex {v} but there are {n_points} vertices"
                )));
            }
            self.vertex_points.push(v as u32);
        }
        self.counts.push(points.len() as u32);
        self.kinds.push(kind);
        Ok(())
    }
}

/// Polygons (`face`) or polylines (`polyline`) from their vertex lists.
fn read_prims(
    el: &Element,
    cols: &[Column],
    n_points: usize,
    prims: &mut PrimLists,
) -> ParseResult<()> {
    let what = el.name.as_str();
    let Some(vi) = find(el, &["vertex_indices", "vertex_index"]) else {
        return Err(ParseError::whole(format!(
            "element `{what}` lacks a vertex_indices list"
        )));
    };
    let c = &cols[vi];
    if c.list_counts.is_empty() && el.count > 0 {
        return Err(ParseError::whole(format!(
            "{what} property vertex_indices must be a list"
        )));
    }
    let (kind, least) = if what == "face" {
        (PrimKind::Polygon, 3)
    } else {
        (PrimKind::Polyline, 2)
    };
    let mut k = 0;
    for (f, &n) in c.list_counts.iter().enumerate() {
        if n < least {
            return Err(ParseError::whole(format!(
                "{what} {f} has {n} vertices, at least {least} needed"
            )));
        }
        prims.push(what, f, &c.values[k..k + n as usize], n_points, kind)?;
        k += n as usize;
    }
    Ok(())
}

/// Other tools' `edge` elements: two-point polylines.
fn read_edges(
    el: &Element,
    cols: &[Column],
    n_points: usize,
    prims: &mut PrimLists,
) -> ParseResult<()> {
    if let (Some(a), Some(b)) = (find(el, &["vertex1"]), find(el, &["vertex2"])) {
        for i in 0..el.count {
            prims.push(
                "edge",
                i,
                &[cols[a].values[i], cols[b].values[i]],
                n_points,
                PrimKind::Polyline,
            )?;
        }
    }
    Ok(())
}
