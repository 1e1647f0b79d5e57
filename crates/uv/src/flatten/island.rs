//! One island at a time: its triangle mesh over its own wedges, its LSCM
//! solve, and the rescale that gives it its 3D area in uv.

use geode_geo::glam::Vec3;
use geode_geo::ops::triangulate_polygon;
use geode_geo::Geometry;

use super::charts::Charts;
use crate::error::UvError;
use crate::lscm::{choose_pins, lscm, spectral, ConformalMethod, SolverOptions};

/// Wedges and primitives grouped by island, in ascending order within
/// each, and each wedge's number inside its island.
#[derive(Clone, Debug, Default)]
pub(super) struct IslandIndex {
    wedge_offsets: Vec<u32>,
    wedges: Vec<u32>,
    prim_offsets: Vec<u32>,
    prims: Vec<u32>,
    /// Each wedge's place in its island's wedge list.
    pub wedge_local: Vec<u32>,
}

impl IslandIndex {
    pub fn wedges(&self, island: usize) -> &[u32] {
        &self.wedges[self.wedge_offsets[island] as usize..self.wedge_offsets[island + 1] as usize]
    }

    pub fn prims(&self, island: usize) -> &[u32] {
        &self.prims[self.prim_offsets[island] as usize..self.prim_offsets[island + 1] as usize]
    }
}

/// Groups wedges and primitives by island (counting sorts, stable).
pub(super) fn index_islands(charts: &Charts) -> IslandIndex {
    let (wedge_offsets, wedges) = group(charts.islands, charts.wedge_island.iter().copied());
    let (prim_offsets, prims) = group(charts.islands, charts.prim_island.iter().copied());
    let mut wedge_local = vec![0u32; charts.wedge_point.len()];
    for island in 0..charts.islands {
        let span = wedge_offsets[island] as usize..wedge_offsets[island + 1] as usize;
        for (local, &w) in wedges[span].iter().enumerate() {
            wedge_local[w as usize] = local as u32;
        }
    }
    IslandIndex {
        wedge_offsets,
        wedges,
        prim_offsets,
        prims,
        wedge_local,
    }
}

/// CSR of the items `0..` by their group (items in group NONE or past
/// `groups` are left out).
fn group(groups: usize, of: impl Iterator<Item = u32> + Clone) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; groups + 1];
    for g in of.clone().filter(|&g| (g as usize) < groups) {
        offsets[g as usize + 1] += 1;
    }
    for i in 0..groups {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut items = vec![0u32; offsets[groups] as usize];
    for (item, g) in of.enumerate().filter(|&(_, g)| (g as usize) < groups) {
        items[cursor[g as usize] as usize] = item as u32;
        cursor[g as usize] += 1;
    }
    (offsets, items)
}

/// An island as a triangle mesh over its wedges (local numbers).
#[derive(Clone, Debug, Default)]
pub(super) struct IslandMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// The island's wedges' positions and its polygons' triangles.
pub(super) fn island_mesh(
    g: &Geometry,
    charts: &Charts,
    index: &IslandIndex,
    island: usize,
) -> IslandMesh {
    let positions = g.positions();
    let mesh_positions = index
        .wedges(island)
        .iter()
        .map(|&w| positions[charts.wedge_point[w as usize] as usize])
        .collect();
    let mut triangles = Vec::new();
    let mut corners = Vec::new();
    for &prim in index.prims(island) {
        let range = g.prim_vertex_range(prim as usize);
        corners.clear();
        triangulate_polygon(positions, g.prim_points(prim as usize), &mut corners);
        let local = |corner: u32| {
            let wedge = charts.vertex_wedge[range.start + corner as usize];
            index.wedge_local[wedge as usize]
        };
        triangles.extend(corners.iter().map(|t| t.map(local)));
    }
    IslandMesh {
        positions: mesh_positions,
        triangles,
    }
}

/// An island flattened, at the scale of its 3D surface.
#[derive(Clone, Debug, Default)]
pub(super) struct FlatIsland {
    /// One uv per wedge of the island (local order).
    pub uv: Vec<[f64; 2]>,
    pub iterations: usize,
    pub converged: bool,
}

/// LSCM of one island with its two far boundary wedges pinned, rescaled
/// so that its uv area equals its 3D area. An island without area (all
/// its polygons degenerate) collapses to a point.
pub(super) fn flatten_island(
    mesh: &IslandMesh,
    solver: &SolverOptions,
    method: ConformalMethod,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<FlatIsland, UvError> {
    let collapsed = FlatIsland {
        uv: vec![[0.0, 0.0]; mesh.positions.len()],
        iterations: 0,
        converged: true,
    };
    let area_3d = surface_area(mesh);
    let Some(pins) = choose_pins(&mesh.positions, &mesh.triangles) else {
        return Ok(collapsed);
    };
    if area_3d <= 0.0 || !(pins[1].uv[0] > 0.0 && pins[1].uv[0].is_finite()) {
        return Ok(collapsed);
    }
    let spectral = match method {
        ConformalMethod::Spectral => match spectral(&mesh.positions, &mesh.triangles, cancel) {
            Err(UvError::Invalid(_)) => None,
            other => Some(other?),
        },
        ConformalMethod::TwoPins => None,
    };
    let solution = match spectral {
        Some(s) => s,
        None => lscm(&mesh.positions, &mesh.triangles, &pins, solver, cancel)?,
    };
    if solution.uv.iter().flatten().any(|c| !c.is_finite()) {
        return Ok(collapsed);
    }
    let area_uv = uv_area(&solution.uv, &mesh.triangles);
    let ratio = area_3d / area_uv;
    let scale = if ratio > 0.0 && ratio.is_finite() {
        ratio.sqrt()
    } else {
        1.0
    };
    Ok(FlatIsland {
        uv: solution
            .uv
            .iter()
            .map(|&[u, v]| [u * scale, v * scale])
            .collect(),
        iterations: solution.iterations,
        converged: solution.converged,
    })
}

/// The island's 3D area (triangles with positions that are not finite
/// left out).
fn surface_area(mesh: &IslandMesh) -> f64 {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
            0.5 * (b - a).cross(c - a).length()
        })
        .filter(|area| area.is_finite())
        .sum()
}

/// The summed unsigned area of the triangles in uv.
fn uv_area(uv: &[[f64; 2]], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| uv[i as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs()
        })
        .sum()
}
