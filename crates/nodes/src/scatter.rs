//! Scatter nodes: seeded points inside a closed mesh (winding number), on
//! its surface (by area), or inside a field (f >= 0); uniform or blue noise
//! (sample elimination), exact in count.

use geode_geo::glam::Vec3;
use geode_geo::{ops, AttribClass, AttribData, Attribute, Geometry, TypeInfo};
use geode_growth::scatter::{self, ScatterError};
use geode_growth::InsideTest;
use geode_mesher::polygonise::sample as sample_field;
use geode_op::{
    geometry_input, CookContext, CookError, InputSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, PortType, Registry, Value,
};
use rayon::prelude::*;

use crate::util::{geometry, input, vec3};

const COUNT: P = P::new(
    "count",
    "Count",
    T::Int,
    D::Int(1000),
    "Exact number of points.",
)
.range(0.0, 100_000_000.0);
const SEED: P = P::new(
    "seed",
    "Seed",
    T::Int,
    D::Int(0),
    "Random seed: the same seed gives the same points on any machine and thread count.",
);
const DENSITY: P = P::new(
    "density",
    "Density",
    T::Float,
    D::Float(0.0),
    "Points per unit volume (inside) or area (surface); when above 0 it sets the count.",
)
.at_least(0.0);
const RELAX: P = P::new("relax", "Blue noise", T::Toggle, D::Toggle(false), "Spread the points evenly (five times the candidates, the most crowded removed one by one) instead of uniform random.");

/// Blue noise keeps `count` of five times as many candidates.
const OVERSAMPLE: usize = 5;

fn scatter_error(ctx: &CookContext, e: ScatterError) -> CookError {
    match e {
        ScatterError::Cancelled => CookError::cancelled(ctx.path),
        other => ctx.kernel(other),
    }
}

fn points(pts: Vec<Vec3>) -> Result<Value, CookError> {
    let mut g = Geometry::new();
    g.set_positions(pts);
    geometry(g)
}

/// The point count: `density` x the measure (volume or area) when density
/// is set, else `count`.
fn target_count(
    ctx: &CookContext,
    p: &Params,
    measure: impl FnOnce() -> f64,
) -> Result<usize, CookError> {
    let density = p.float(&DENSITY)?;
    let (n, param) = if density <= 0.0 {
        (p.int(&COUNT)? as f64, &COUNT)
    } else {
        let n = (density * measure()).round();
        if !(0.0..=1e8).contains(&n) {
            return Err(ctx.param_error(&DENSITY, format!("gives {n} points; at most 100000000")));
        }
        (n, &DENSITY)
    };
    // Each point's position and normal, and with relax its candidates'
    // positions and neighbour lists.
    let mut bytes = n * 24.0;
    if p.toggle(&RELAX)? {
        bytes += n * OVERSAMPLE as f64 * (16.0 + scatter::BYTES_PER_CANDIDATE);
    }
    ctx.reserve(param, bytes, &format!("scattering {n} points"))?;
    Ok(n as usize)
}

/// The share of the box `lo..hi` that passes `test`, from a fixed probe of
/// candidates (seeded apart from the scatter's own).
fn probe_share(lo: Vec3, hi: Vec3, seed: u64, test: &(dyn Fn(&[Vec3]) -> Vec<bool> + Sync)) -> f64 {
    const PROBE: u64 = 1 << 16;
    let probe_seed = seed ^ 0x005E_ED0F_DE45_17E5;
    let cands: Vec<Vec3> = (0..PROBE)
        .map(|i| scatter::candidate(lo, hi, probe_seed, i))
        .collect();
    test(&cands).into_iter().filter(|&b| b).count() as f64 / PROBE as f64
}

/// Points inside a solid given by its bounds and an inside test.
fn inside(
    ctx: &CookContext,
    p: &Params,
    lo: Vec3,
    hi: Vec3,
    test: &(dyn Fn(&[Vec3]) -> Vec<bool> + Sync),
    count: usize,
) -> Result<Vec<Vec3>, CookError> {
    let seed = p.int(&SEED)? as u64;
    let relax = p.toggle(&RELAX)?;
    let wanted = if relax { count * OVERSAMPLE } else { count };
    let cancel = || ctx.cancel.is_cancelled();
    let (cands, share) =
        scatter::inside(lo, hi, wanted, seed, test, &cancel).map_err(|e| scatter_error(ctx, e))?;
    if !relax {
        return Ok(cands);
    }
    let volume = (hi - lo).as_dvec3().element_product() * share;
    Ok(scatter::eliminate(&cands, count, volume, 3, &cancel)
        .map_err(|e| scatter_error(ctx, e))?
        .into_iter()
        .map(|i| cands[i])
        .collect())
}

const SCATTER_MODE: P = P::new(
    "mode",
    "Mode",
    T::Menu(&["inside", "surface"]),
    D::Str("inside"),
    "Fill the solid or cover the surface.",
);

static SCATTER: NodeSpec = NodeSpec::new(
    "scatter",
    "Scatter",
    "scatter",
    "Seeded points inside a closed polygon mesh (its winding number decides, so holes and nested shells count right) or on its surface (uniform by area, with the face normal as N).",
    &[geometry_input("geometry")],
    &[
        SCATTER_MODE,
        COUNT,
        DENSITY,
        SEED,
        RELAX,
    ],
);

fn cook_scatter(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let g = input(ctx, inputs, 0)?;
    let tris = geode_growth::inside::triangles(g);
    if tris.is_empty() {
        return Err(ctx.input_error("input 1 has no polygons to scatter in or on"));
    }
    if p.string(&SCATTER_MODE)? == "inside" {
        let b = ops::bounds(g).ok_or_else(|| ctx.input_error("input 1 is empty"))?;
        let count = target_count(ctx, p, || ops::signed_volume(g).abs() as f64)?;
        let test = InsideTest::new(tris);
        let pts = inside(
            ctx,
            p,
            b.min,
            b.max,
            &|c: &[Vec3]| c.par_iter().map(|q| test.contains(*q)).collect(),
            count,
        )?;
        return points(pts);
    }
    let count = target_count(ctx, p, || scatter::area(&tris))?;
    let seed = p.int(&SEED)? as u64;
    let relax = p.toggle(&RELAX)?;
    let wanted = if relax { count * OVERSAMPLE } else { count };
    let cancel = || ctx.cancel.is_cancelled();
    let mut found =
        scatter::on_surface(&tris, wanted, seed, &cancel).map_err(|e| scatter_error(ctx, e))?;
    if relax {
        let keep = scatter::eliminate(&found.positions, count, scatter::area(&tris), 2, &cancel)
            .map_err(|e| scatter_error(ctx, e))?;
        found = scatter::SurfacePoints {
            positions: keep.iter().map(|&i| found.positions[i]).collect(),
            triangles: keep.iter().map(|&i| found.triangles[i]).collect(),
        };
    }
    let faces: Vec<Vec3> = tris
        .par_iter()
        .map(|t| (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero())
        .collect();
    let normals = found
        .triangles
        .par_iter()
        .with_min_len(1 << 14)
        .map(|&t| faces[t as usize])
        .collect();
    drop(found.triangles);
    let mut out = Geometry::new();
    out.set_positions(found.positions);
    out.set_attrib(
        AttribClass::Point,
        "N",
        Attribute::from_data(AttribData::Vec3(normals), TypeInfo::Normal),
    )
    .map_err(|e| ctx.kernel(e))?;
    geometry(out)
}

static SCATTER_FIELD: NodeSpec = NodeSpec::new(
    "scatter_field",
    "Scatter in Field",
    "scatter",
    "Seeded points where a field is >= 0 (inside its solid), within a box.",
    &[InputSpec {
        name: "field",
        ty: PortType::Field,
        required: true,
    }],
    &[
        crate::frep_polygonise::BOUNDS_MIN,
        crate::frep_polygonise::BOUNDS_MAX,
        COUNT,
        DENSITY,
        SEED,
        RELAX,
    ],
);

fn cook_scatter_field(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let f = inputs
        .first()
        .and_then(|v| v.as_ref())
        .and_then(|v| v.as_field())
        .ok_or_else(|| ctx.input_error("input 1 needs a field"))?;
    let (lo, hi) = (
        vec3(p, &crate::frep_polygonise::BOUNDS_MIN)?,
        vec3(p, &crate::frep_polygonise::BOUNDS_MAX)?,
    );
    if (hi - lo).cmple(Vec3::ZERO).any() {
        return Err(ctx.param_error(
            &crate::frep_polygonise::BOUNDS_MAX,
            "the box is empty: max must exceed min on every axis",
        ));
    }
    let test =
        |c: &[Vec3]| -> Vec<bool> { sample_field(f, c).into_iter().map(|v| v >= 0.0).collect() };
    let seed = p.int(&SEED)? as u64;
    let count = target_count(ctx, p, || {
        (hi - lo).as_dvec3().element_product() * probe_share(lo, hi, seed, &test)
    })?;
    let pts = inside(ctx, p, lo, hi, &test, count)?;
    points(pts)
}

pub fn register(r: &mut Registry) {
    r.node(&SCATTER, cook_scatter);
    r.node(&SCATTER_FIELD, cook_scatter_field);
}
