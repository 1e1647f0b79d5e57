//! sort: points or primitives in a new order (Houdini's Sort): by an axis,
//! an attribute, at random (seeded), along a vector, by nearness to a
//! point, or reversed; a stable sort (equal keys keep their order), then
//! optionally reversed and shifted.

use geode_geo::glam::Vec3;
use geode_geo::{ops, random, AttribClass};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{class, element_positions, geometry, input_owned, vec3, ELEMENT_CLASSES};

const CLASS: P = P::new(
    "class",
    "Sort",
    T::Menu(ELEMENT_CLASSES),
    D::Str("point"),
    "Sort points or primitives (by their centroids).",
);
const KEY: P = P::new(
    "key",
    "Sort by",
    T::Menu(&["none", "x", "y", "z", "attribute", "random", "vector", "proximity"]),
    D::Str("x"),
    "The key: no change, a position axis, an attribute's component, a seeded random order, the position along a vector, or the distance to a point.",
);
const ATTRIBUTE: P = P::new("attribute", "Attribute", T::String, D::Str(""), "The attribute (of the sorted class) to sort by, `name` or `name[k]` for a component; strings sort by text.");
const SEED: P = P::new(
    "seed",
    "Seed",
    T::Int,
    D::Int(0),
    "The random order's seed.",
);
const VECTOR: P = P::new(
    "vector",
    "Vector",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "Sort along this direction.",
);
const POINT: P = P::new(
    "point",
    "Point",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Sort by distance to this point, nearest first.",
);
const REVERSE: P = P::new(
    "reverse",
    "Reverse",
    T::Toggle,
    D::Toggle(false),
    "Reverse the order after sorting.",
);
const OFFSET: P = P::new(
    "offset",
    "Offset",
    T::Int,
    D::Int(0),
    "Shift the order cyclically: element k moves to k + offset (modulo the count).",
);

static SORT: NodeSpec = NodeSpec::new(
    "sort",
    "Sort",
    "attribute",
    "Renumbers points or primitives (Houdini's Sort): by axis, attribute, random seed, along a vector or by nearness to a point; stable, then reversed and shifted if asked.",
    &[geometry_input("geometry")],
    &[CLASS, KEY, ATTRIBUTE, SEED, VECTOR, POINT, REVERSE, OFFSET],
);

/// A sort key: numbers, or text.
enum Keys {
    Numbers(Vec<f64>),
    Text(Vec<String>),
}

fn cook_sort(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut g = input_owned(ctx, inputs, 0)?;
    let c = class(p, &CLASS)?;
    let n = crate::util::count(&g, c);
    let at = || element_positions(&g, c);
    let along = |d: Vec3| Keys::Numbers(at().iter().map(|q| f64::from(q.dot(d))).collect());
    let keys = match p.string(&KEY)? {
        "none" => None,
        "x" => Some(along(Vec3::X)),
        "y" => Some(along(Vec3::Y)),
        "z" => Some(along(Vec3::Z)),
        "vector" => {
            let d = vec3(p, &VECTOR)?;
            if d == Vec3::ZERO || !d.is_finite() {
                return Err(ctx.param_error(
                    &VECTOR,
                    "the vector is zero (or not finite): nothing to sort along",
                ));
            }
            Some(along(d))
        }
        "proximity" => {
            let o = vec3(p, &POINT)?;
            Some(Keys::Numbers(
                at().iter().map(|q| f64::from(q.distance(o))).collect(),
            ))
        }
        "random" => {
            let seed = p.int(&SEED)? as u64;
            Some(Keys::Numbers(
                (0..n)
                    .map(|i| random::unit_f64(seed, i as u64, 7))
                    .collect(),
            ))
        }
        _ => Some(attribute_keys(ctx, p, &g, c)?),
    };
    let mut order: Vec<u32> = (0..n as u32).collect();
    match &keys {
        Some(Keys::Numbers(k)) => order.sort_by(|&a, &b| k[a as usize].total_cmp(&k[b as usize])),
        Some(Keys::Text(k)) => order.sort_by(|&a, &b| k[a as usize].cmp(&k[b as usize])),
        None => {}
    }
    if p.toggle(&REVERSE)? {
        order.reverse();
    }
    if n > 0 {
        let shift = p.int(&OFFSET)?.rem_euclid(n as i64) as usize;
        order.rotate_right(shift);
    }
    ctx.check()?;
    let r = if c == AttribClass::Point {
        ops::reorder_points(&mut g, &order)
    } else {
        ops::reorder_prims(&mut g, &order)
    };
    r.map_err(|e| ctx.kernel(e))?;
    geometry(g)
}

/// The keys an attribute gives: a number's component, or a string.
fn attribute_keys(
    ctx: &CookContext,
    p: &Params,
    g: &geode_geo::Geometry,
    c: AttribClass,
) -> Result<Keys, CookError> {
    let text = p.string(&ATTRIBUTE)?;
    let (name, k) = match text.strip_suffix(']').and_then(|t| t.split_once('[')) {
        Some((name, k)) => (
            name,
            k.parse::<usize>().map_err(|_| {
                ctx.param_error(&ATTRIBUTE, format!("`{k}` is no component number"))
            })?,
        ),
        None => (text, 0),
    };
    let a = crate::util::attribute_of(ctx, &ATTRIBUTE, g, c, name)?;
    if let Some(s) = a.as_strings() {
        return Ok(Keys::Text(
            (0..s.indices.len()).map(|i| s.get(i).to_owned()).collect(),
        ));
    }
    if let Some(v) = a.as_i32() {
        return Ok(Keys::Numbers(v.iter().map(|&x| f64::from(x)).collect()));
    }
    match a.data().as_floats() {
        Some((f, w)) if k < w => Ok(Keys::Numbers(
            f.chunks(w).map(|e| f64::from(e[k])).collect(),
        )),
        Some((_, w)) => Err(ctx.param_error(
            &ATTRIBUTE,
            format!("`{name}` has {w} components: {k} is past them"),
        )),
        None => Err(ctx.param_error(
            &ATTRIBUTE,
            format!("`{name}` is an array attribute: sort by numbers or strings"),
        )),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&SORT, cook_sort);
}
