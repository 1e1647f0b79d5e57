//! polyreduce: quadric error decimation (Garland and Heckbert edge
//! collapse with optimal placement) to a share of the triangles, a
//! triangle count or an error bound. Polygons are triangulated first (as
//! Houdini's PolyReduce does, the output is triangles). Borders move only
//! along themselves (constraint planes hold their shape) or are locked;
//! seams (a vertex attribute that differs across an edge) likewise; a
//! collapse never flips, folds or degenerates a triangle and keeps a
//! closed manifold closed (the link condition, and no closed fan below
//! three triangles, so a closed mesh ends at a tetrahedron at the least).
//! Collapses are taken in MeshLab's order: the quadric cost (floored at
//! a trace of the model's scale) over the worst shape of the triangles
//! it leaves, below a quality threshold; the error bound reads the cost
//! alone.
//!
//! Attributes: float point attributes are blended at every collapse by
//! where the new position lies along the edge (so a point that absorbed
//! many carries their blend), float vertex attributes the same way per
//! wedge; other point and vertex attributes and point groups come from
//! the surviving element, primitive attributes and groups from the source
//! polygon of the surviving triangle (`carry::build`).
//!
//! `mesh` builds the working mesh, `collapse` runs the loop over `heap`;
//! the error measure is `geode_geo::ops::Quadric`, the one the viewport's
//! bounded reduction uses too.

mod collapse;
mod heap;
mod mesh;

use geode_geo::ops::{renumber_used, triangulate_with};
use geode_geo::{AttribClass, AttribData, Geometry, PrimKind, P};

use crate::carry::{self, copy, Plan};
use crate::ModelError;
use collapse::{Limits, Rows};
use mesh::{Mesh, Setup, NONE};

/// How far to reduce.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// Keep this share of the triangles, in percent (0 to 100).
    Percent(f64),
    /// Keep this many triangles.
    Count(usize),
    /// Collapse everything within `Reduce::max_error`.
    Error,
}

/// A reduction's parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reduce {
    pub target: Target,
    /// No collapse whose error exceeds this (model units: the root mean
    /// squared distance of the new point to the planes it stands for);
    /// infinite for none.
    pub max_error: f64,
    /// Border points never move.
    pub lock_borders: bool,
    /// Seam points never move (otherwise they move along their seam).
    pub lock_seams: bool,
}

impl Default for Reduce {
    fn default() -> Reduce {
        Reduce {
            target: Target::Percent(10.0),
            max_error: f64::INFINITY,
            lock_borders: false,
            lock_seams: false,
        }
    }
}

/// The reduced geometry and what it took.
pub struct Reduced {
    pub geometry: Geometry,
    pub triangles_in: usize,
    pub triangles_out: usize,
    pub collapses: usize,
    /// The largest error of a collapse made (model units).
    pub max_error: f64,
}

/// A triangle may turn at most this far in one collapse (cos 84°): a fold
/// is refused well before it happens.
const MIN_COS: f64 = 0.1;

/// Reduces the polygons of `g` (see the module doc).
pub fn reduce(
    g: &Geometry,
    how: &Reduce,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Reduced, ModelError> {
    check(g, how)?;
    let tri = if (0..g.num_prims()).any(|k| g.prim_vertex_range(k).len() > 3) {
        triangulate_with(g, None, cancel).ok_or(ModelError::Cancelled)?
    } else {
        g.clone()
    };
    let triangles: Vec<[u32; 3]> = (0..tri.num_prims())
        .map(|k| {
            let p = tri.prim_points(k);
            [p[0], p[1], p[2]]
        })
        .collect();
    let vertex = Columns::floats(&tri, AttribClass::Vertex);
    let others = other_columns(&tri);
    let same = |a: u32, b: u32| {
        vertex.same(a, b)
            && others
                .iter()
                .all(|d| d.get(a as usize) == d.get(b as usize))
    };
    let has_vertex = !tri.attribs(AttribClass::Vertex).is_empty();
    let mut mesh = Mesh::new(Setup {
        positions: tri.positions(),
        triangles,
        same_vertex: has_vertex.then_some(&same as &(dyn Fn(u32, u32) -> bool + Sync)),
        lock_borders: how.lock_borders,
        lock_seams: how.lock_seams,
        cancel,
    })
    .ok_or(ModelError::Cancelled)?;
    let triangles_in = mesh.live;
    let target = match how.target {
        Target::Percent(p) => (triangles_in as f64 * p / 100.0).round() as usize,
        Target::Count(n) => n,
        Target::Error => 0,
    };
    let point = Columns::floats(&tri, AttribClass::Point);
    let mut point_rows = point.rows(&tri, AttribClass::Point);
    let mut wedge_rows = vertex.rows(&tri, AttribClass::Vertex);
    let limits = Limits {
        target,
        max_error: how.max_error,
        min_cos: MIN_COS,
    };
    let outcome = collapse::run(&mut mesh, &mut point_rows, &mut wedge_rows, &limits, cancel)?;
    let triangles_out = mesh.live;
    let mut out = output(&tri, &mesh, cancel)?;
    point.write(&mut out.0, AttribClass::Point, &point_rows, &out.1);
    vertex.write(&mut out.0, AttribClass::Vertex, &wedge_rows, &out.2);
    Ok(Reduced {
        geometry: out.0,
        triangles_in,
        triangles_out,
        collapses: outcome.collapses,
        max_error: outcome.max_error,
    })
}

/// Refuses bad parameters and primitives other than polygons.
fn check(g: &Geometry, how: &Reduce) -> Result<(), ModelError> {
    if let Some(k) = g.prim_kinds().iter().position(|k| *k != PrimKind::Polygon) {
        return Err(ModelError::Invalid(format!(
            "polyreduce takes polygons; primitive {k} is a {}",
            g.prim_kinds()[k].name()
        )));
    }
    if let Target::Percent(p) = how.target {
        if !(0.0..=100.0).contains(&p) {
            return Err(ModelError::Invalid(format!(
                "the percentage to keep must be between 0 and 100, not {p}"
            )));
        }
    }
    if how.max_error.is_nan() || how.max_error < 0.0 {
        return Err(ModelError::Invalid(format!(
            "the error bound must be zero or more, not {}",
            how.max_error
        )));
    }
    if how.target == Target::Error && how.max_error.is_infinite() {
        return Err(ModelError::Invalid(
            "reducing to an error bound needs a finite bound".into(),
        ));
    }
    Ok(())
}

/// The surviving triangles as a geometry (points renumbered in their old
/// order), every attribute and group carried from `tri`; also each output
/// point's old point and each output vertex's wedge.
fn output(
    tri: &Geometry,
    mesh: &Mesh,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Geometry, Vec<u32>, Vec<u32>), ModelError> {
    let live: Vec<usize> = (0..mesh.tris.len())
        .filter(|&t| mesh.tris[t][0] != NONE)
        .collect();
    let (new_index, kept) = renumber_used(mesh.pos.len(), live.iter().flat_map(|&t| mesh.tris[t]));
    let corners: Vec<u32> = live
        .iter()
        .flat_map(|&t| (0..3).map(move |j| mesh.wedge[3 * t + j]))
        .collect();
    let plan = Plan {
        positions: kept
            .iter()
            .map(|&p| mesh.pos[p as usize].as_vec3())
            .collect(),
        point_sources: kept.iter().map(|&p| copy(p)).collect(),
        vertex_points: live
            .iter()
            .flat_map(|&t| mesh.tris[t].map(|p| new_index[p as usize]))
            .collect(),
        vertex_sources: corners.iter().map(|&w| copy(w)).collect(),
        prim_counts: vec![3; live.len()],
        prim_kinds: vec![PrimKind::Polygon; live.len()],
        prim_sources: live.iter().map(|&t| t as u32).collect(),
        first_new_prim: usize::MAX,
    };
    let g = carry::build(tri, plan, "polyreduce", cancel)?;
    Ok((g, kept, corners))
}

/// The non-float vertex columns (compared value by value for wedges).
fn other_columns(g: &Geometry) -> Vec<&AttribData> {
    g.attribs(AttribClass::Vertex)
        .iter()
        .map(|(_, a)| a.data())
        .filter(|d| d.as_floats().is_none())
        .collect()
}

/// The float columns of a class (P aside), laid side by side in rows.
struct Columns<'a> {
    columns: Vec<(&'a str, &'a [f32], usize)>,
    width: usize,
}

impl<'a> Columns<'a> {
    fn floats(g: &'a Geometry, class: AttribClass) -> Columns<'a> {
        let columns: Vec<_> = g
            .attribs(class)
            .iter()
            .filter(|(name, _)| !(class == AttribClass::Point && *name == P))
            .filter_map(|(name, a)| a.data().as_floats().map(|(f, w)| (name, f, w)))
            .collect();
        let width = columns.iter().map(|c| c.2).sum();
        Columns { columns, width }
    }

    /// Whether elements `a` and `b` hold the same floats (bit for bit).
    fn same(&self, a: u32, b: u32) -> bool {
        self.columns.iter().all(|&(_, f, w)| {
            let (a, b) = (a as usize * w, b as usize * w);
            (0..w).all(|k| f[a + k].to_bits() == f[b + k].to_bits())
        })
    }

    fn rows(&self, g: &Geometry, class: AttribClass) -> Rows {
        let n = g.attribs(class).len();
        let mut data = vec![0.0; n * self.width];
        let mut at = 0;
        for &(_, f, w) in &self.columns {
            for e in 0..n {
                data[e * self.width + at..e * self.width + at + w]
                    .copy_from_slice(&f[e * w..(e + 1) * w]);
            }
            at += w;
        }
        Rows {
            width: self.width,
            data,
        }
    }

    /// Writes each output element's row (`from[i]`'s) into its columns.
    fn write(&self, out: &mut Geometry, class: AttribClass, rows: &Rows, from: &[u32]) {
        let mut at = 0;
        for &(name, _, w) in &self.columns {
            let column = out.attribs_mut(class).get_mut(name).expect("carried");
            let (dst, _) = column.floats_mut().expect("a float column");
            for (i, &src) in from.iter().enumerate() {
                let row = src as usize * rows.width + at;
                dst[i * w..(i + 1) * w].copy_from_slice(&rows.data[row..row + w]);
            }
            if let Some(q) = column.as_quat_mut() {
                q.iter_mut().for_each(|x| *x = x.normalize());
            }
            at += w;
        }
    }
}
