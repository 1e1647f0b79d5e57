//! Small helpers shared by the node families: input access, vectors, class menus.

use std::sync::Arc;

use geode_geo::glam::{Vec2, Vec3};
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
    param: &str,
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
pub fn text_file(ctx: &CookContext, param: &str, path: &str) -> Result<String, CookError> {
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
/// when empty (every element); a group's name, or a Houdini group pattern
/// (`0-9 !3`, `@Cd.x>0.5`, `top*`) as `expandpointgroup` reads it. A name
/// that is no group is an error naming the parameter, with the nearest
/// group's name.
pub fn group_param(
    ctx: &CookContext,
    p: &Params,
    spec: &geode_op::ParamSpec,
    g: &Geometry,
    class: AttribClass,
) -> Result<Option<geode_geo::Group>, CookError> {
    let name = p.string(spec)?;
    if name.is_empty() {
        return Ok(None);
    }
    let len = if class == AttribClass::Point {
        g.num_points()
    } else {
        g.num_prims()
    };
    let plain = name.chars().all(|c| c.is_alphanumeric() || c == '_')
        && !name.chars().all(|c| c.is_ascii_digit());
    if !plain {
        let members = geode_vex::pattern::expand(g, class, name);
        return Ok(Some(geode_geo::Group::from_members(len, members)));
    }
    let groups = if class == AttribClass::Point {
        g.point_groups()
    } else {
        g.prim_groups()
    };
    match groups.get(name) {
        Some(grp) => Ok(Some(grp.clone())),
        None => {
            let kind = if class == AttribClass::Point {
                "point"
            } else {
                "primitive"
            };
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
            Err(ctx.param_error(spec.name, format!("no {kind} group `{name}`{hint}")))
        }
    }
}
