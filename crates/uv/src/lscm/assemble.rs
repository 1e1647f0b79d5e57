//! LSCM's per-triangle terms and the Hermitian system they add up to.
//!
//! Each triangle is laid in its own plane with corners `p0, p1, p2`
//! counter-clockwise about its normal. A linear map to uv, written
//! `U = u + i v` per corner, is conformal on it exactly when
//! `sum_j W_j U_j = 0` with `W_j = p_{j+2} - p_{j+1}` as complex numbers
//! (the gradient of u turned a quarter turn equals the gradient of v);
//! Lévy et al.'s energy is `sum_T |sum_j W_j U_j|^2 / d_T`, `d_T` twice
//! the area. Scaling the `W_j` by `1 / sqrt(d_T)`, the energy is
//! `U^H H U` with `H_jk = sum_T conj(W_j) W_k`. Pinned corners move to
//! the right-hand side: `H_ff U_f = -H_fp U_p`.

use geode_geo::glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::solver::{Complex, Csr};

/// Triangles thinner than this (twice the area over the longest edge
/// squared) carry no usable angle and are left out of the energy.
const MIN_SHAPE: f64 = 1e-10;

/// One triangle's corners and its weighted coefficients `W_j / sqrt(d)`.
#[derive(Clone, Copy, Debug)]
pub(super) struct TriangleTerm {
    pub corners: [u32; 3],
    pub w: [Complex; 3],
}

/// The terms of every triangle with an area (degenerate ones dropped).
pub(super) fn triangle_terms(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<TriangleTerm> {
    triangles
        .par_iter()
        .with_min_len(4096)
        .filter_map(|&corners| {
            let [a, b, c] = corners.map(|i| positions[i as usize].as_dvec3());
            conformal_coefficients(a, b, c).map(|w| TriangleTerm { corners, w })
        })
        .collect()
}

/// `W_j / sqrt(d)` of a triangle, or None when it has no area to speak of.
pub(super) fn conformal_coefficients(a: DVec3, b: DVec3, c: DVec3) -> Option<[Complex; 3]> {
    let (ab, ac) = (b - a, c - a);
    let normal = ab.cross(ac);
    let twice_area = normal.length();
    let longest = ab
        .length_squared()
        .max(ac.length_squared())
        .max((c - b).length_squared());
    if !twice_area.is_finite() || !longest.is_finite() || twice_area <= MIN_SHAPE * longest {
        return None;
    }
    let x_axis = ab.normalize();
    let y_axis = (normal / twice_area).cross(x_axis);
    let p = [
        Complex::ZERO,
        Complex::new(ab.length(), 0.0),
        Complex::new(ac.dot(x_axis), ac.dot(y_axis)),
    ];
    let weight = 1.0 / twice_area.sqrt();
    Some([
        (p[2] - p[1]).scale(weight),
        (p[0] - p[2]).scale(weight),
        (p[1] - p[0]).scale(weight),
    ])
}

/// How each vertex enters the system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Role {
    /// Unknown number `k` of the system.
    Free(u32),
    /// Fixed at this uv.
    Pinned(Complex),
    /// In no triangle with an area: solved for afterwards.
    Unused,
}

/// Rows per parallel chunk of the assembly.
const ASSEMBLY_CHUNK: usize = 1024;

/// The system `H x = rhs` over the free vertices (in the order of
/// `free_vertices`), from the triangles incident to each vertex.
pub(super) fn assemble(
    terms: &[TriangleTerm],
    roles: &[Role],
    free_vertices: &[u32],
) -> (Csr, Vec<Complex>) {
    let incident = incident_triangles(terms, roles.len());
    let chunks: Vec<_> = free_vertices
        .par_chunks(ASSEMBLY_CHUNK)
        .map(|rows| {
            let mut lens = Vec::with_capacity(rows.len());
            let mut cols = Vec::new();
            let mut values = Vec::new();
            let mut rhs = Vec::with_capacity(rows.len());
            let mut row: Vec<(u32, Complex)> = Vec::new();
            for &vertex in rows {
                rhs.push(assemble_row(terms, roles, &incident, vertex, &mut row));
                lens.push(row.len());
                cols.extend(row.iter().map(|e| e.0));
                values.extend(row.iter().map(|e| e.1));
            }
            (lens, cols, values, rhs)
        })
        .collect();
    let mut matrix = Csr {
        ncols: free_vertices.len(),
        offsets: vec![0],
        ..Csr::default()
    };
    let mut rhs = Vec::with_capacity(free_vertices.len());
    for (lens, cols, values, b) in chunks {
        for len in lens {
            let last = matrix.offsets[matrix.offsets.len() - 1];
            matrix.offsets.push(last + len);
        }
        matrix.cols.extend(cols);
        matrix.values.extend(values);
        rhs.extend(b);
    }
    (matrix, rhs)
}

/// One free vertex's row (into `row`, sorted by column, duplicates
/// summed in triangle order) and its right-hand side.
fn assemble_row(
    terms: &[TriangleTerm],
    roles: &[Role],
    incident: &Incidence,
    vertex: u32,
    row: &mut Vec<(u32, Complex)>,
) -> Complex {
    row.clear();
    let mut rhs = Complex::ZERO;
    for &t in incident.of(vertex) {
        let term = &terms[t as usize];
        let Some(j) = term.corners.iter().position(|&c| c == vertex) else {
            continue;
        };
        let wj = term.w[j].conj();
        for (k, &other) in term.corners.iter().enumerate() {
            let h = wj * term.w[k];
            match roles[other as usize] {
                Role::Free(col) => row.push((col, h)),
                Role::Pinned(uv) => rhs -= h * uv,
                Role::Unused => {}
            }
        }
    }
    row.sort_by_key(|e| e.0);
    row.dedup_by(|later, kept| {
        if later.0 == kept.0 {
            kept.1 += later.1;
            true
        } else {
            false
        }
    });
    rhs
}

/// The triangles incident to each vertex, in triangle order.
pub(super) struct Incidence {
    offsets: Vec<u32>,
    triangles: Vec<u32>,
}

impl Incidence {
    pub fn of(&self, vertex: u32) -> &[u32] {
        let v = vertex as usize;
        &self.triangles[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }
}

/// Counting sort of triangle corners by vertex.
pub(super) fn incident_triangles(terms: &[TriangleTerm], vertices: usize) -> Incidence {
    let mut offsets = vec![0u32; vertices + 1];
    for term in terms {
        for &c in &term.corners {
            offsets[c as usize + 1] += 1;
        }
    }
    for v in 0..vertices {
        offsets[v + 1] += offsets[v];
    }
    let mut cursor = offsets.clone();
    let mut triangles = vec![0u32; offsets[vertices] as usize];
    for (t, term) in terms.iter().enumerate() {
        for &c in &term.corners {
            triangles[cursor[c as usize] as usize] = t as u32;
            cursor[c as usize] += 1;
        }
    }
    Incidence { offsets, triangles }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The identity map of a flat triangle is conformal: zero residual.
    #[test]
    fn a_flat_triangle_maps_to_itself_without_energy() {
        let p = [
            DVec3::new(0.2, 0.1, 0.0),
            DVec3::new(1.3, 0.4, 0.0),
            DVec3::new(0.5, 1.7, 0.0),
        ];
        let w = conformal_coefficients(p[0], p[1], p[2]).unwrap();
        let residual = (0..3).fold(Complex::ZERO, |acc, j| {
            acc + w[j] * Complex::new(p[j].x, p[j].y)
        });
        assert!(residual.norm_sqr() < 1e-24, "{residual:?}");
        // Its mirror image is not conformal in LSCM's sense.
        let mirrored = (0..3).fold(Complex::ZERO, |acc, j| {
            acc + w[j] * Complex::new(p[j].x, -p[j].y)
        });
        assert!(mirrored.norm_sqr() > 1e-3);
        let flat = conformal_coefficients(p[0], p[1], p[0] * 0.5 + p[1] * 0.5);
        assert!(flat.is_none());
    }
}
