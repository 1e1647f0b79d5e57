//! NURBS surfaces as a node: exact quadrics by revolution, or a B-spline
//! patch over the points of an input grid, tessellated with normals and UVs.

use geode_op::{
    CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P, ParamType as T,
    Params, PortType, Registry, Value,
};
use geode_spline::bspline::{Knots, NurbsSurface};

use crate::util::{geometry, vec3};

const NURBS_SHAPE: P = P::new(
    "shape",
    "Shape",
    T::Menu(&["sphere", "cylinder", "torus", "patch"]),
    D::Str("sphere"),
    "Which surface.",
);
const NURBS_RADIUS: P = P::new(
    "radius",
    "Radius",
    T::Float,
    D::Float(1.0),
    "Sphere and cylinder radius; torus major radius.",
)
.at_least(0.0);
const NURBS_MINOR_RADIUS: P = P::new(
    "minor_radius",
    "Minor radius",
    T::Float,
    D::Float(0.25),
    "Torus tube radius.",
)
.at_least(0.0);
const NURBS_HEIGHT: P = P::new(
    "height",
    "Height",
    T::Float,
    D::Float(2.0),
    "Cylinder height (centred).",
)
.at_least(0.0);
const NURBS_ROWS: P = P::new(
    "rows",
    "Rows",
    T::Int,
    D::Int(4),
    "Patch control rows (along u).",
)
.range(2.0, 100_000.0);
const NURBS_COLUMNS: P = P::new(
    "columns",
    "Columns",
    T::Int,
    D::Int(4),
    "Patch control columns (along v).",
)
.range(2.0, 100_000.0);
const NURBS_DEGREE: P = P::new(
    "degree",
    "Degree",
    T::Int,
    D::Int(3),
    "Patch degree in both directions (clamped to the control counts).",
)
.range(1.0, 10.0);
const NURBS_SAMPLES: P = P::new(
    "samples",
    "Samples",
    T::Vec2,
    D::Vec2([33.0, 65.0]),
    "Tessellation samples along u and v.",
)
.range(2.0, 10_000.0);
const NURBS_CENTER: P = P::new("center", "Center", T::Vec3, D::Vec3([0.0; 3]), "Offset.");
const NURBS_OUTPUT: P = P::new("output", "Output", T::Menu(&["polygons", "patch"]), D::Str("polygons"), "Tessellated quads, or one spline patch primitive (control points as points, weights in `Pw`) that transforms and merges keep exact; the convert node or `geode cook` tessellates it.");

static NURBS: NodeSpec = NodeSpec::new(
    "nurbs_surface",
    "NURBS Surface",
    "spline",
    "A NURBS surface tessellated into quads with exact normals N and parametric uv: an exact sphere, cylinder or torus (rational circles revolved about +Y), or a clamped B-spline patch with the input's points as its control grid (`rows` x `columns`, in point order).",
    &[InputSpec { name: "control grid", ty: PortType::Geometry, required: false }],
    &[
        NURBS_SHAPE,
        NURBS_RADIUS,
        NURBS_MINOR_RADIUS,
        NURBS_HEIGHT,
        NURBS_ROWS,
        NURBS_COLUMNS,
        NURBS_DEGREE,
        NURBS_SAMPLES,
        NURBS_CENTER,
        NURBS_OUTPUT,
    ],
);

fn cook_nurbs(ctx: &CookContext, inputs: &[Option<Value>], p: &Params) -> Result<Value, CookError> {
    let (r, minor, h) = (
        p.float(&NURBS_RADIUS)?,
        p.float(&NURBS_MINOR_RADIUS)?,
        p.float(&NURBS_HEIGHT)?,
    );
    let surface = match p.string(&NURBS_SHAPE)? {
        "cylinder" => NurbsSurface::cylinder(r, h),
        "torus" => NurbsSurface::torus(r, minor),
        "patch" => {
            let grid = inputs
                .first()
                .and_then(|v| v.as_ref())
                .and_then(|v| v.as_geometry())
                .ok_or_else(|| ctx.input_error("a patch needs its control grid on input 1"))?;
            let (rows, cols) = (
                p.int(&NURBS_ROWS)? as usize,
                p.int(&NURBS_COLUMNS)? as usize,
            );
            if grid.num_points() != rows * cols {
                return Err(ctx.param_error(
                    &NURBS_ROWS,
                    format!(
                        "rows x columns = {} but input 1 has {} points",
                        rows * cols,
                        grid.num_points()
                    ),
                ));
            }
            let degree = p.int(&NURBS_DEGREE)? as usize;
            let (du, dv) = (degree.min(rows - 1), degree.min(cols - 1));
            let points = grid
                .positions()
                .iter()
                .map(|q| q.as_dvec3().extend(1.0))
                .collect();
            NurbsSurface::new(
                Knots::clamped_uniform(du, rows),
                Knots::clamped_uniform(dv, cols),
                points,
            )
            .map_err(|e| ctx.kernel(e))?
        }
        _ => NurbsSurface::sphere(r),
    };
    let offset = vec3(p, &NURBS_CENTER)?;
    if p.string(&NURBS_OUTPUT)? == "patch" {
        let mut surface = surface;
        let shift = offset.as_dvec3();
        for h in surface.points.iter_mut() {
            *h += (shift * h.w).extend(0.0);
        }
        let mut g = geode_geo::Geometry::new();
        geode_spline::bspline::patch::add_patch(&mut g, &surface).map_err(|e| ctx.kernel(e))?;
        return geometry(g);
    }
    let [su, sv] = p.vector::<2>(&NURBS_SAMPLES)?;
    crate::util::reserve_mesh(ctx, &NURBS_SAMPLES, su * sv, 4.0 * su * sv, su * sv)?;
    let t = surface.tessellate(su as usize, sv as usize);
    let mut t = t;
    t.positions.iter_mut().for_each(|q| *q += offset);
    geometry(t.into_geometry().map_err(|e| ctx.kernel(e))?)
}

pub fn register(r: &mut Registry) {
    r.node(&NURBS, cook_nurbs);
}
