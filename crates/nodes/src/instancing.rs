//! Copy to points: the source on every template point by Houdini's
//! instance attributes, as packed instances or real geometry.

use geode_curve::{copy_to_points, CopyOptions};
use geode_op::{
    geometry_input, CookContext, CookError, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, Params, Registry, Value,
};

use crate::util::{geometry, input, reserve_mesh};

const COPY_TO_POINTS_PACK: P = P::new(
    "pack",
    "Pack and instance",
    T::Toggle,
    D::Toggle(true),
    "Packed instances instead of real copies.",
);
const COPY_TO_POINTS_PIECE_ATTRIBUTE: P = P::new("piece_attribute", "Piece attribute", T::String, D::Str(""), "Integer or string primitive attribute splitting the source into pieces (empty: the whole source).");
const COPY_TO_POINTS_VARIANT_ATTRIBUTE: P = P::new(
    "variant_attribute",
    "Variant attribute",
    T::String,
    D::Str("variant"),
    "Integer template point attribute choosing each point's piece (wrapped; absent: point number).",
);

static COPY_TO_POINTS: NodeSpec = NodeSpec::new(
    "copy_to_points",
    "Copy to Points",
    "instancing",
    "A copy of input 1 on every point of input 2, placed by the points' instance attributes as SideFX documents them: moved by -pivot, scaled by scale x pscale, turned by orient (else N as +Z with up as +Y, else v), then by rot, moved to P + trans; a transform matrix replaces scale and rotations. orient and rot are any float4 (a wrangle's vector4 too), N, up, v, scale, trans and pivot any float3, pscale a float or an int; another type under one of these names is an error. Packed copies share one geometry (memory per copy is a transform). Other template point attributes are copied onto the copies.",
    &[geometry_input("source"), geometry_input("template")],
    &[
        COPY_TO_POINTS_PACK,
        COPY_TO_POINTS_PIECE_ATTRIBUTE,
        COPY_TO_POINTS_VARIANT_ATTRIBUTE,
    ],
)
// 2: instance attributes from any column of their width, rot after orient, N alone by the dihedral turn, v.
.version(2);

fn cook_copy_to_points(
    ctx: &CookContext,
    inputs: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let (source, template) = (input(ctx, inputs, 0)?, input(ctx, inputs, 1)?);
    let opts = CopyOptions {
        packed: p.toggle(&COPY_TO_POINTS_PACK)?,
        piece_attrib: p.string(&COPY_TO_POINTS_PIECE_ATTRIBUTE)?.to_owned(),
        variant_attrib: p.string(&COPY_TO_POINTS_VARIANT_ATTRIBUTE)?.to_owned(),
    };
    if !opts.packed {
        let n = template.num_points() as f64;
        reserve_mesh(
            ctx,
            &COPY_TO_POINTS_PACK,
            n * source.num_points() as f64,
            n * source.num_vertices() as f64,
            n * source.num_prims() as f64,
        )?;
    }
    let cancel = || ctx.cancel.is_cancelled();
    let g = copy_to_points(source, template, &opts, &cancel).map_err(|e| match e {
        geode_curve::CopyError::BadPieceAttrib(_) => {
            ctx.kernel_at(&COPY_TO_POINTS_PIECE_ATTRIBUTE, e)
        }
        geode_curve::CopyError::BadVariantAttrib(_) => {
            ctx.kernel_at(&COPY_TO_POINTS_VARIANT_ATTRIBUTE, e)
        }
        other => ctx.kernel(other),
    })?;
    geometry(g)
}

pub fn register(r: &mut Registry) {
    r.node(&COPY_TO_POINTS, cook_copy_to_points);
}
