//! Choosing LSCM's two pinned vertices: two far-apart boundary vertices.

use geode_geo::glam::Vec3;

use super::Pin;

/// Two vertices to pin, as Lévy et al. suggest: far apart on the boundary
/// of the triangles (edges used by one triangle, or by more than two),
/// or anywhere on a closed surface. Found by two sweeps (the vertex
/// farthest from the first boundary vertex, then the one farthest from
/// that), which gives the diameter or close to it; ties go to the lower
/// index. The first is pinned at (0, 0), the second at (distance, 0), so
/// the solution has about the surface's own scale. None when the
/// triangles reference fewer than two distinct vertices.
pub fn choose_pins(positions: &[Vec3], triangles: &[[u32; 3]]) -> Option<[Pin; 2]> {
    let candidates = boundary_vertices(triangles);
    let candidates = if candidates.len() >= 2 {
        candidates
    } else {
        let mut used: Vec<u32> = triangles.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        used
    };
    if candidates.len() < 2 {
        return None;
    }
    let position = |v: u32| positions[v as usize].as_dvec3();
    let farthest_from = |from: u32| {
        let origin = position(from);
        let mut best = (candidates[0], -1.0);
        for &v in &candidates {
            let d = position(v).distance_squared(origin);
            if d > best.1 && v != from {
                best = (v, d);
            }
        }
        best
    };
    let (a, _) = farthest_from(candidates[0]);
    let (b, distance_squared) = farthest_from(a);
    Some([
        Pin {
            vertex: a,
            uv: [0.0, 0.0],
        },
        Pin {
            vertex: b,
            uv: [distance_squared.max(0.0).sqrt(), 0.0],
        },
    ])
}

/// Vertices on an edge not shared by exactly two triangles, ascending.
fn boundary_vertices(triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut boundary: Vec<u32> = boundary_edges(triangles).into_iter().flatten().collect();
    boundary.sort_unstable();
    boundary.dedup();
    boundary
}

/// Edges (lower vertex first, sorted) in one triangle or in more than two.
pub(super) fn boundary_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut edges: Vec<[u32; 2]> = triangles
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .filter(|e| e[0] != e[1])
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    let mut boundary = Vec::new();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        if j - i != 2 {
            boundary.push(edges[i]);
        }
        i = j;
    }
    boundary
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_strip_is_pinned_at_its_ends() {
        // A 3 x 1 strip of quads along x, split into triangles.
        let mut positions = Vec::new();
        for i in 0..4 {
            positions.push(Vec3::new(i as f32, 0.0, 0.0));
            positions.push(Vec3::new(i as f32, 0.5, 0.0));
        }
        let mut triangles = Vec::new();
        for i in 0..3u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
        let [p, q] = choose_pins(&positions, &triangles).unwrap();
        let ends = [p.vertex.min(q.vertex), p.vertex.max(q.vertex)];
        assert!(ends == [0, 7] || ends == [1, 6], "{ends:?}");
        assert!((q.uv[0] - (9.0f64 + 0.25).sqrt()).abs() < 1e-6);
        assert!(choose_pins(&positions, &[]).is_none());
    }
}
