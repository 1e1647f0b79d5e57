//! Picking in the viewport: the point, vertex and primitive under a click on
//! a drawn triangle, segment or loose point (in the order `viewport.rs` draws
//! them), and primitive centres for the viewport's primitive numbers.

use geode_geo::glam::Vec3;
use geode_geo::{Geometry, PrimKind};
use serde::Deserialize;
use serde_json::{json, Value as Json};

/// What the page's ray hit, by its index in the drawn arrays.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum Hit {
    Triangle(usize),
    Segment(usize),
    Point(usize),
}

/// `{point, vertex, primitive}` of a hit at `at` (the corner nearest to it),
/// or None when the index is past what was drawn.
pub fn pick(g: &Geometry, hit: Hit, at: Vec3) -> Option<Json> {
    let p = g.positions();
    let nearest = |corners: &[(u32, Option<u32>, u32)]| {
        corners.iter().copied().min_by(|a, b| {
            let d = |c: &(u32, Option<u32>, u32)| p[c.2 as usize].distance_squared(at);
            d(a).total_cmp(&d(b))
        })
    };
    let (prim, vertex, point) = match hit {
        Hit::Triangle(k) => {
            let mut seen = 0usize;
            let mut found = None;
            crate::viewport::for_each_fan(g, |t| {
                if seen == k {
                    found = Some(t);
                }
                seen += 1;
            });
            let t = found?;
            let corners: Vec<_> = t.iter().map(|&(pr, v, pt)| (pr, Some(v), pt)).collect();
            nearest(&corners)?
        }
        Hit::Segment(k) => {
            let mut seen = 0usize;
            let mut found = None;
            for prim in 0..g.num_prims() {
                if !matches!(g.prim_kind(prim), PrimKind::Polyline | PrimKind::Patch(_)) {
                    continue;
                }
                let n = g.prim_points(prim).len().saturating_sub(1);
                if k < seen + n {
                    let base = g.prim_offsets()[prim] as usize + (k - seen);
                    let pts = g.prim_points(prim);
                    let i = k - seen;
                    found = Some(vec![
                        (prim as u32, Some(base as u32), pts[i]),
                        (prim as u32, Some(base as u32 + 1), pts[i + 1]),
                    ]);
                    break;
                }
                seen += n;
            }
            nearest(&found?)?
        }
        Hit::Point(k) => {
            let mut used = vec![false; g.num_points()];
            for prim in 0..g.num_prims() {
                for &q in g.prim_points(prim) {
                    used[q as usize] = true;
                }
            }
            let point = (0..g.num_points()).filter(|&i| !used[i]).nth(k)?;
            return Some(json!({"point": point, "vertex": null, "primitive": null}));
        }
    };
    Some(json!({"point": point, "vertex": vertex, "primitive": prim}))
}

/// The centre (mean of its points) of each of the first `limit` primitives.
pub fn prim_centers(g: &Geometry, limit: usize) -> Vec<f32> {
    let p = g.positions();
    let mut out = Vec::with_capacity(g.num_prims().min(limit) * 3);
    for prim in 0..g.num_prims().min(limit) {
        let pts = g.prim_points(prim);
        let c = if pts.is_empty() {
            g.packed_world_transform(prim)
                .map_or(Vec3::ZERO, |m| m.transform_point3(Vec3::ZERO))
        } else {
            pts.iter().map(|&q| p[q as usize]).sum::<Vec3>() / pts.len() as f32
        };
        out.extend_from_slice(&c.to_array());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two quads side by side (fan triangles 0-1 and 2-3), a polyline and a loose point.
    fn scene() -> Geometry {
        let mut g = Geometry::new();
        let pts = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [2., 0., 0.],
            [2., 1., 0.],
            [0., 3., 0.],
            [1., 3., 0.],
            [5., 5., 5.],
        ];
        g.set_positions(pts.iter().map(|a| Vec3::from_array(*a)).collect());
        g.add_polygon(&[0, 1, 2, 3]).unwrap();
        g.add_polygon(&[1, 4, 5, 2]).unwrap();
        g.add_polyline(&[6, 7]).unwrap();
        g
    }

    #[test]
    fn a_hit_names_the_nearest_corner_and_its_primitive() {
        let g = scene();
        // Triangle 3 is the second quad's (1, 5, 2) fan; a hit near point 5.
        let j = pick(&g, Hit::Triangle(3), Vec3::new(1.9, 0.9, 0.0)).unwrap();
        assert_eq!(j, json!({"point": 5, "vertex": 6, "primitive": 1}));
        let j = pick(&g, Hit::Segment(0), Vec3::new(0.1, 3.0, 0.0)).unwrap();
        assert_eq!(j, json!({"point": 6, "vertex": 8, "primitive": 2}));
        let j = pick(&g, Hit::Point(0), Vec3::ZERO).unwrap();
        assert_eq!(j["point"], 8);
        assert!(pick(&g, Hit::Triangle(4), Vec3::ZERO).is_none());
        assert_eq!(&prim_centers(&g, 1), &[0.5, 0.5, 0.0]);
    }
}
