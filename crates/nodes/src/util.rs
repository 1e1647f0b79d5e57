//! Small helpers shared by the node families: input access, vectors, class menus.

use std::sync::Arc;

use geode_geo::glam::{Vec2, Vec3};
use geode_geo::pattern::GroupPattern;
use geode_geo::{AttribClass, Geometry};
use geode_op::{CookContext, CookError, ParamName, ParamValue, Params, Value};

/// The geometry on input `i` (inputs are checked at load; this guards the rest).
pub fn input<'a>(
    ctx: &CookContext,
    inputs: &'a [Option<Value>],
    i: usize,
) -> Result<&'a Arc<Geometry>, CookError> {
    inputs
        .get(i)
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_geometry())
        .ok_or_else(|| ctx.input_error(format!("input {} needs geometry", i + 1)))
}

/// A copy of input `i` to modify: cheap, every column stays shared with
/// the input until written (copy on write).
pub fn input_owned(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    i: usize,
) -> Result<Geometry, CookError> {
    Ok(Geometry::clone(input(ctx, inputs, i)?))
}

pub fn vec3(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<Vec3, CookError> {
    let [x, y, z] = p.vector::<3>(name)?;
    Ok(Vec3::new(x as f32, y as f32, z as f32))
}

pub fn vec2(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<Vec2, CookError> {
    let [x, y] = p.vector::<2>(name)?;
    Ok(Vec2::new(x as f32, y as f32))
}

pub const CLASSES: &[&str] = &["point", "vertex", "primitive", "detail"];
pub const ELEMENT_CLASSES: &[&str] = &["point", "primitive"];

pub fn class(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<AttribClass, CookError> {
    Ok(match p.string(name)? {
        "point" => AttribClass::Point,
        "vertex" => AttribClass::Vertex,
        "primitive" => AttribClass::Primitive,
        _ => AttribClass::Detail,
    })
}

/// Number of elements of a class.
pub fn count(g: &Geometry, c: AttribClass) -> usize {
    match c {
        AttribClass::Point => g.num_points(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Detail => 1,
    }
}

/// Bytes a polygon mesh takes per point (P, N, uv and a share of the
/// topology caches), per vertex (point index, vertex normal or uv) and per
/// primitive (offset, kind, an attribute): measured on the primitive nodes'
/// outputs, rounded up.
const BYTES_PER_POINT: f64 = 48.0;
const BYTES_PER_VERTEX: f64 = 24.0;
const BYTES_PER_PRIM: f64 = 24.0;

/// Refuses, before allocating, a mesh of about this many points, vertices
/// and primitives that the memory budget cannot hold; `param` is the
/// parameter that asked for it.
pub fn reserve_mesh(
    ctx: &CookContext,
    param: &geode_op::ParamSpec,
    points: f64,
    vertices: f64,
    prims: f64,
) -> Result<(), CookError> {
    let bytes = points * BYTES_PER_POINT + vertices * BYTES_PER_VERTEX + prims * BYTES_PER_PRIM;
    ctx.reserve(
        param,
        bytes,
        &format!(
            "{} point{} and {} primitive{}",
            count_text(points),
            if points == 1.0 { "" } else { "s" },
            count_text(prims),
            if prims == 1.0 { "" } else { "s" }
        ),
    )
}

/// `4.3 billion`, `12.5 million`, `512`: counts in error messages.
/// A length for a message: four significant digits, written plainly
/// (0.5, 0.1235, 1.235e-8).
pub fn length_text(x: f32) -> String {
    let rounded: f32 = format!("{x:.3e}").parse().unwrap_or(x);
    format!("{rounded:?}")
}

pub fn count_text(n: f64) -> String {
    if n >= 1e9 {
        format!("{:.1} billion", n / 1e9)
    } else if n >= 1e6 {
        format!("{:.1} million", n / 1e6)
    } else {
        format!("{n:.0}")
    }
}

/// Rows of a list parameter's old text form: `;`-separated entries of
/// words, each read by `row` (None: not of the form, reported as
/// ``{what} {n} `{entry}`: expected {form}``).
pub fn legacy_rows(
    text: &str,
    what: &str,
    form: &str,
    row: impl Fn(&[&str]) -> Option<Vec<ParamValue>>,
) -> Result<Vec<Vec<ParamValue>>, String> {
    text.split(';')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .enumerate()
        .map(|(k, entry)| {
            let words: Vec<&str> = entry.split_whitespace().collect();
            row(&words).ok_or_else(|| format!("{what} {} `{entry}`: expected {form}", k + 1))
        })
        .collect()
}

/// A finite number.
pub fn finite(s: &str) -> Option<f64> {
    s.parse::<f64>().ok().filter(|x| x.is_finite())
}

pub fn geometry(g: Geometry) -> Result<Value, CookError> {
    Ok(Value::geometry(g))
}

/// The text of the file `param` names, read as the environment allows
/// (`CookContext::read_file`); not UTF-8 is a parameter error.
pub fn text_file(
    ctx: &CookContext,
    param: &geode_op::ParamSpec,
    path: &str,
) -> Result<String, CookError> {
    let bytes = ctx.read_file(param, path)?;
    String::from_utf8(bytes).map_err(|e| {
        ctx.param_error(
            param,
            format!(
                "{path}: not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The group parameter `spec` names on `g` for elements of `class`: None
/// when it selects everything (empty, or `*`); otherwise a Houdini group
/// pattern (`0-9:2 ^3`, `@Cd.x>0.5`, `top*`, geode-geo's one parser). A
/// pattern that does not parse or apply is an error naming the parameter
/// and the column; a plain name that is no group says which groups there
/// are, or the nearest one's name.
pub fn group_param(
    ctx: &CookContext,
    p: &Params,
    spec: &geode_op::ParamSpec,
    g: &Geometry,
    class: AttribClass,
) -> Result<Option<geode_geo::Group>, CookError> {
    let text = p.string(spec)?;
    let pattern = GroupPattern::parse(text)
        .map_err(|e| ctx.param_error(spec, format!("group pattern `{text}`: {e}")))?;
    if pattern.is_everything() {
        return Ok(None);
    }
    if let Some(name) = pattern.single_name() {
        missing_group(ctx, spec, g, class, name)?;
    }
    pattern
        .group(g, class)
        .map(Some)
        .map_err(|e| ctx.param_error(spec, format!("group pattern `{text}`: {e}")))
}

/// An error when `name` is no group of `class` on `g`.
fn missing_group(
    ctx: &CookContext,
    spec: &geode_op::ParamSpec,
    g: &Geometry,
    class: AttribClass,
    name: &str,
) -> Result<(), CookError> {
    let (groups, kind) = match class {
        AttribClass::Point => (g.point_groups(), "point"),
        AttribClass::Primitive => (g.prim_groups(), "primitive"),
        _ => return Ok(()),
    };
    if groups.contains_key(name) {
        return Ok(());
    }
    let known: Vec<&str> = groups.keys().map(String::as_str).collect();
    let mut hint = geode_vex::suggest(name, known.iter().copied());
    if hint.is_empty() {
        // Nothing close: say what there is.
        hint = match known.len() {
            0 => format!(" (there are no {kind} groups)"),
            n if n <= 12 => format!(" ({kind} groups: {})", known.join(", ")),
            n => format!(" ({n} {kind} groups: {}, ...)", known[..12].join(", ")),
        };
    }
    Err(ctx.param_error(spec, format!("no {kind} group `{name}`{hint}")))
}

/// Refuses `name` for parameter `param` unless it is a valid attribute
/// name (letters, digits and `_`, not starting with a digit).
pub fn attribute_name(
    ctx: &CookContext,
    param: &geode_op::ParamSpec,
    name: &str,
) -> Result<(), CookError> {
    if !geode_geo::attrib::is_valid_name(name) {
        return Err(ctx.param_error(
            param,
            format!("`{name}` is not a valid attribute name (letters, digits and _, not starting with a digit)"),
        ));
    }
    Ok(())
}

/// The attribute `name` of class `c`, or an error naming the parameter
/// and the attributes there are (the nearest first when one is close).
pub fn attribute_of<'g>(
    ctx: &CookContext,
    param: &geode_op::ParamSpec,
    g: &'g Geometry,
    c: AttribClass,
    name: &str,
) -> Result<&'g geode_geo::Attribute, CookError> {
    if let Some(a) = g.attrib(c, name) {
        return Ok(a);
    }
    let known: Vec<&str> = g.attribs(c).names().collect();
    let mut hint = geode_vex::suggest(name, known.iter().copied());
    if hint.is_empty() {
        hint = if known.is_empty() {
            " (there are none)".to_owned()
        } else {
            format!(" (there are: {})", known.join(", "))
        };
    }
    Err(ctx.param_error(
        param,
        format!("no {} attribute `{name}`{hint}", class_name(c)),
    ))
}

/// The class as the nodes' menus spell it.
pub fn class_name(c: AttribClass) -> &'static str {
    match c {
        AttribClass::Point => "point",
        AttribClass::Vertex => "vertex",
        AttribClass::Primitive => "primitive",
        AttribClass::Detail => "detail",
    }
}

/// Where each element of a class is: a point's position, a vertex's
/// point's, a primitive's centroid (a packed primitive's origin), the
/// detail at the points' mean.
pub fn element_positions(g: &Geometry, c: AttribClass) -> Vec<Vec3> {
    let p = g.positions();
    let mean = |pts: &mut dyn Iterator<Item = Vec3>, n: usize| pts.sum::<Vec3>() / n.max(1) as f32;
    match c {
        AttribClass::Primitive => (0..g.num_prims())
            .map(|i| {
                if let (geode_geo::PrimKind::Packed(_), Some(m)) =
                    (g.prim_kind(i), g.packed_world_transform(i))
                {
                    return m.w_axis.truncate();
                }
                let pts = g.prim_points(i);
                mean(&mut pts.iter().map(|&k| p[k as usize]), pts.len())
            })
            .collect(),
        AttribClass::Vertex => g.vertex_points().iter().map(|&k| p[k as usize]).collect(),
        AttribClass::Detail => vec![mean(&mut p.iter().copied(), p.len())],
        AttribClass::Point => p.to_vec(),
    }
}
