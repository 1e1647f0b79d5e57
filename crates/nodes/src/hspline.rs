//! Hierarchical spline surfaces as a node: a base surface, whole-level and
//! local refinements, and edits given as parameters (so they can be
//! keyframed, which the thesis's host could not do), tessellated from the
//! finest level.

use geode_geo::glam::DVec3;
use geode_op::{
    CookContext, CookError, FnOperator, ListSpec, NodeSpec, ParamDefault as D, ParamSpec as P,
    ParamType as T, ParamValue, Params, Registry, Value,
};
use geode_spline::hspline::{file, Hspline, HsplineError, Topology};
use geode_spline::skin::SkinMethod;

use crate::skin::{posed_skeleton, skeleton_from_params, BEND, BEND_JOINT, POSE, SKELETON};

use crate::util::geometry;

const HSPLINE_TOPOLOGY: P = P::new(
    "topology",
    "Topology",
    T::Menu(&["plane", "cylinder", "torus"]),
    D::Str("plane"),
    "Plane (open), cylinder (wrapped around) or torus (wrapped both ways).",
);
const HSPLINE_ROWS: P = P::new(
    "rows",
    "Rows",
    T::Int,
    D::Int(6),
    "Base control vertices along u.",
)
.range(4.0, 4096.0);
const HSPLINE_COLUMNS: P = P::new(
    "columns",
    "Columns",
    T::Int,
    D::Int(6),
    "Base control vertices along v.",
)
.range(4.0, 4096.0);
const HSPLINE_SIZE: P = P::new("size", "Size", T::Vec2, D::Vec2([2.0, 2.0]), "Plane extent in X and Z; cylinder diameter and height; torus outer diameter and tube diameter.");
const HSPLINE_LEVELS: P = P::new(
    "levels",
    "Levels",
    T::Int,
    D::Int(1),
    "Whole-surface refinements.",
)
.range(0.0, 6.0);
const HSPLINE_REGION: P = P::new("region", "Local region", T::Vec4, D::Vec4([0.0; 4]), "u0 u1 v0 v1 (vertex indices of the finest level): refine once more there; zeros: no local level.");
const HSPLINE_EDIT_LEVEL: P = P::new(
    "edit_level",
    "Edit level",
    T::Int,
    D::Int(0),
    "Level of the animatable edit.",
)
.range(0.0, 16.0);
const HSPLINE_EDIT_VERTEX: P = P::new(
    "edit_vertex",
    "Edit vertex",
    T::Vec2,
    D::Vec2([0.0, 0.0]),
    "i j of the animatable edit.",
);
const HSPLINE_EDIT_MOVE: P = P::new(
    "edit_move",
    "Edit move",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "World vector the vertex moves by (zero: no edit).",
);
const HSPLINE_EDITS: P = P::list(
    "edits",
    "More edits",
    &EDIT_ROWS,
    "Further control-vertex moves, each row keyframable.",
);
const HSPLINE_SYMMETRIC: P = P::new("symmetric", "Symmetric", T::Toggle, D::Toggle(false), "Mirror every edit across X = 0 (plane, cylinder or torus; wrapped directions need an even vertex count).");
const HSPLINE_SAMPLES: P = P::new(
    "samples",
    "Samples",
    T::Vec2,
    D::Vec2([48.0, 48.0]),
    "Tessellation samples along u and v.",
)
.range(3.0, 10_000.0);
const HSPLINE_OUTPUT: P = P::new("output", "Output", T::Menu(&["polygons", "patch"]), D::Str("polygons"), "Tessellated quads, or the finest level as one cubic B-spline patch primitive (its control points as points; a wrapped side closes on the same points), which transforms and merges keep exact.");
const HSPLINE_LOAD: P = P::new("load", "Load .hs", T::File, D::Str(""), "Start from the hierarchy in this .hs file (docs/hs-format.md) instead of the base surface; refinements and edits apply on top. `$HIP` is the network's folder.");
const HSPLINE_SAVE: P = P::new(
    "save",
    "Save .hs",
    T::File,
    D::Str(""),
    "Write the hierarchy (after refinements and edits) to this .hs file, atomically.",
);
const HSPLINE_OPTIMIZE: P = P::new(
    "optimize",
    "Optimize for space",
    T::Toggle,
    D::Toggle(true),
    "Leave zero offsets out of the saved file.",
);
const HSPLINE_ENVELOPE: P = P::new("envelope", "Envelope", T::Menu(&["none", "linear", "dual_quaternion", "from_file"]), D::Str("none"), "Skin the surface with the skeleton: linear blend or dual quaternions (weights automatic from the distance to the bones; skeleton and weights are saved in the .hs file), or with the skeleton, weights, level and method of the loaded .hs file (posed by `pose` and `bend`).");
const HSPLINE_ENVELOPE_LEVEL: P = P::new("envelope_level", "Envelope level", T::Int, D::Int(0), "The level whose control vertices are skinned; finer offsets then follow in the deformed frames (the finest level or above: no hierarchy effect).").range(0.0, 16.0);

static HSPLINE: NodeSpec = NodeSpec::new(
    "hspline",
    "Hierarchical Spline",
    "spline",
    "A hierarchical bicubic B-spline surface (Forsey and Bartels): a plane, cylinder or torus of rows x columns control vertices, refined `levels` times everywhere and optionally once more over a region; edits move control vertices by world vectors, stored as offsets in the coarser surface's local frame so detail follows coarser edits. One edit has its own animatable parameters; more are rows of the list parameter `edits`. With `symmetric` every edit is mirrored across X = 0. Output: the finest level as quads with N and uv, carrying the hierarchy (a typed payload, checked against the points) for the attach node when it is not enveloped.",
    &[],
    &[
        HSPLINE_TOPOLOGY,
        HSPLINE_ROWS,
        HSPLINE_COLUMNS,
        HSPLINE_SIZE,
        HSPLINE_LEVELS,
        HSPLINE_REGION,
        HSPLINE_EDIT_LEVEL,
        HSPLINE_EDIT_VERTEX,
        HSPLINE_EDIT_MOVE,
        HSPLINE_EDITS,
        HSPLINE_SYMMETRIC,
        HSPLINE_SAMPLES,
        HSPLINE_OUTPUT,
        HSPLINE_LOAD,
        HSPLINE_SAVE,
        HSPLINE_OPTIMIZE,
        HSPLINE_ENVELOPE,
        HSPLINE_ENVELOPE_LEVEL,
        SKELETON,
        POSE,
        BEND_JOINT,
        BEND,
    ],
)
.writes(&[&HSPLINE_SAVE]);

/// An edit row: which control vertex of which level moves, and by how much.
const EDIT_LEVEL: P = P::new(
    "level",
    "Level",
    T::Int,
    D::Int(0),
    "The level whose control vertex moves.",
)
.range(0.0, 16.0);

const EDIT_VERTEX: P = P::new(
    "vertex",
    "Vertex",
    T::Vec2,
    D::Vec2([0.0, 0.0]),
    "i j of the control vertex (u, v).",
)
.at_least(0.0);

const EDIT_MOVE: P = P::new(
    "move",
    "Move",
    T::Vec3,
    D::Vec3([0.0; 3]),
    "World vector the vertex moves by (keyframable).",
);

static EDIT_ROWS: ListSpec = ListSpec {
    fields: &[EDIT_LEVEL, EDIT_VERTEX, EDIT_MOVE],
    legacy: Some(legacy_edits),
};

type Edit = (usize, usize, usize, DVec3);

/// Old networks: `level i j dx dy dz` entries separated by `;`.
fn legacy_edits(text: &str) -> Result<Vec<Vec<ParamValue>>, String> {
    crate::util::legacy_rows(text, "edit", "`level i j dx dy dz`", |w| {
        let int = |s: &str| s.parse::<usize>().ok().map(|x| x as f64);
        let num = crate::util::finite;
        match *w {
            [l, i, j, x, y, z] => Some(vec![
                ParamValue::Int(int(l)? as i64),
                ParamValue::Vector(vec![int(i)?, int(j)?]),
                ParamValue::Vector(vec![num(x)?, num(y)?, num(z)?]),
            ]),
            _ => None,
        }
    })
}

/// The edit rows with their parameter names (for errors).
fn edits(p: &Params) -> Result<Vec<(Edit, String)>, CookError> {
    p.list(&HSPLINE_EDITS)?
        .iter()
        .map(|row| {
            let [i, j] = row.vector::<2>(&EDIT_VERTEX)?.map(|x| x.max(0.0) as usize);
            let mv = DVec3::from_array(row.vector::<3>(&EDIT_MOVE)?);
            Ok((
                (row.int(&EDIT_LEVEL)? as usize, i, j, mv),
                row.name(&EDIT_MOVE),
            ))
        })
        .collect()
}

fn cook_hspline_node(
    ctx: &CookContext,
    _: &[Option<Value>],
    p: &Params,
) -> Result<Value, CookError> {
    let topology = match p.string(&HSPLINE_TOPOLOGY)? {
        "cylinder" => Topology::Cylinder,
        "torus" => Topology::Torus,
        _ => Topology::Plane,
    };
    let err = |e: HsplineError| ctx.kernel(e);
    let [sx, sy] = p.vector::<2>(&HSPLINE_SIZE)?;
    let load = p.string(&HSPLINE_LOAD)?;
    let mut h = if load.is_empty() {
        Hspline::new(
            topology,
            p.int(&HSPLINE_ROWS)? as usize,
            p.int(&HSPLINE_COLUMNS)? as usize,
            [sx, sy],
        )
        .map_err(err)?
    } else {
        let text = crate::util::text_file(ctx, &HSPLINE_LOAD, load)?;
        file::load(&text).map_err(|e| {
            ctx.param_error(&HSPLINE_LOAD, format!("{load}: {e}"))
                .with_source(e)
        })?
    };
    for _ in 0..p.int(&HSPLINE_LEVELS)? {
        ctx.check()?;
        h.refine(None).map_err(err)?;
    }
    let [u0, u1, v0, v1] = p.vector::<4>(&HSPLINE_REGION)?.map(|x| x.max(0.0) as usize);
    if u1 > u0 && v1 > v0 {
        h.refine(Some(((u0, u1), (v0, v1))))
            .map_err(|e| ctx.kernel_at(&HSPLINE_REGION, e))?;
    }
    let mut edits = edits(p)?;
    let mv = p.vector::<3>(&HSPLINE_EDIT_MOVE)?;
    if mv != [0.0; 3] {
        let [i, j] = p
            .vector::<2>(&HSPLINE_EDIT_VERTEX)?
            .map(|x| x.max(0.0) as usize);
        let level = p.int(&HSPLINE_EDIT_LEVEL)? as usize;
        edits.insert(
            0,
            ((level, i, j, DVec3::from_array(mv)), "edit_move".into()),
        );
    }
    let symmetric = p.toggle(&HSPLINE_SYMMETRIC)?;
    for ((level, i, j, d), param) in edits {
        h.move_cv(level, i, j, d)
            .map_err(|e| ctx.kernel(e).at_param(&param))?;
        if symmetric {
            // The vertex across X = 0: a plane's columns run along X; a
            // cylinder's or torus's vertices go round Y from +X, so the
            // mirror of angle a is pi - a.
            let (nu, nv) = h.grid_size(level).map_err(err)?;
            let (mi, mj) = if h.topology == Topology::Plane {
                (nu - 1 - i, j)
            } else if nv % 2 == 0 {
                (i, (nv / 2 + nv - j % nv) % nv)
            } else {
                return Err(ctx.param_error(
                    &HSPLINE_SYMMETRIC,
                    format!(
                        "level {level} has {nv} vertices around: mirroring needs an even count"
                    ),
                ));
            };
            if (mi, mj) != (i, j) {
                h.move_cv(level, mi, mj, DVec3::new(-d.x, d.y, d.z))
                    .map_err(|e| ctx.kernel_at(&HSPLINE_SYMMETRIC, e))?;
            }
        }
    }
    // Enveloping: the skeleton and weights join the hierarchy (and its
    // .hs file); the pose comes from the parameters.
    let finest = h.levels() - 1;
    let motions = match p.string(&HSPLINE_ENVELOPE)? {
        "none" => None,
        "from_file" => {
            let Some(e) = &h.envelope else {
                return Err(ctx.param_error(
                    &HSPLINE_ENVELOPE,
                    "`from_file` needs a loaded .hs file with enveloping data",
                ));
            };
            Some(posed_skeleton(ctx, p, &e.joints)?.motions())
        }
        method => {
            let skeleton = skeleton_from_params(ctx, p)?;
            let method = if method == "linear" {
                SkinMethod::Linear
            } else {
                SkinMethod::DualQuaternion
            };
            h.set_envelope(p.int(&HSPLINE_ENVELOPE_LEVEL)? as usize, method, &skeleton);
            Some(skeleton.motions())
        }
    };
    let save = p.string(&HSPLINE_SAVE)?;
    if !save.is_empty() {
        let text = file::save(&h, p.toggle(&HSPLINE_OPTIMIZE)?);
        ctx.check()?;
        let path = std::path::Path::new(save);
        geode_io::write_atomic(path, |w| {
            w.write_all(text.as_bytes())
                .map_err(|e| geode_io::IoError::os(path, e))
        })
        .map_err(|e| ctx.io(&HSPLINE_SAVE, e))?;
    }
    let [su, sv] = p.vector::<2>(&HSPLINE_SAMPLES)?;
    crate::util::reserve_mesh(ctx, &HSPLINE_SAMPLES, su * sv, 4.0 * su * sv, su * sv)?;
    let enveloped = motions.is_some();
    let grid = match motions {
        None => h.grid(finest).map_err(err)?,
        Some(m) => h.enveloped_grid(&m).map_err(err)?,
    };
    if p.string(&HSPLINE_OUTPUT)? == "patch" {
        let (indices, basis) = h.patch_layout(&grid);
        let mut g = geode_geo::Geometry::new();
        g.add_points(&grid.points.iter().map(|q| q.as_vec3()).collect::<Vec<_>>());
        g.add_patch(&indices, basis).map_err(|e| ctx.kernel(e))?;
        return geometry(g);
    }
    let t = h.tessellate_grid(&grid, su as usize, sv as usize);
    let mut g = t.into_geometry().map_err(|e| ctx.kernel(e))?;
    if !enveloped {
        crate::attach::carry_hierarchy(&mut g, &h).map_err(|e| ctx.kernel(e))?;
    }
    geometry(g)
}

fn key_hspline_node(ctx: &geode_op::KeyContext, p: &Params) -> Result<Option<u128>, CookError> {
    // The loaded file's content is part of the key: editing it recooks.
    Ok(ctx.file_hash(p.string(&HSPLINE_LOAD)?))
}

pub fn register(r: &mut Registry) {
    r.add(FnOperator {
        spec: &HSPLINE,
        cook: cook_hspline_node,
        key_extra: Some(key_hspline_node),
    });
}
