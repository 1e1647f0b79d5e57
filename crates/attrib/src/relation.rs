//! Which elements of one class each element of another gathers from (a
//! primitive's points, a point's primitives, every point for the detail),
//! as compressed rows, and the area each element stands for.

use geode_geo::glam::Vec3;
use geode_geo::{AttribClass, Geometry};

use crate::AttribError;

/// Rows of source elements, one row per target element.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rows {
    pub offsets: Vec<u32>,
    pub entries: Vec<u32>,
}

impl Rows {
    pub fn len(&self) -> usize {
        self.offsets.len() - 1
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn row(&self, i: usize) -> &[u32] {
        &self.entries[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Rows from (row, entry) pairs by a counting sort; entries keep the
    /// pairs' order within a row.
    fn from_pairs(rows: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Rows {
        let mut offsets = vec![0u32; rows + 1];
        for (r, _) in pairs.clone() {
            offsets[r as usize + 1] += 1;
        }
        for i in 0..rows {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![0u32; offsets[rows] as usize];
        for (r, e) in pairs {
            entries[fill[r as usize] as usize] = e;
            fill[r as usize] += 1;
        }
        Rows { offsets, entries }
    }

    fn each(n: usize, of: impl Fn(usize) -> u32) -> Rows {
        Rows {
            offsets: (0..=n as u32).collect(),
            entries: (0..n).map(of).collect(),
        }
    }
}

/// How many elements of `class` `g` has.
pub fn count(g: &Geometry, class: AttribClass) -> usize {
    match class {
        AttribClass::Point => g.num_points(),
        AttribClass::Vertex => g.num_vertices(),
        AttribClass::Primitive => g.num_prims(),
        AttribClass::Detail => 1,
    }
}

/// The primitive of every vertex.
pub fn prim_of_vertex(g: &Geometry) -> Vec<u32> {
    let mut out = vec![0u32; g.num_vertices()];
    for prim in 0..g.num_prims() {
        for v in g.prim_vertex_range(prim) {
            out[v] = prim as u32;
        }
    }
    out
}

/// For each element of `to`, the elements of `from` it gathers: through
/// vertices between points and primitives (a point used twice by one
/// primitive counts twice), every element for the detail, the one detail
/// element for every element.
pub fn sources(g: &Geometry, from: AttribClass, to: AttribClass) -> Result<Rows, AttribError> {
    use AttribClass::*;
    let vp = g.vertex_points();
    let nv = g.num_vertices();
    Ok(match (from, to) {
        (a, b) if a == b => {
            return Err(AttribError::Invalid(format!(
                "promoting from {} to {} changes nothing: choose another class",
                class_name(a),
                class_name(b)
            )))
        }
        (_, Detail) => Rows {
            offsets: vec![0, count(g, from) as u32],
            entries: (0..count(g, from) as u32).collect(),
        },
        (Detail, _) => Rows::each(count(g, to), |_| 0),
        (Point, Vertex) => Rows::each(nv, |v| vp[v]),
        (Primitive, Vertex) => {
            let pov = prim_of_vertex(g);
            Rows::each(nv, |v| pov[v])
        }
        (Vertex, Point) => {
            Rows::from_pairs(g.num_points(), (0..nv as u32).map(|v| (vp[v as usize], v)))
        }
        (Vertex, Primitive) => Rows {
            offsets: g.prim_offsets().to_vec(),
            entries: (0..nv as u32).collect(),
        },
        (Point, Primitive) => Rows {
            offsets: g.prim_offsets().to_vec(),
            entries: vp.to_vec(),
        },
        (Primitive, Point) => {
            let pov = prim_of_vertex(g);
            Rows::from_pairs(g.num_points(), (0..nv).map(|v| (vp[v], pov[v])))
        }
        _ => unreachable!("every pair of classes is covered above"),
    })
}

/// The area of a polygon (Newell's normal, half its length); zero for
/// anything with fewer than three points.
pub fn polygon_area(positions: &[Vec3], points: &[u32]) -> f32 {
    if points.len() < 3 {
        return 0.0;
    }
    let mut n = Vec3::ZERO;
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        n += positions[a as usize].cross(positions[b as usize]);
    }
    0.5 * n.length()
}

/// The area each element of `class` stands for: a primitive its own, a
/// vertex an equal share of its primitive's, a point the sum of its
/// vertices' shares, the detail the total.
pub fn element_areas(g: &Geometry, class: AttribClass) -> Vec<f32> {
    let p = g.positions();
    let prim: Vec<f32> = (0..g.num_prims())
        .map(|i| {
            if g.prim_kind(i) == geode_geo::PrimKind::Polygon {
                polygon_area(p, g.prim_points(i))
            } else {
                0.0
            }
        })
        .collect();
    let vertex = || {
        let mut out = vec![0.0f32; g.num_vertices()];
        for (i, a) in prim.iter().enumerate() {
            let r = g.prim_vertex_range(i);
            let share = a / r.len().max(1) as f32;
            out[r].fill(share);
        }
        out
    };
    match class {
        AttribClass::Primitive => prim,
        AttribClass::Vertex => vertex(),
        AttribClass::Point => {
            let mut out = vec![0.0f32; g.num_points()];
            for (v, s) in vertex().into_iter().enumerate() {
                out[g.vertex_points()[v] as usize] += s;
            }
            out
        }
        AttribClass::Detail => vec![prim.iter().map(|&a| f64::from(a)).sum::<f64>() as f32],
    }
}

/// The class's name as the nodes spell it.
pub fn class_name(c: AttribClass) -> &'static str {
    match c {
        AttribClass::Point => "point",
        AttribClass::Vertex => "vertex",
        AttribClass::Primitive => "primitive",
        AttribClass::Detail => "detail",
    }
}

/// Every polygon as triangles (ear clipping where concave), with the
/// primitive each came from: the surface a closest-point or ray query reads.
pub fn surface_triangles(g: &Geometry) -> (Vec<[u32; 3]>, Vec<u32>) {
    let p = g.positions();
    let mut tris = Vec::new();
    let mut prims = Vec::new();
    let mut local = Vec::new();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != geode_geo::PrimKind::Polygon {
            continue;
        }
        let pts = g.prim_points(prim);
        local.clear();
        geode_geo::ops::triangulate_polygon(p, pts, &mut local);
        for t in &local {
            tris.push(t.map(|k| pts[k as usize]));
            prims.push(prim as u32);
        }
    }
    (tris, prims)
}
