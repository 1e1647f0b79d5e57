//! Isotropic remeshing (Botsch and Kobbelt 2004, "A remeshing approach to
//! multiresolution modeling"): every iteration splits edges longer than
//! 4/3 of the target length, collapses those shorter than 4/5 (both aimed
//! 4% long, `mesh::AIM`, so the mean lands on the target), flips
//! edges to bring valences toward 6 (4 on borders), moves each vertex to
//! its neighbours' centroid in its tangent plane and projects it back
//! onto the original surface (closest point, walked to from where it was
//! last; vertices on feature lines after each of three relaxation rounds,
//! the others after the third), so the result converges to
//! near-equilateral triangles of the target size on the input's shape.
//!
//! The target length is one number (absolute or a fraction of the bounding
//! box diagonal) or, in adaptive mode, follows curvature between a minimum
//! and a maximum with a limited gradation (`remesh/sizing.rs`).
//!
//! Features: edges whose faces' normals differ by more than the crease
//! angle, border edges, and edges between two points of an optional point
//! group (geode has no edge groups) are kept: never flipped, collapsed
//! only along their line, their vertices relaxed along it and projected
//! onto the original feature edges; corners (a vertex with one or more
//! than two feature edges) never move.
//!
//! The working mesh is flat arrays (`remesh/mesh.rs`) whose adjacency is
//! rebuilt in place per pass; splits are a parallel pattern refinement,
//! collapses and flips sequential sweeps in a fixed order (a pass after
//! the first retests only edges at a vertex the last one touched),
//! relaxation and projection parallel per vertex: the output is the same
//! bytes on any thread count.
//! Attributes come from the original at each point's projection
//! (`remesh/output.rs`). The output is triangles.

use geode_geo::glam::Vec3;
use geode_geo::ops::bounds;
use geode_geo::{Geometry, Group, PrimKind};

use rayon::prelude::*;

use crate::ModelError;

mod collapse;
mod flip;
mod mesh;
mod output;
mod relax;
mod sizing;
mod split;
mod surface;

use mesh::{Mesh, Proj, Topo, NONE};

/// Relaxation and projection rounds per iteration.
const RELAX_ROUNDS: usize = 3;

/// The target length is at most that of equilateral triangles this many
/// of which cover the surface.
const FEWEST_TRIANGLES: f32 = 100.0;

/// How long the edges should be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sizing {
    /// One length everywhere.
    Uniform { length: f32 },
    /// Following curvature: the length whose chord strays `tolerance` from
    /// the surface, within `[min, max]`, growing at most `gradation` per
    /// unit of distance.
    Adaptive {
        min: f32,
        max: f32,
        tolerance: f32,
        gradation: f32,
    },
}

/// What `remesh` does.
#[derive(Clone, Copy, Debug)]
pub struct RemeshOptions<'a> {
    pub sizing: Sizing,
    /// Lengths and tolerance are fractions of the bounding box diagonal.
    pub relative: bool,
    pub iterations: u32,
    /// Degrees: edges whose faces turn more than this are features.
    pub crease_angle: f32,
    /// Edges between two of these points are features too.
    pub feature_points: Option<&'a Group>,
}

impl Default for RemeshOptions<'_> {
    fn default() -> Self {
        RemeshOptions {
            sizing: Sizing::Uniform { length: 0.02 },
            relative: true,
            iterations: 10,
            crease_angle: 30.0,
            feature_points: None,
        }
    }
}

/// The remeshed surface of `g`'s polygons (triangles), every attribute and
/// group carried from the original. `cancel` is polled in every phase.
pub fn remesh(
    g: &Geometry,
    opts: &RemeshOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Geometry, ModelError> {
    let sizing = absolute_sizing(g, opts)?;
    let (mut m, origin) = working_mesh(g, cancel)?;
    if m.faces.is_empty() {
        return Ok(Geometry::default());
    }
    // Setup phases take tens of milliseconds each on a million triangles
    // (two or three times that in a test build): a cancel is answered
    // between every two of them.
    let mut topo = Topo::build(&m);
    ModelError::unless_cancelled(cancel)?;
    check_manifold(&m, &topo)?;
    ModelError::unless_cancelled(cancel)?;
    mark_features(&mut m, &topo, opts, &origin);
    ModelError::unless_cancelled(cancel)?;
    topo.rebuild(&m);
    ModelError::unless_cancelled(cancel)?;
    mark_corners(&mut m, &topo, opts.crease_angle);
    ModelError::unless_cancelled(cancel)?;
    let sizes = match sizing {
        Sizing::Uniform { length } => {
            m.size.iter_mut().for_each(|s| *s = length);
            None
        }
        Sizing::Adaptive {
            min,
            max,
            tolerance,
            gradation,
        } => {
            let sizes = sizing::adaptive_sizes(&m, &topo, min, max, tolerance, gradation);
            m.size.copy_from_slice(&sizes);
            Some(sizes)
        }
    };
    ModelError::unless_cancelled(cancel)?;
    let original = Topo::build(&m);
    ModelError::unless_cancelled(cancel)?;
    let surface =
        surface::Surface::new(&m, original, sizes, cancel).ok_or(ModelError::Cancelled)?;
    let mut scratch = Vec::new();
    for _ in 0..opts.iterations {
        split::split_long_edges(&mut m, &mut topo, cancel)?;
        collapse::collapse_short_edges(&mut m, &mut topo, cancel)?;
        flip::flip_edges(&mut m, &mut topo, cancel)?;
        // Three rounds of relaxation per iteration: one left the spread
        // of edge lengths 1.1 to 1.4 times pymeshlab's, three bring it
        // below (sphere, torus, car). Free vertices go back onto the
        // surface after the last only: a tangential step leaves the
        // surface by its length squared times the curvature, and the
        // three projections cost a third of the whole remesh on a
        // million triangles for the same sphere, torus and car to the
        // digit; feature vertices, relaxed along chords, after each.
        for round in 1..=RELAX_ROUNDS {
            ModelError::unless_cancelled(cancel)?;
            relax::relax(&mut m, &topo, &mut scratch);
            let which = if round == RELAX_ROUNDS {
                relax::Onto::All
            } else {
                relax::Onto::Features
            };
            relax::project(&mut m, &topo, &surface, which, cancel);
        }
    }
    ModelError::unless_cancelled(cancel)?;
    output::build(g, m, &surface, &origin)
}

/// An estimate of the output's triangle count (for memory reservations):
/// the area over an equilateral triangle of the smallest target length.
pub fn expected_triangles(g: &Geometry, opts: &RemeshOptions) -> Result<f64, ModelError> {
    let length = match absolute_sizing(g, opts)? {
        Sizing::Uniform { length } => length,
        Sizing::Adaptive { min, .. } => min,
    } as f64;
    let area = geode_geo::ops::surface_area(g) as f64;
    Ok(area / (3f64.sqrt() / 4.0 * length * length) + g.num_prims() as f64)
}

/// The sizing in absolute lengths, the options checked.
fn absolute_sizing(g: &Geometry, opts: &RemeshOptions) -> Result<Sizing, ModelError> {
    let bad = |what: &str, v: f32| ModelError::Invalid(format!("{what} must be positive, not {v}"));
    let positive = |what: &str, v: f32| {
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(bad(what, v))
        }
    };
    if !(0.0..=180.0).contains(&opts.crease_angle) {
        return Err(ModelError::Invalid(format!(
            "crease angle must be in [0, 180] degrees, not {}",
            opts.crease_angle
        )));
    }
    if let Some(group) = opts.feature_points {
        if group.len() != g.num_points() {
            return Err(ModelError::Invalid(format!(
                "the feature group has {} entries for {} points",
                group.len(),
                g.num_points()
            )));
        }
    }
    let scale = if opts.relative {
        bounds(g).map_or(1.0, |b| b.size().length())
    } else {
        1.0
    };
    // No edge longer than leaves the surface about a hundred triangles: a
    // longer target (a slider dragged past the model's size) collapsed a
    // sphere to a speck of four.
    let area = geode_geo::ops::surface_area(g);
    let longest = (area / (3f32.sqrt() / 4.0 * FEWEST_TRIANGLES)).sqrt();
    let cap = |l: f32| if longest > 0.0 { l.min(longest) } else { l };
    Ok(match opts.sizing {
        Sizing::Uniform { length } => Sizing::Uniform {
            length: cap(positive("target length", length)? * scale),
        },
        Sizing::Adaptive {
            min,
            max,
            tolerance,
            gradation,
        } => {
            let (min, max) = (
                positive("minimum length", min)?,
                positive("maximum length", max)?,
            );
            if min > max {
                return Err(ModelError::Invalid(format!(
                    "minimum length {min} exceeds maximum length {max}"
                )));
            }
            if !(gradation >= 0.0 && gradation.is_finite()) {
                return Err(ModelError::Invalid(format!(
                    "gradation must be zero or more, not {gradation}"
                )));
            }
            Sizing::Adaptive {
                min: cap(min * scale),
                max: cap(max * scale),
                tolerance: positive("tolerance", tolerance)? * scale,
                gradation,
            }
        }
    })
}

/// The source's polygons as triangles (fans) over the points they use,
/// with where each came from.
fn working_mesh(
    g: &Geometry,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Mesh, output::Origin), ModelError> {
    if let Some(k) = g.prim_kinds().iter().position(|k| *k != PrimKind::Polygon) {
        return Err(ModelError::Invalid(format!(
            "remesh takes polygons; primitive {k} is a {}",
            g.prim_kinds()[k].name()
        )));
    }
    let mut index = vec![NONE; g.num_points()];
    let mut point = Vec::new();
    let mut faces = Vec::new();
    let mut prim = Vec::new();
    let mut vertices = Vec::new();
    for k in 0..g.num_prims() {
        if k % 8192 == 0 {
            ModelError::unless_cancelled(cancel)?;
        }
        let pts = g.prim_points(k);
        let first = g.prim_vertex_range(k).start as u32;
        for j in 1..pts.len().saturating_sub(1) {
            let corners = [0, j, j + 1];
            let t = corners.map(|c| {
                let p = pts[c] as usize;
                if index[p] == NONE {
                    index[p] = point.len() as u32;
                    point.push(p as u32);
                }
                index[p]
            });
            faces.push(t);
            prim.push(k as u32);
            vertices.push(corners.map(|c| first + c as u32));
        }
    }
    let pos: Vec<Vec3> = point.iter().map(|&p| g.positions()[p as usize]).collect();
    let n = pos.len();
    let mut proj = vec![
        Proj {
            tri: 0,
            w: [1.0, 0.0, 0.0]
        };
        n
    ];
    for (f, t) in faces.iter().enumerate().rev() {
        for (k, &v) in t.iter().enumerate() {
            let mut w = [0.0; 3];
            w[k] = 1.0;
            proj[v as usize] = Proj { tri: f as u32, w };
        }
    }
    let mesh = Mesh {
        pos,
        size: vec![0.0; n],
        proj,
        fixed: vec![false; n],
        mask: vec![0; faces.len()],
        faces,
    };
    Ok((
        mesh,
        output::Origin {
            prim,
            vertices,
            point,
        },
    ))
}

/// Refuses what the half-edge phases cannot take: an edge of more than
/// two faces, two faces of opposite orientation, a face with a repeated
/// point. The first such face is named.
fn check_manifold(m: &Mesh, topo: &Topo) -> Result<(), ModelError> {
    let fault = |f: usize| -> Option<ModelError> {
        let t = m.faces[f];
        if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
            return Some(ModelError::Invalid(format!(
                "remesh needs a manifold mesh: triangle {f} repeats a point"
            )));
        }
        (0..3).find_map(|k| {
            let h = topo.half_edge(m, t[k], t[(k + 1) % 3]);
            (h != 3 * f as u32 + k as u32).then(|| ModelError::Invalid(format!(
                "remesh needs an oriented manifold mesh: the edge from point {} to {} is used by more than one face the same way (non-manifold or inconsistently oriented)",
                t[k], t[(k + 1) % 3]
            )))
        })
    };
    match (0..m.faces.len()).into_par_iter().find_map_first(fault) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Fixes the vertices where feature lines meet or end (not two feature
/// edges) or turn by more than the crease angle.
fn mark_corners(m: &mut Mesh, topo: &Topo, crease_angle: f32) {
    let cos = crease_angle.to_radians().cos();
    for v in 0..m.pos.len() as u32 {
        m.fixed[v as usize] = match topo.feature[v as usize] {
            0 => false,
            2 => match topo.feature_ends(m, v) {
                Some([a, b]) => {
                    let p = m.pos[v as usize];
                    let into = (p - m.pos[a as usize]).normalize_or_zero();
                    let out = (m.pos[b as usize] - p).normalize_or_zero();
                    into.dot(out) < cos
                }
                None => true,
            },
            _ => true,
        };
    }
}

/// Sets the feature bits: border edges, creases sharper than the angle,
/// edges between two points of the feature group.
fn mark_features(m: &mut Mesh, topo: &Topo, opts: &RemeshOptions, origin: &output::Origin) {
    let cos = opts.crease_angle.to_radians().cos();
    let normal = |m: &Mesh, f: u32| {
        let q = m.faces[f as usize].map(|v| m.pos[v as usize]);
        (q[1] - q[0]).cross(q[2] - q[0]).normalize_or_zero()
    };
    let mesh = &*m;
    let feature = |h: u32| {
        let o = topo.opp[h as usize];
        // A face without area has no normal: it makes no crease.
        let crease = o != NONE && {
            let (n, p) = (normal(mesh, h / 3), normal(mesh, o / 3));
            n != Vec3::ZERO && p != Vec3::ZERO && n.dot(p) < cos
        };
        let grouped = opts.feature_points.is_some_and(|g| {
            g.contains(origin.point[mesh.from(h) as usize] as usize)
                && g.contains(origin.point[mesh.to(h) as usize] as usize)
        });
        o == NONE || crease || grouped
    };
    let masks: Vec<u8> = (0..mesh.faces.len() as u32)
        .into_par_iter()
        .map(|f| {
            (0..3).fold(mesh.mask[f as usize], |bits, k| {
                bits | (feature(3 * f + k) as u8) << k
            })
        })
        .collect();
    m.mask = masks;
}
