//! Wiring nodes: merge, switch, null, object_merge.

use geode_geo::{ops, Geometry};
use geode_op::{
    CancelToken, CheckContext, CookContext, CookError, InputSpec, KeyContext, NodeSpec, Operator,
    ParamDefault as D, ParamSpec as P, ParamType as T, Params, PortType, Registry, Value,
};

use crate::network_file::{self, Outer};
use crate::util::geometry;

const ANY_GEOMETRY: &[InputSpec] = &[InputSpec {
    name: "geometry",
    ty: PortType::Geometry,
    required: false,
}];

static MERGE: NodeSpec = NodeSpec::new(
    "merge",
    "Merge",
    "flow",
    "Combines all inputs in order. Attributes missing on some inputs take their defaults; groups are kept.",
    ANY_GEOMETRY,
    &[],
)
.variadic();

fn cook_merge(ctx: &CookContext, inputs: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
    let gs: Vec<&Geometry> = inputs
        .iter()
        .flatten()
        .filter_map(|v| v.as_geometry().map(|g| &**g))
        .collect();
    geometry(ops::merge(&gs).map_err(|e| ctx.kernel(e))?)
}

const SWITCH_INDEX: P = P::new(
    "index",
    "Index",
    T::Int,
    D::Int(0),
    "Which input (0 is the first).",
)
.at_least(0.0);

static SWITCH: NodeSpec = NodeSpec::new(
    "switch",
    "Switch",
    "flow",
    "Passes one of its inputs through, chosen by index (clamped to the inputs present).",
    ANY_GEOMETRY,
    &[SWITCH_INDEX],
)
.variadic();

fn cook_switch(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    if inputs.is_empty() {
        return Err(ctx.input_error("switch has no inputs"));
    }
    let i = (p.int(&SWITCH_INDEX)?.max(0) as usize).min(inputs.len() - 1);
    inputs[i]
        .clone()
        .ok_or_else(|| ctx.param_error(&SWITCH_INDEX, format!("input {} is not connected", i + 1)))
}

static NULL: NodeSpec = NodeSpec::new(
    "null",
    "Null",
    "flow",
    "Passes its input through unchanged: a named place in a network.",
    &[InputSpec {
        name: "geometry",
        ty: PortType::Geometry,
        required: true,
    }],
    &[],
);

fn cook_null(ctx: &CookContext, inputs: &[Option<Value>], _: &Params) -> Result<Value, CookError> {
    inputs
        .first()
        .cloned()
        .flatten()
        .ok_or_else(|| ctx.input_error("input 1 is not connected"))
}

const OBJECT_MERGE_OBJECTS: P = P::new(
    "objects",
    "Objects",
    T::String,
    D::Str(""),
    "The nodes to merge, by path, separated by spaces: absolute (`/box1`, `/sub/box1`) or from this node's network (`box1`, `../box1`); with a file, nodes of that file's network (from its top level). Read when the network loads (plain text, not an expression).",
)
.not_animatable();

const OBJECT_MERGE_FILE: P = P::new(
    "file",
    "Network File",
    T::File,
    D::Str(""),
    "Another network file (`.json`) whose nodes `objects` names; empty for this network. Write `$HIP/parts.json` for a file beside this network (a bare relative path is from the current folder, as for the file node). It is cooked at this frame with its own `$HIP`; its results' content keys this node, so editing it (or a file it reads) recooks the merge. A file that reaches itself through merges is refused.",
);

static OBJECT_MERGE: NodeSpec = NodeSpec::new(
    "object_merge",
    "Object Merge",
    "flow",
    "Merges other nodes by path, without wires (Houdini's Object Merge): of this network, or of another network file; then transforms the result (scale, rotate, translate about a pivot, as transform does). Nodes of this network are read as inputs: their results key this node's cache, and a loop that names itself is refused when the network loads.",
    &[],
    &[
        OBJECT_MERGE_OBJECTS,
        OBJECT_MERGE_FILE,
        crate::transform::TRANSFORM_TRANSLATE,
        crate::transform::TRANSFORM_ROTATE,
        crate::transform::TRANSFORM_SCALE,
        crate::transform::TRANSFORM_UNIFORM_SCALE,
        crate::transform::TRANSFORM_PIVOT,
    ],
)
.references("objects")
.references_unless("file");

fn cook_object_merge(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let from_file;
    let values: &[Option<Value>] = match p.string(&OBJECT_MERGE_FILE)? {
        "" => inputs,
        file => {
            let outer = Outer::new(ctx.path, &OBJECT_MERGE_FILE, ctx.frame, ctx.env, ctx.cancel);
            from_file = other_file_objects(&outer, file, p)?
                .into_iter()
                .map(Some)
                .collect::<Vec<_>>();
            &from_file
        }
    };
    let mut parts: Vec<&Geometry> = Vec::with_capacity(values.len());
    for (k, v) in values.iter().enumerate() {
        match v.as_ref().map(|v| v.as_geometry()) {
            Some(Some(g)) => parts.push(g),
            _ => {
                return Err(ctx.param_error(
                    &OBJECT_MERGE_OBJECTS,
                    format!("object {} is not a geometry", k + 1),
                ))
            }
        }
    }
    let merged = ops::merge(&parts).map_err(|e| ctx.kernel(e))?;
    geometry(ops::transformed(&merged, crate::transform::matrix(p)?))
}

/// The other file's nodes `objects` names, cooked.
fn other_file_objects(outer: &Outer, file: &str, p: &Params) -> Result<Vec<Value>, CookError> {
    network_file::cook_nodes(outer, file, &object_paths(outer, file, p)?)
}

/// The paths `objects` names (at least one).
fn object_paths<'p>(outer: &Outer, file: &str, p: &'p Params) -> Result<Vec<&'p str>, CookError> {
    let paths: Vec<&str> = p
        .string(&OBJECT_MERGE_OBJECTS)?
        .split_whitespace()
        .collect();
    if paths.is_empty() {
        return Err(CookError::param(
            outer.path,
            OBJECT_MERGE_OBJECTS.name,
            format!("names no node of `{file}` to merge"),
        ));
    }
    Ok(paths)
}

/// object_merge: its own operator for `geode check`'s look at the other
/// file (this network's paths are checked when it loads).
struct ObjectMerge;

impl Operator for ObjectMerge {
    fn spec(&self) -> &'static NodeSpec {
        &OBJECT_MERGE
    }
    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        params: &Params,
    ) -> Result<Value, CookError> {
        cook_object_merge(ctx, inputs, params)
    }
    fn key_extra(&self, ctx: &KeyContext, params: &Params) -> Result<Option<u128>, CookError> {
        key_object_merge(ctx, params)
    }
    fn check(&self, ctx: &CheckContext, p: &Params) -> Result<(), CookError> {
        let file = p.string(&OBJECT_MERGE_FILE)?;
        if file.is_empty() {
            return Ok(());
        }
        let cancel = CancelToken::new();
        let outer = Outer::new(ctx.path, &OBJECT_MERGE_FILE, ctx.frame, ctx.env, &cancel);
        let paths = object_paths(&outer, file, p)?;
        network_file::check_nodes(&outer, file, &paths)
    }
}

/// With a file, the key covers the other network's results (their content
/// hashes), whatever they read; without one, the inputs do.
fn key_object_merge(ctx: &KeyContext, p: &Params) -> Result<Option<u128>, CookError> {
    let file = p.string(&OBJECT_MERGE_FILE)?;
    if file.is_empty() {
        return Ok(None);
    }
    let outer = Outer::new(ctx.path, &OBJECT_MERGE_FILE, ctx.frame, ctx.env, ctx.cancel);
    let mut h = xxhash_rust::xxh3::Xxh3::new();
    for v in other_file_objects(&outer, file, p)? {
        h.update(&v.identity().to_le_bytes());
    }
    Ok(Some(h.digest128()))
}

pub fn register(r: &mut Registry) {
    r.add(ObjectMerge);
    r.node(&MERGE, cook_merge);
    r.node(&SWITCH, cook_switch);
    r.node(&NULL, cook_null);
}
