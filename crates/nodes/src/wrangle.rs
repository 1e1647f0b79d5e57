//! The wrangle node (Houdini's Attribute Wrangle): runs a VEX snippet over
//! the points, vertices, primitives or detail of its first input, reading
//! up to three more inputs and the node's spare parameters through `ch()`.

use geode_geo::AttribClass;
use geode_op::{
    CheckContext, CookContext, CookError, ErrorKind, InputSpec, NodeSpec, Operator,
    ParamDefault as D, ParamSpec as P, ParamType as T, ParamValue, Params, PortType, Registry,
    Value,
};
use geode_vex::{BindSpec, Channel, RunError, RunOptions};

use crate::util::{geometry, input};

const RUN_OVER_CLASSES: &[&str] = &["points", "vertices", "primitives", "detail"];

const SNIPPET: P = P::new(
    "snippet",
    "VEXpression",
    T::String,
    D::Str(""),
    "VEX code run once per element: @bindings, locals, functions, loops and SideFX's library (see docs/wrangle.md).",
)
.code();
const RUN_OVER: P = P::new(
    "run_over",
    "Run Over",
    T::Menu(RUN_OVER_CLASSES),
    D::Str("points"),
    "The elements the snippet runs over; detail runs it once.",
);
const GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "Only these elements (points or primitives, as run over): a group name or a Houdini group pattern (`0-9 ^3`, `top*`, `@P.y>0`); empty for all.",
);

const fn optional(name: &'static str) -> InputSpec {
    InputSpec {
        name,
        ty: PortType::Geometry,
        required: false,
    }
}

static WRANGLE: NodeSpec = NodeSpec::new(
    "wrangle",
    "Attribute Wrangle",
    "attributes",
    "Runs a VEX snippet over every point, vertex, primitive or the detail of input 1. Every element reads the input as it was; writes to other elements, new and removed geometry apply after all ran, in element order. ch(\"name\") reads the node's spare parameters.",
    &[
        InputSpec { name: "geometry", ty: PortType::Geometry, required: true },
        optional("input 2"),
        optional("input 3"),
        optional("input 4"),
    ],
    &[SNIPPET, RUN_OVER, GROUP],
)
.spare_params();

fn channel(v: &ParamValue) -> Channel {
    match v {
        ParamValue::Float(x) => Channel::Num(vec![*x]),
        ParamValue::Int(i) => Channel::Num(vec![*i as f64]),
        ParamValue::Toggle(b) => Channel::Num(vec![f64::from(u8::from(*b))]),
        ParamValue::Vector(v) => Channel::Num(v.clone()),
        ParamValue::String(s) => Channel::Str(s.clone()),
        ParamValue::List(_) => Channel::Num(Vec::new()),
        // chramp() evaluates it; ch() of it is its number of keys (a ramp
        // is a multiparm in Houdini, and a multiparm's value is its count).
        ParamValue::Ramp(r) => Channel::Ramp(r.clone()),
    }
}

fn run_over(p: &Params) -> Result<AttribClass, CookError> {
    Ok(match p.string(&RUN_OVER)? {
        "vertices" => AttribClass::Vertex,
        "primitives" => AttribClass::Primitive,
        "detail" => AttribClass::Detail,
        _ => AttribClass::Point,
    })
}

struct Wrangle;

impl Operator for Wrangle {
    fn spec(&self) -> &'static NodeSpec {
        &WRANGLE
    }

    fn cook(
        &self,
        ctx: &CookContext,
        inputs: &[Option<Value>],
        p: &Params,
    ) -> Result<Value, CookError> {
        let g0 = input(ctx, inputs, 0)?;
        let others: Vec<Option<&geode_geo::Geometry>> = (1..4)
            .map(|i| {
                inputs
                    .get(i)
                    .and_then(|v| v.as_ref())
                    .and_then(|v| v.as_geometry())
                    .map(|g| g.as_ref())
            })
            .collect();
        let mut all = vec![Some(g0.as_ref())];
        all.extend(others);
        let class = run_over(p)?;
        let channels = |name: &str| p.spare(name).map(channel);
        let names = || p.spares().iter().map(|(n, _)| n.clone()).collect();
        let spec = BindSpec {
            run_over: class,
            inputs: all.clone(),
            channels: &channels,
            channel_names: &names,
            frame: ctx.frame,
            time: ctx.env.time(ctx.frame),
        };
        let program = geode_vex::compile(p.string(&SNIPPET)?, &spec).map_err(|e| {
            let pos = e.pos;
            ctx.kernel_at(&SNIPPET, e).at_position(pos.line, pos.col)
        })?;
        let group = group_members(ctx, p, g0, class)?;
        let mut out = geode_geo::Geometry::clone(g0);
        let cancel = ctx.cancel_fn();
        let opts = RunOptions {
            group: group.as_deref(),
            cancel: &cancel,
            memory_budget: ctx.env.memory_budget,
        };
        match geode_vex::run(&program, &mut out, &all, &opts) {
            Ok(report) => {
                show_printed(ctx, &report.printed);
                geometry(out)
            }
            Err(RunError::Cancelled) => Err(CookError::cancelled(ctx.path)),
            Err(e @ RunError::OverBudget { pos, .. }) => {
                Err(CookError::new(ctx.path, ErrorKind::Resource, e.to_string())
                    .at_param("snippet")
                    .at_position(pos.line, pos.col)
                    .with_source(e))
            }
            Err(e @ RunError::At { pos, .. }) if pos.line > 0 => {
                Err(ctx.kernel_at(&SNIPPET, e).at_position(pos.line, pos.col))
            }
            Err(e) => Err(ctx.kernel_at(&SNIPPET, e)),
        }
    }

    fn reads_frame(&self, p: &Params) -> bool {
        p.string(&SNIPPET)
            .is_ok_and(|s| s.contains("@Frame") || s.contains("@Time"))
    }

    /// Compiles the snippet against what is known without cooking: the
    /// class it runs over, which inputs are wired, the spare parameters and
    /// the frame; the inputs' attributes are unknown (see `wrangle_check`).
    fn check(&self, ctx: &CheckContext, p: &Params) -> Result<(), CookError> {
        let class = run_over(p)?;
        if !p.string(&GROUP)?.is_empty() {
            group_class(ctx.path, class)?;
        }
        let channels = |name: &str| p.spare(name).map(channel);
        let names = || p.spares().iter().map(|(n, _)| n.clone()).collect();
        let unknown = crate::wrangle_check::Unknown {
            run_over: class,
            wired: ctx.wired,
            channels: &channels,
            channel_names: &names,
            frame: ctx.frame,
            time: ctx.env.time(ctx.frame),
        };
        crate::wrangle_check::compiles(p.string(&SNIPPET)?, &unknown)
            .map_err(|e| ctx.text_error("snippet", e.pos.line, e.pos.col, e.msg))
    }
}

/// Refuses a group on a class groups do not select.
fn group_class(path: &str, class: AttribClass) -> Result<(), CookError> {
    match class {
        AttribClass::Point | AttribClass::Primitive => Ok(()),
        _ => Err(CookError::param(
            path,
            "group",
            "a group selects points or primitives; run over those to use one",
        )),
    }
}

/// The sorted members of the named group, or None for every element.
fn group_members(
    ctx: &CookContext,
    p: &Params,
    g: &geode_geo::Geometry,
    class: AttribClass,
) -> Result<Option<Vec<u32>>, CookError> {
    if p.string(&GROUP)?.is_empty() {
        return Ok(None);
    }
    group_class(ctx.path, class)?;
    let grp = crate::util::group_param(ctx, p, &GROUP, g, class)?;
    Ok(grp.map(|grp| {
        (0..grp.len())
            .filter(|&i| grp.contains(i))
            .map(|i| i as u32)
            .collect()
    }))
}

pub fn register(r: &mut Registry) {
    r.add(Wrangle);
}

/// What `printf` printed, in element order, as the cook's messages (the
/// CLI writes them to stderr, the studio shows them on the node): the
/// first `PRINTED_LINES` lines, then how many more there were.
fn show_printed(ctx: &CookContext, printed: &[String]) {
    const PRINTED_LINES: usize = 200;
    if printed.is_empty() {
        return;
    }
    // Calls print pieces; lines are what their text says.
    let text = printed.concat();
    let lines = text.strip_suffix('\n').unwrap_or(&text).split('\n');
    let mut shown = 0usize;
    let mut more = 0usize;
    for line in lines {
        if shown < PRINTED_LINES {
            ctx.warn(format!("printf: {line}"));
            shown += 1;
        } else {
            more += 1;
        }
    }
    if more > 0 {
        ctx.warn(format!("printf: ... and {more} more lines"));
    }
}
