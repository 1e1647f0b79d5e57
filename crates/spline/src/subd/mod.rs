//! Catmull-Clark subdivision of geode geometry (OpenSubdiv's Catmark rules):
//! reads the OpenSubdiv tags geode-io puts on OBJ meshes (`creaseweight`
//! per vertex, `cornerweight` per point, `subd_hole` per primitive,
//! `subd_boundary` and `subd_creasemethod` on the detail), refines
//! uniformly, and optionally pushes points to the limit surface with exact
//! limit normals.

mod fvar;
mod fvar_linear;
mod fvar_step;
mod level;
mod limit;
#[cfg(test)]
mod opensubdiv_tests;
mod refine;
mod scheme;

use geode_geo::glam::{DVec3, Vec2, Vec3, Vec4};
use geode_geo::{AttribClass, AttribData, Attribute, GeoError, Geometry, PrimKind, TypeInfo};
use rayon::prelude::*;

pub(crate) use fvar::FVarChannel;
pub use fvar::FVarLinear;
pub(crate) use level::Rows;
pub use level::{Level, INFINITE};
pub(crate) use limit::{limit_frame, limit_normals, limit_positions, mean_face_normal};
pub(crate) use refine::{
    plan, refine_topology, refine_topology_with, refine_values, refine_values_cancellable,
};

/// OpenSubdiv's vertex boundary interpolation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundaryMode {
    /// Boundary edges sharp; boundary faces are not part of the limit
    /// surface in OpenSubdiv (refined positions equal edge-only).
    None,
    EdgeOnly,
    /// Also corners (one face, two edges) infinitely sharp.
    EdgeAndCorner,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CreaseMethod {
    Uniform,
    Chaikin,
}

#[derive(Clone, Debug, PartialEq)]
pub struct SubdOptions {
    pub levels: u32,
    /// None: from the geometry's `subd_boundary` (0 none, 1 edge and
    /// corner, 2 edge only), else edge only.
    pub boundary: Option<BoundaryMode>,
    /// None: from `subd_creasemethod` (`chaikin`), else uniform.
    pub crease: Option<CreaseMethod>,
    /// Face-varying (vertex attribute) interpolation. None: from the
    /// geometry's `subd_fvar_boundary` (OpenSubdiv's tag values), else
    /// `Boundaries`: islands keep their outlines, their insides smooth.
    pub fvar: Option<FVarLinear>,
    /// Push points to the limit surface and write limit normals `N`.
    pub limit: bool,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SubdError {
    #[error("primitive {0} is not a polygon (subdivision needs a polygon mesh)")]
    NotPolygon(usize),
    #[error("cancelled")]
    Cancelled,
    #[error(transparent)]
    Geo(#[from] GeoError),
}

/// The base level and options of a geometry.
pub fn base_level(
    g: &Geometry,
    opts: &SubdOptions,
) -> Result<(Level, BoundaryMode, CreaseMethod), SubdError> {
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != PrimKind::Polygon {
            return Err(SubdError::NotPolygon(prim));
        }
    }
    let faces = Rows {
        offsets: g.prim_offsets().to_vec(),
        items: g.vertex_points().to_vec(),
    };
    let crease = g
        .attrib(AttribClass::Vertex, "creaseweight")
        .and_then(|a| a.as_f32());
    let mut level = Level::from_faces(g.num_points(), faces, |corner| {
        crease.map_or(0.0, |c| c[corner])
    });
    if let Some(c) = g
        .attrib(AttribClass::Point, "cornerweight")
        .and_then(|a| a.as_f32())
    {
        level.vertex_sharpness = c.to_vec();
    }
    if let Some(h) = g
        .attrib(AttribClass::Primitive, "subd_hole")
        .and_then(|a| a.as_i32())
    {
        level.hole = h.iter().map(|&x| x != 0).collect();
    }
    let detail_int = |name: &str| {
        g.attrib(AttribClass::Detail, name)
            .and_then(|a| a.as_i32())
            .map(|v| v[0])
    };
    let boundary = opts.boundary.unwrap_or(match detail_int("subd_boundary") {
        Some(0) => BoundaryMode::None,
        Some(1) => BoundaryMode::EdgeAndCorner,
        _ => BoundaryMode::EdgeOnly,
    });
    let method = g
        .attrib(AttribClass::Detail, "subd_creasemethod")
        .and_then(|a| a.as_strings())
        .map(|s| s.get(0).to_owned());
    let crease_method = opts
        .crease
        .unwrap_or(if method.as_deref() == Some("chaikin") {
            CreaseMethod::Chaikin
        } else {
            CreaseMethod::Uniform
        });
    level.sharpen_boundaries(boundary == BoundaryMode::EdgeAndCorner);
    Ok((level, boundary, crease_method))
}

/// Numeric attributes of one class as flat f64 columns (name, type info,
/// width, values); integers, quaternions, matrices and strings do not blend.
fn columns(g: &Geometry, class: AttribClass) -> Vec<(String, TypeInfo, usize, Vec<f64>)> {
    g.attribs(class)
        .iter()
        .filter_map(|(name, a)| {
            let (dim, vals): (usize, Vec<f64>) = match a.data() {
                AttribData::Float(v) => (1, v.iter().map(|&x| x as f64).collect()),
                AttribData::Vec2(v) => (
                    2,
                    v.iter().flat_map(|x| x.to_array()).map(f64::from).collect(),
                ),
                AttribData::Vec3(v) => (
                    3,
                    v.iter().flat_map(|x| x.to_array()).map(f64::from).collect(),
                ),
                AttribData::Vec4(v) => (
                    4,
                    v.iter().flat_map(|x| x.to_array()).map(f64::from).collect(),
                ),
                _ => return None,
            };
            Some((name.to_owned(), a.type_info, dim, vals))
        })
        .collect()
}

/// A column of `n` values of `dim` numbers each (`value(i)`), written in
/// place in parallel: the last level's corners are the largest array a
/// subdivision outputs.
fn column<'a>(dim: usize, n: usize, value: impl Fn(usize) -> &'a [f64] + Sync) -> AttribData {
    let all = || (0..n).into_par_iter().map(&value);
    let f = |v: &[f64], k: usize| v[k] as f32;
    match dim {
        1 => AttribData::Float(all().map(|v| f(v, 0)).collect()),
        2 => AttribData::Vec2(all().map(|v| Vec2::new(f(v, 0), f(v, 1))).collect()),
        3 => AttribData::Vec3(
            all()
                .map(|v| Vec3::new(f(v, 0), f(v, 1), f(v, 2)))
                .collect(),
        ),
        _ => AttribData::Vec4(
            all()
                .map(|v| Vec4::new(f(v, 0), f(v, 1), f(v, 2), f(v, 3)))
                .collect(),
        ),
    }
}

/// The faces a subdivision outputs: all but the holes.
struct Kept {
    /// Their points and sizes.
    points: Vec<u32>,
    counts: Vec<u32>,
    /// The level's faces and corners they are, where holes were left out
    /// (None: all of them).
    faces: Option<Vec<u32>>,
    corners: Option<Vec<u32>>,
}

impl Kept {
    /// The kept faces of the last level (its corner points are moved out
    /// when every face is kept: they are the output's largest column).
    fn faces(
        level: &mut Level,
        stop: &dyn Fn() -> Result<(), SubdError>,
    ) -> Result<Kept, SubdError> {
        let size = |f: usize| level.faces.offsets[f + 1] - level.faces.offsets[f];
        if !level.hole.par_iter().any(|&h| h) {
            let counts = (0..level.faces.len()).into_par_iter().map(size).collect();
            return Ok(Kept {
                points: std::mem::take(&mut level.faces.items),
                counts,
                faces: None,
                corners: None,
            });
        }
        let faces: Vec<u32> = (0..level.faces.len() as u32)
            .filter(|&f| !level.hole[f as usize])
            .collect();
        let (mut points, mut corners) = (Vec::new(), Vec::new());
        let mut counts = Vec::with_capacity(faces.len());
        for (k, &f) in faces.iter().enumerate() {
            if k % (1 << 16) == 0 {
                stop()?;
            }
            points.extend_from_slice(level.faces.row(f as usize));
            counts.push(size(f as usize));
            corners.extend(level.faces.offsets[f as usize]..level.faces.offsets[f as usize + 1]);
        }
        Ok(Kept {
            points,
            counts,
            faces: Some(faces),
            corners: Some(corners),
        })
    }
}

/// The values of the listed corners (None: every corner) of a face-varying
/// channel as a column.
fn corner_column(channel: &FVarChannel, corners: Option<&[u32]>) -> AttribData {
    let d = channel.dim;
    let n = corners.map_or(channel.corner_value.len(), <[u32]>::len);
    column(d, n, |i| {
        let c = corners.map_or(i, |list| list[i] as usize);
        let at = channel.corner_value[c] as usize * d;
        &channel.values[at..at + d]
    })
}

/// Positions of every refined level (level 0 first) as flat `x y z` runs,
/// and the last level's topology (its adjacency only with `full_last`, which
/// limit masks need).
pub fn refine_levels(
    base: Level,
    positions: Vec<f64>,
    levels: u32,
    method: CreaseMethod,
    full_last: bool,
) -> (Vec<Vec<f64>>, Level) {
    let mut level = base;
    let mut all = vec![positions];
    for k in 0..levels {
        let adjacency = full_last || k + 1 < levels;
        let child =
            refine_topology_with(&level, method == CreaseMethod::Chaikin, adjacency, &|| {
                false
            })
            .expect("never stopped");
        let pl = plan(&level, &child, method == CreaseMethod::Chaikin);
        let out = refine_values(&level, &child, &pl, all.last().expect("a level"), 3);
        all.push(out);
        level = child;
    }
    (all, level)
}

/// Flat `x y z` runs as points.
#[cfg(test)]
pub(crate) fn points(flat: &[f64]) -> Vec<DVec3> {
    flat.chunks(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect()
}

/// Subdivides `g` by `opts.levels` levels (at least one when `limit` is
/// asked: the limit masks need quads). Hole faces are refined but not
/// output.
pub fn subdivide(
    g: &Geometry,
    opts: &SubdOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, SubdError> {
    let (mut level, _, method) = base_level(g, opts)?;
    let chaikin = method == CreaseMethod::Chaikin;
    let levels = if opts.limit {
        opts.levels.max(1)
    } else {
        opts.levels
    };
    let mut positions: Vec<f64> = g
        .positions()
        .iter()
        .flat_map(|p| p.as_dvec3().to_array())
        .collect();
    let mut points: Vec<(String, TypeInfo, usize, Vec<f64>)> = columns(g, AttribClass::Point)
        .into_iter()
        .filter(|c| c.0 != "P")
        .collect();
    let mode = opts.fvar.unwrap_or_else(|| {
        g.attrib(AttribClass::Detail, "subd_fvar_boundary")
            .and_then(|a| a.as_i32())
            .map_or(FVarLinear::Boundaries, |v| FVarLinear::from_tag(v[0]))
    });
    let mut corners: Vec<(String, TypeInfo, FVarChannel)> = columns(g, AttribClass::Vertex)
        .into_iter()
        .filter(|c| c.0 != "creaseweight")
        .map(|(name, info, dim, vals)| {
            let channel = FVarChannel::from_corners(&level, &vals, dim);
            (name, info, channel)
        })
        .collect();
    let mut prim_of: Vec<u32> = (0..g.num_prims() as u32).collect();
    // Polled between the phases of every level (each can take a while).
    let stop = || {
        if cancel() {
            Err(SubdError::Cancelled)
        } else {
            Ok(())
        }
    };
    for k in 0..levels {
        stop()?;
        let child = refine_topology_with(&level, chaikin, opts.limit || k + 1 < levels, cancel)
            .ok_or(SubdError::Cancelled)?;
        stop()?;
        let pl = plan(&level, &child, chaikin);
        stop()?;
        positions = refine_values_cancellable(&level, &child, &pl, &positions, 3, cancel)
            .ok_or(SubdError::Cancelled)?;
        for c in points.iter_mut() {
            c.3 = refine_values_cancellable(&level, &child, &pl, &c.3, c.2, cancel)
                .ok_or(SubdError::Cancelled)?;
        }
        for c in corners.iter_mut() {
            stop()?;
            c.2 = c.2.refine(&level, &child, &pl, mode);
        }
        stop()?;
        prim_of = (0..level.faces.len())
            .flat_map(|f| std::iter::repeat_n(prim_of[f], level.faces.row(f).len()))
            .collect();
        level = child;
    }
    let (pos, normals) = if opts.limit {
        let control: Vec<DVec3> = positions
            .chunks(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect();
        // Tangent masks weigh the control points, not the limit points.
        let normals = limit_normals(&level, &control);
        for c in corners.iter_mut() {
            c.2 = c.2.limit(&level, mode);
        }
        let pos = limit_positions(&level, &control);
        (pos.par_iter().map(|p| p.as_vec3()).collect(), Some(normals))
    } else {
        let pos = positions
            .par_chunks_exact(3)
            .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
            .collect();
        (pos, None)
    };
    stop()?;
    let kept = Kept::faces(&mut level, &stop)?;
    stop()?;
    let mut out = Geometry::from_polygons(pos, kept.points, &kept.counts)?;
    stop()?;
    for (name, info, dim, vals) in points {
        stop()?;
        out.set_attrib(
            AttribClass::Point,
            &name,
            Attribute::from_data(
                column(dim, vals.len() / dim, |i| &vals[i * dim..(i + 1) * dim]),
                info,
            ),
        )?;
    }
    if let Some(n) = normals {
        out.set_attrib(
            AttribClass::Point,
            "N",
            Attribute::from_data(
                AttribData::Vec3(n.iter().map(|v| v.as_vec3()).collect()),
                TypeInfo::Normal,
            ),
        )?;
    }
    for (name, info, channel) in corners {
        stop()?;
        out.set_attrib(
            AttribClass::Vertex,
            &name,
            Attribute::from_data(corner_column(&channel, kept.corners.as_deref()), info),
        )?;
    }
    let kept_prims: Vec<u32> = match &kept.faces {
        Some(faces) => faces.iter().map(|&f| prim_of[f as usize]).collect(),
        None => prim_of,
    };
    for (name, a) in g.attribs(AttribClass::Primitive).iter() {
        if name == "subd_hole" {
            continue;
        }
        stop()?;
        out.set_attrib(
            AttribClass::Primitive,
            name,
            Attribute::from_data(a.data().gather(&kept_prims), a.type_info),
        )?;
    }
    for (name, a) in g.attribs(AttribClass::Detail).iter() {
        out.set_attrib(AttribClass::Detail, name, a.clone())?;
    }
    Ok(out)
}
