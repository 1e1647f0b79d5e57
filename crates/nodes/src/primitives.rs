//! Mesh primitive nodes: box, sphere, grid, tube, torus (with divisions and a centre).

use geode_geo::analytic::{self, AnalyticShape};
use geode_geo::glam::{Mat4, Vec2, Vec3};
use geode_geo::{ops, primitives, Geometry};
use geode_op::{
    CookContext, CookError, NodeSpec, ParamDefault as D, ParamName, ParamSpec as P, ParamType as T,
    Params, Registry, Value,
};

use crate::util::{geometry, reserve_mesh, vec2, vec3};

const CENTER: P = P::new(
    "center",
    "Center",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "Where the primitive is centred.",
);

fn placed(mut g: Geometry, center: Vec3) -> Geometry {
    if center != Vec3::ZERO {
        ops::transform(&mut g, Mat4::from_translation(center));
    }
    g
}

const ANALYTIC: P = P::new(
    "analytic",
    "Analytic",
    T::Toggle,
    D::Toggle(false),
    "Tag the polygons with the exact solid they approximate (primitive attributes analytic_*), so frep_from_primitives can use this mesh as an FRep input.",
)
.not_animatable();

/// Places the mesh at its centre, tagged with its exact solid when asked.
fn finish(
    ctx: &CookContext,
    mut g: Geometry,
    p: &Params,
    shape: AnalyticShape,
) -> Result<Value, CookError> {
    if p.toggle(&ANALYTIC)? {
        analytic::tag(&mut g, shape).map_err(|e| ctx.kernel(e))?;
    }
    geometry(placed(g, vec3(p, &CENTER)?))
}

fn div(p: &Params, name: &(impl ParamName + ?Sized)) -> Result<u32, CookError> {
    Ok(p.int(name)?.clamp(1, 1 << 16) as u32)
}

/// Refuses a grid of `columns` x `rows` quads (times `copies`) that the
/// memory budget cannot hold, blaming the larger parameter.
fn reserve_quads(
    ctx: &CookContext,
    p: &Params,
    (columns, rows): (&P, &P),
    copies: f64,
) -> Result<(), CookError> {
    let (c, r) = (div(p, columns)? as f64, div(p, rows)? as f64);
    let param = if c >= r { columns } else { rows };
    let quads = c * r * copies;
    reserve_mesh(
        ctx,
        param,
        (c + 1.0) * (r + 1.0) * copies,
        4.0 * quads,
        quads,
    )
}

const BOX_SIZE: P = P::new(
    "size",
    "Size",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Edge lengths along X, Y and Z.",
)
.at_least(0.0);
const BOX_DIVISIONS: P = P::new(
    "divisions",
    "Divisions",
    T::Vec3,
    D::Vec3([1.0; 3]),
    "Quads along each axis (rounded).",
)
.range(1.0, 4096.0);

static BOX: NodeSpec = NodeSpec::new(
    "box",
    "Box",
    "primitive",
    "An axis-aligned box of closed quads; each face is divided into a grid and shared edges share points.",
    &[],
    &[
        BOX_SIZE,
        CENTER,
        BOX_DIVISIONS,
        ANALYTIC,
    ],
);

fn cook_box_node(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let d = p.vector::<3>(&BOX_DIVISIONS)?.map(|x| x.round() as u32);
    let [x, y, z] = d.map(f64::from);
    let quads = 2.0 * (x * y + y * z + x * z);
    reserve_mesh(ctx, &BOX_DIVISIONS, quads + 2.0, 4.0 * quads, quads)?;
    let size = vec3(p, &BOX_SIZE)?;
    finish(
        ctx,
        primitives::box_mesh(size, d),
        p,
        AnalyticShape::Box {
            size: size.to_array(),
        },
    )
}

const SPHERE_RADIUS: P = P::new(
    "radius",
    "Radius",
    T::Float,
    D::Float(1.0),
    "Sphere radius.",
)
.at_least(0.0);
const SPHERE_ROWS: P =
    P::new("rows", "Rows", T::Int, D::Int(16), "Latitude bands.").range(2.0, 65536.0);
const SPHERE_COLUMNS: P = P::new(
    "columns",
    "Columns",
    T::Int,
    D::Int(32),
    "Longitude segments.",
)
.range(3.0, 65536.0);

static SPHERE: NodeSpec = NodeSpec::new(
    "sphere",
    "Sphere",
    "primitive",
    "A closed UV sphere: quads, with triangle fans at the poles.",
    &[],
    &[SPHERE_RADIUS, CENTER, SPHERE_ROWS, SPHERE_COLUMNS, ANALYTIC],
);

fn cook_sphere(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let radius = p.float(&SPHERE_RADIUS)? as f32;
    reserve_quads(ctx, p, (&SPHERE_COLUMNS, &SPHERE_ROWS), 1.0)?;
    let g = primitives::uv_sphere(radius, div(p, &SPHERE_COLUMNS)?, div(p, &SPHERE_ROWS)?);
    finish(ctx, g, p, AnalyticShape::Sphere { radius })
}

const GRID_SIZE: P = P::new(
    "size",
    "Size",
    T::Vec2,
    D::Vec2([10.0, 10.0]),
    "Extent along X and Z.",
)
.at_least(0.0);
const GRID_ROWS: P =
    P::new("rows", "Rows", T::Int, D::Int(10), "Quads along Z.").range(1.0, 65536.0);
const GRID_COLUMNS: P =
    P::new("columns", "Columns", T::Int, D::Int(10), "Quads along X.").range(1.0, 65536.0);

static GRID: NodeSpec = NodeSpec::new(
    "grid",
    "Grid",
    "primitive",
    "A grid of quads in the XZ plane facing +Y, with point `uv`.",
    &[],
    &[GRID_SIZE, CENTER, GRID_ROWS, GRID_COLUMNS],
);

fn cook_grid(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    reserve_quads(ctx, p, (&GRID_COLUMNS, &GRID_ROWS), 1.0)?;
    let size: Vec2 = vec2(p, &GRID_SIZE)?;
    geometry(placed(
        primitives::grid(size, div(p, &GRID_COLUMNS)?, div(p, &GRID_ROWS)?),
        vec3(p, &CENTER)?,
    ))
}

const TUBE_RADIUS: P =
    P::new("radius", "Radius", T::Float, D::Float(0.5), "Tube radius.").at_least(0.0);
const TUBE_HEIGHT: P = P::new(
    "height",
    "Height",
    T::Float,
    D::Float(1.0),
    "Length along Y.",
);
const TUBE_ROWS: P = P::new(
    "rows",
    "Rows",
    T::Int,
    D::Int(1),
    "Segments along the height.",
)
.range(1.0, 65536.0);
const TUBE_COLUMNS: P =
    P::new("columns", "Columns", T::Int, D::Int(24), "Segments around.").range(3.0, 65536.0);
const TUBE_CAPS: P = P::new(
    "caps",
    "End caps",
    T::Toggle,
    D::Toggle(true),
    "Close both ends with polygons.",
);

static TUBE: NodeSpec = NodeSpec::new(
    "tube",
    "Tube",
    "primitive",
    "A tube along +Y from the centre, optionally capped (then closed).",
    &[],
    &[
        TUBE_RADIUS,
        TUBE_HEIGHT,
        CENTER,
        TUBE_ROWS,
        TUBE_COLUMNS,
        TUBE_CAPS,
        ANALYTIC,
    ],
);

fn cook_tube(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    reserve_quads(ctx, p, (&TUBE_COLUMNS, &TUBE_ROWS), 1.0)?;
    let (radius, height) = (p.float(&TUBE_RADIUS)? as f32, p.float(&TUBE_HEIGHT)? as f32);
    let g = primitives::tube(
        radius,
        height,
        div(p, &TUBE_COLUMNS)?,
        div(p, &TUBE_ROWS)?,
        p.toggle(&TUBE_CAPS)?,
    );
    finish(
        ctx,
        g,
        p,
        AnalyticShape::Tube {
            radius,
            y0: 0.0,
            y1: height,
        },
    )
}

const TORUS_MAJOR_RADIUS: P = P::new(
    "major_radius",
    "Major radius",
    T::Float,
    D::Float(1.0),
    "Distance from the axis to the tube's centre.",
)
.at_least(0.0);
pub(crate) const TORUS_MINOR_RADIUS: P = P::new(
    "minor_radius",
    "Minor radius",
    T::Float,
    D::Float(0.25),
    "Tube radius.",
)
.at_least(0.0);
const TORUS_ROWS: P = P::new(
    "rows",
    "Rows",
    T::Int,
    D::Int(12),
    "Segments around the tube.",
)
.range(3.0, 65536.0);
const TORUS_COLUMNS: P = P::new(
    "columns",
    "Columns",
    T::Int,
    D::Int(24),
    "Segments around the axis.",
)
.range(3.0, 65536.0);

static TORUS: NodeSpec = NodeSpec::new(
    "torus",
    "Torus",
    "primitive",
    "A closed torus around the Y axis.",
    &[],
    &[
        TORUS_MAJOR_RADIUS,
        TORUS_MINOR_RADIUS,
        CENTER,
        TORUS_ROWS,
        TORUS_COLUMNS,
        ANALYTIC,
    ],
);

fn cook_torus(ctx: &CookContext, _: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (major, minor) = (
        p.float(&TORUS_MAJOR_RADIUS)? as f32,
        p.float(&TORUS_MINOR_RADIUS)? as f32,
    );
    reserve_quads(ctx, p, (&TORUS_COLUMNS, &TORUS_ROWS), 1.0)?;
    let g = primitives::torus(major, minor, div(p, &TORUS_COLUMNS)?, div(p, &TORUS_ROWS)?);
    finish(ctx, g, p, AnalyticShape::Torus { major, minor })
}

pub fn register(r: &mut Registry) {
    r.node(&BOX, cook_box_node);
    r.node(&SPHERE, cook_sphere);
    r.node(&GRID, cook_grid);
    r.node(&TUBE, cook_tube);
    r.node(&TORUS, cook_torus);
}
