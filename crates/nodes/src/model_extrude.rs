//! The polyextrude node: faces extruded (connected or one by one, with
//! inset, divisions, twist and front scale) and curves extruded into
//! strips (geode-model's `extrude`).

use geode_geo::AttribClass;
use geode_model::extrude::{extrude, Extrude};
use geode_model::ModelError;
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, group_param, input, vec3};

const GROUP: P = P::new(
    "group",
    "Group",
    T::String,
    D::Str(""),
    "The primitives to extrude: a group's name or a pattern (`0-3`, `@side==2`); empty for all.",
);
const DISTANCE: P = P::new(
    "distance",
    "Distance",
    T::Float,
    D::Float(0.1),
    "How far the front moves along its direction (negative: inward).",
);
const INSET: P = P::new(
    "inset",
    "Inset",
    T::Float,
    D::Float(0.0),
    "How far each outline edge of the front moves inward in its plane.",
);
const DIVISIONS: P = P::new(
    "divisions",
    "Divisions",
    T::Int,
    D::Int(1),
    "Rings of the walls.",
)
.range(1.0, 1024.0);
const TWIST: P = P::new(
    "twist",
    "Twist",
    T::Float,
    D::Float(0.0),
    "Degrees the front turns about its piece's normal.",
);
const FRONT_SCALE: P = P::new(
    "front_scale",
    "Front scale",
    T::Float,
    D::Float(1.0),
    "Scale of the front about its piece's centre.",
);
const CONNECTED: P = P::new(
    "connected",
    "Keep shared edges together",
    T::Toggle,
    D::Toggle(true),
    "Faces sharing edges extrude as one piece (each point along the mean normal of its faces); off: every face on its own.",
);
const OUTPUT_FRONT: P = P::new(
    "output_front",
    "Output front",
    T::Toggle,
    D::Toggle(true),
    "Keep the moved faces (group extrudeFront).",
);
const OUTPUT_BACK: P = P::new(
    "output_back",
    "Output back",
    T::Toggle,
    D::Toggle(false),
    "Keep the original faces, reversed (group extrudeBack): an open surface becomes a solid.",
);
const DISTANCE_ATTRIB: P = P::new(
    "distance_attrib",
    "Distance scale attribute",
    T::String,
    D::Str(""),
    "A point float attribute multiplying each point's distance (empty: none).",
);
const DIRECTION: P = P::new(
    "direction",
    "Curve direction",
    T::Vec3,
    D::Vec3([0.0, 1.0, 0.0]),
    "The direction a curve without point normals (N) extrudes along.",
);

static POLYEXTRUDE: NodeSpec = NodeSpec::new(
    "polyextrude",
    "PolyExtrude",
    "model",
    "Extrudes polygons (their front moves along the normal, walls join the outline to it) and polylines (into strips along N or a direction). Groups extrudeFront, extrudeSide, extrudeBack. Walls take their face's primitive attributes and their edge's vertex attributes; new points their source point's. Unlike Houdini, the wall's UVs are the edge's (not laid out along the walls), and inset and distance are one step (Houdini's too), not Blender's separate inset.",
    &[geometry_input("geometry")],
    &[GROUP, DISTANCE, INSET, DIVISIONS, TWIST, FRONT_SCALE, CONNECTED, OUTPUT_FRONT, OUTPUT_BACK, DISTANCE_ATTRIB, DIRECTION],
);

fn cook_polyextrude(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let group = group_param(ctx, p, &GROUP, g, AttribClass::Primitive)?;
    let how = Extrude {
        distance: p.float(&DISTANCE)? as f32,
        inset: p.float(&INSET)? as f32,
        divisions: p.int(&DIVISIONS)?.clamp(1, 1024) as u32,
        twist: p.float(&TWIST)? as f32,
        front_scale: p.float(&FRONT_SCALE)? as f32,
        connected: p.toggle(&CONNECTED)?,
        output_front: p.toggle(&OUTPUT_FRONT)?,
        output_back: p.toggle(&OUTPUT_BACK)?,
        direction: vec3(p, &DIRECTION)?,
    };
    let name = p.string(&DISTANCE_ATTRIB)?;
    let scale = if name.is_empty() {
        None
    } else {
        let attr = g.attrib(AttribClass::Point, name).ok_or_else(|| {
            ctx.param_error(&DISTANCE_ATTRIB, format!("no point attribute `{name}`"))
        })?;
        Some(attr.as_f32().ok_or_else(|| {
            ctx.param_error(
                &DISTANCE_ATTRIB,
                format!(
                    "point attribute `{name}` is {}, expected a float",
                    attr.attrib_type()
                ),
            )
        })?)
    };
    // Each selected corner makes a point per ring and a wall quad.
    let corners = g.num_vertices() as f64 * how.divisions as f64;
    ctx.reserve(&DIVISIONS, corners * 64.0, "the extrusion")?;
    match extrude(g, group.as_ref(), scale, &how, &ctx.cancel_fn()) {
        Ok(out) => {
            if out.overrun_fronts > 0 {
                ctx.warn(format!(
                    "inset {} is past where the edges of {} front(s) meet: they turn inside out and the result overlaps itself (lower the inset)",
                    how.inset, out.overrun_fronts
                ));
            }
            geometry(out.geometry)
        }
        Err(ModelError::Cancelled) => Err(CookError::cancelled(ctx.path)),
        Err(e) => Err(ctx.kernel(e)),
    }
}

pub fn register(r: &mut Registry) {
    r.node(&POLYEXTRUDE, cook_polyextrude);
}
