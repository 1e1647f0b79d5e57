//! Bundle nodes (seed 004's streams): pack geometries into one wire, add to a bundle, extract from it.

use std::sync::Arc;

use geode_op::{
    Bundle, CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};

use crate::util::input;

fn bundle_input<'a>(
    ctx: &CookContext,
    inputs: &'a [Option<Value>],
) -> Result<&'a Arc<Bundle>, CookError> {
    inputs
        .first()
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_bundle())
        .ok_or_else(|| ctx.input_error("input 1 needs a bundle"))
}

const PACK_NAMES: P = P::new(
    "names",
    "Names",
    T::String,
    D::Str(""),
    "Names for the inputs, in order, separated by commas.",
);

static PACK: NodeSpec = NodeSpec::new(
    "bundle_pack",
    "Bundle Pack",
    "bundle",
    "Packs its geometry inputs into one bundle, named by a comma-separated list (missing names become input1, input2, ...).",
    &[InputSpec { name: "geometry", ty: PortType::Geometry, required: false }],
    &[
        PACK_NAMES,
    ],
)
.variadic()
.output(PortType::Bundle);

fn cook_pack(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let names: Vec<&str> = p
        .string(&PACK_NAMES)?
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    let mut b = Bundle::default();
    for (i, v) in inputs.iter().enumerate() {
        let Some(g) = v.as_ref().and_then(|v| v.as_geometry()) else {
            continue;
        };
        let name = names
            .get(i)
            .map_or_else(|| format!("input{}", i + 1), |s| s.to_string());
        if b.entries.insert(name.clone(), Arc::clone(g)).is_some() {
            return Err(ctx.param_error(&PACK_NAMES, format!("`{name}` is used twice")));
        }
    }
    Ok(Value::Bundle(Arc::new(b)))
}

const ENTRY_NAME: P = P::new(
    "name",
    "Name",
    T::String,
    D::Str("geometry"),
    "Name of the entry.",
);

static ADD: NodeSpec = NodeSpec::new(
    "bundle_add",
    "Bundle Add",
    "bundle",
    "Adds (or replaces) one named geometry in a bundle.",
    &[
        InputSpec {
            name: "bundle",
            ty: PortType::Bundle,
            required: true,
        },
        InputSpec {
            name: "geometry",
            ty: PortType::Geometry,
            required: true,
        },
    ],
    &[ENTRY_NAME],
)
.output(PortType::Bundle);

fn cook_add(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let mut b = Bundle::clone(bundle_input(ctx, inputs)?);
    b.entries.insert(
        p.string(&ENTRY_NAME)?.to_owned(),
        Arc::clone(input(ctx, inputs, 1)?),
    );
    Ok(Value::Bundle(Arc::new(b)))
}

static EXTRACT: NodeSpec = NodeSpec::new(
    "bundle_extract",
    "Bundle Extract",
    "bundle",
    "Takes one named geometry out of a bundle.",
    &[InputSpec {
        name: "bundle",
        ty: PortType::Bundle,
        required: true,
    }],
    &[ENTRY_NAME],
);

fn cook_extract(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let b = bundle_input(ctx, inputs)?;
    let name = p.string(&ENTRY_NAME)?;
    b.entries
        .get(name)
        .map(|g| Value::Geometry(Arc::clone(g)))
        .ok_or_else(|| {
            let known: Vec<&str> = b.entries.keys().map(|k| k.as_str()).collect();
            ctx.param_error(
                &ENTRY_NAME,
                format!("the bundle has no `{name}` (it has: {})", known.join(", ")),
            )
        })
}

pub fn register(r: &mut Registry) {
    r.node(&PACK, cook_pack);
    r.node(&ADD, cook_add);
    r.node(&EXTRACT, cook_extract);
}
