//! Offsets and shells of solids with a true thickness: the frep_offset and
//! frep_shell nodes over the kernel's distance estimate.

use geode_frep::distance::{self, Measure, ShellSide};
use geode_op::{
    CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T, Params,
    PortType, Registry, Value,
};

use crate::frep::{field_input, out, FIELD_IN};

const MEASURE: P = P::new(
    "measure",
    "Measure",
    T::Menu(&["distance", "field"]),
    D::Str("distance"),
    "distance: the input's value turned into a distance to its surface (Newton steps along the gradient), so the result has the thickness asked for any field; field: the raw value, exact and cheaper when the input already is a distance (spheres, boxes, sweeps).",
);

fn measure(p: &Params) -> Result<Measure, CookError> {
    Ok(match p.string(&MEASURE)? {
        "field" => Measure::Field,
        _ => Measure::Distance,
    })
}

const OFFSET_DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.1),
    "How far the surface moves, in model units: positive grows the solid, negative shrinks it.",
);

static OFFSET: NodeSpec = NodeSpec::new(
    "frep_offset",
    "FRep Offset",
    "frep",
    "Grows (positive) or shrinks (negative) a solid by a distance measured from its surface.",
    &[FIELD_IN],
    &[OFFSET_DISTANCE, MEASURE],
)
.output(PortType::Field);

fn cook_offset(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let d = p.float(&OFFSET_DISTANCE)?;
    crate::frep_volume::warn_beyond_band(ctx, f, d);
    out(distance::offset(f, d, measure(p)?))
}

const SHELL_THICKNESS: P = P::new(
    "thickness",
    "Thickness",
    T::Float,
    D::Float(0.05),
    "The wall's thickness in model units.",
)
.at_least(1e-9);

const SHELL_SIDE: P = P::new(
    "side",
    "Side",
    T::Menu(&["inside", "outside", "centered"]),
    D::Str("inside"),
    "Where the wall lies: inside the surface (the solid hollowed, its outside kept), outside it, or centred on it.",
);

static SHELL: NodeSpec = NodeSpec::new(
    "frep_shell",
    "FRep Shell",
    "frep",
    "A hollow wall of a given thickness along a solid's surface (for printing: a closed skin whose inside is empty).",
    &[FIELD_IN],
    &[SHELL_THICKNESS, SHELL_SIDE, MEASURE],
)
.output(PortType::Field);

fn cook_shell(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let f = field_input(ctx, inputs, 0)?;
    let side = match p.string(&SHELL_SIDE)? {
        "outside" => ShellSide::Outside,
        "centered" => ShellSide::Centered,
        _ => ShellSide::Inside,
    };
    crate::frep_volume::warn_beyond_band(ctx, f, p.float(&SHELL_THICKNESS)?);
    out(distance::shell(
        f,
        p.float(&SHELL_THICKNESS)?,
        side,
        measure(p)?,
    ))
}

pub fn register(r: &mut Registry) {
    r.node(&OFFSET, cook_offset);
    r.node(&SHELL, cook_shell);
}
