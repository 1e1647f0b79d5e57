//! Inside a closed triangle mesh: the winding number at a point, counted
//! exactly as signed crossings of a ray along +X (for a closed mesh that is
//! the generalized winding number, and robust: shared edges and vertices are
//! counted once by a top-left tie rule), with the triangles bucketed on a
//! grid over Y-Z so a query tests only those the ray can meet. For a closed
//! mesh a voxel grid answers most queries at once: the winding number is
//! constant in a voxel no triangle's box touches, so each run of such
//! voxels along X takes the exact answer at its first centre.

use geode_geo::glam::{DVec2, Vec3};

pub struct InsideTest {
    triangles: Vec<[Vec3; 3]>,
    lo: DVec2,
    cell: f64,
    dims: [usize; 2],
    /// Triangle indices per grid cell (CSR).
    starts: Vec<u32>,
    items: Vec<u32>,
    /// Winding numbers of voxels no triangle touches (closed meshes only).
    voxels: Option<Voxels>,
}

/// A voxel's state: its winding number, or touched by a triangle's box.
const TOUCHED: i8 = i8::MIN;

/// Voxels per triangle of the mesh (a 64k-triangle sphere: 128^3, of which
/// about 3% are touched).
const VOXELS_PER_TRIANGLE: f64 = 32.0;

struct Voxels {
    lo: Vec3,
    /// Voxels per unit length.
    per_unit: f32,
    dims: [usize; 3],
    state: Vec<i8>,
}

impl Voxels {
    /// The voxel holding `q`, if inside the grid.
    fn index(&self, q: Vec3) -> Option<usize> {
        let c = (q - self.lo) * self.per_unit;
        if !(c.cmpge(Vec3::ZERO).all()) {
            return None;
        }
        let c = [c.x as usize, c.y as usize, c.z as usize];
        (c[0] < self.dims[0] && c[1] < self.dims[1] && c[2] < self.dims[2])
            .then(|| (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0])
    }
}

impl InsideTest {
    pub fn new(triangles: Vec<[Vec3; 3]>) -> InsideTest {
        let yz = |p: Vec3| DVec2::new(p.y as f64, p.z as f64);
        let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
        for t in &triangles {
            for p in t {
                lo = lo.min(yz(*p));
                hi = hi.max(yz(*p));
            }
        }
        if triangles.is_empty() {
            (lo, hi) = (DVec2::ZERO, DVec2::ONE);
        }
        let size = (hi - lo).max(DVec2::splat(1e-9));
        // About one triangle per cell along each axis of a square grid.
        let side = (triangles.len() as f64).sqrt().clamp(1.0, 2048.0);
        let cell = size.x.max(size.y) / side;
        let dims = [
            ((size.x / cell) as usize + 1).min(4096),
            ((size.y / cell) as usize + 1).min(4096),
        ];
        let cell_of =
            |v: f64, axis: usize| (((v - [lo.x, lo.y][axis]) / cell) as usize).min(dims[axis] - 1);
        let mut counts = vec![0u32; dims[0] * dims[1] + 1];
        let mut spans = Vec::with_capacity(triangles.len());
        for t in &triangles {
            let (a, b) = t.iter().fold(
                (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
                |(a, b), p| (a.min(yz(*p)), b.max(yz(*p))),
            );
            let span = [
                cell_of(a.x, 0),
                cell_of(b.x, 0),
                cell_of(a.y, 1),
                cell_of(b.y, 1),
            ];
            for i in span[0]..=span[1] {
                for j in span[2]..=span[3] {
                    counts[i * dims[1] + j + 1] += 1;
                }
            }
            spans.push(span);
        }
        for k in 1..counts.len() {
            counts[k] += counts[k - 1];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; *counts.last().unwrap_or(&0) as usize];
        for (ti, span) in spans.iter().enumerate() {
            for i in span[0]..=span[1] {
                for j in span[2]..=span[3] {
                    let c = i * dims[1] + j;
                    items[fill[c] as usize] = ti as u32;
                    fill[c] += 1;
                }
            }
        }
        let mut test = InsideTest {
            triangles,
            lo,
            cell,
            dims,
            starts: counts,
            items,
            voxels: None,
        };
        if geode_geo::ops::is_closed_soup(test.triangles.iter().copied()) {
            test.voxels = Some(test.voxelize());
        }
        test
    }

    /// The voxel grid over the mesh's box: voxels its triangles' boxes touch
    /// (grown by a margin well above float rounding), then along each row
    /// every run of untouched voxels takes the exact winding number at its
    /// first voxel's centre.
    fn voxelize(&self) -> Voxels {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for t in &self.triangles {
            for p in t {
                lo = lo.min(*p);
                hi = hi.max(*p);
            }
        }
        let size = (hi - lo).max(Vec3::splat(1e-6));
        let wanted =
            (self.triangles.len() as f64 * VOXELS_PER_TRIANGLE).clamp(1.0, (1u64 << 24) as f64);
        let per_unit = (wanted / (size.x as f64 * size.y as f64 * size.z as f64)).cbrt() as f32;
        let dims = [0, 1, 2].map(|a| ((size[a] * per_unit).ceil() as usize).clamp(1, 1024));
        let mut state = vec![0i8; dims[0] * dims[1] * dims[2]];
        let margin = 1e-3 / per_unit + 1e-5 * size.max_element();
        let cell_of = |v: f32, a: usize| {
            (((v - lo[a]) * per_unit).floor().max(0.0) as usize).min(dims[a] - 1)
        };
        for t in &self.triangles {
            let (a, b) = t.iter().fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(a, b), p| (a.min(*p), b.max(*p)),
            );
            let (a, b) = (a - Vec3::splat(margin), b + Vec3::splat(margin));
            for z in cell_of(a.z, 2)..=cell_of(b.z, 2) {
                for y in cell_of(a.y, 1)..=cell_of(b.y, 1) {
                    let row = (z * dims[1] + y) * dims[0];
                    state[row + cell_of(a.x, 0)..=row + cell_of(b.x, 0)].fill(TOUCHED);
                }
            }
        }
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                let row = (z * dims[1] + y) * dims[0];
                let mut run = None;
                for x in 0..dims[0] {
                    if state[row + x] == TOUCHED {
                        run = None;
                        continue;
                    }
                    let w = *run.get_or_insert_with(|| {
                        let centre =
                            lo + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) / per_unit;
                        // A winding number beyond an i8 is left to the exact test.
                        i8::try_from(self.exact_winding(centre)).unwrap_or(TOUCHED)
                    });
                    state[row + x] = w;
                }
            }
        }
        Voxels {
            lo,
            per_unit,
            dims,
            state,
        }
    }

    /// From a polygon mesh (polygons fanned into triangles; other primitives ignored).
    pub fn from_geometry(g: &geode_geo::Geometry) -> InsideTest {
        InsideTest::new(triangles(g))
    }

    /// The winding number of the mesh around `q` (0 outside a closed,
    /// outward-facing mesh, 1 inside).
    pub fn winding(&self, q: Vec3) -> i32 {
        if let Some(v) = &self.voxels {
            match v.index(q) {
                Some(i) if v.state[i] != TOUCHED => return v.state[i] as i32,
                _ => {}
            }
        }
        self.exact_winding(q)
    }

    /// The winding number by counting the +X ray's crossings.
    fn exact_winding(&self, q: Vec3) -> i32 {
        let (y, z) = (q.y as f64, q.z as f64);
        let i = (y - self.lo.x) / self.cell;
        let j = (z - self.lo.y) / self.cell;
        if i < 0.0 || j < 0.0 || i >= self.dims[0] as f64 || j >= self.dims[1] as f64 {
            return 0;
        }
        let c = i as usize * self.dims[1] + j as usize;
        let mut w = 0;
        for &t in &self.items[self.starts[c] as usize..self.starts[c + 1] as usize] {
            w += crossing(&self.triangles[t as usize], q);
        }
        w
    }

    pub fn contains(&self, q: Vec3) -> bool {
        self.winding(q) != 0
    }
}

/// The polygons of `g` fanned into triangles (other primitives ignored).
pub fn triangles(g: &geode_geo::Geometry) -> Vec<[Vec3; 3]> {
    let p = g.positions();
    let mut tris = Vec::new();
    for prim in 0..g.num_prims() {
        if g.prim_kind(prim) != geode_geo::PrimKind::Polygon {
            continue;
        }
        let pts = g.prim_points(prim);
        for k in 1..pts.len().saturating_sub(1) {
            tris.push([
                p[pts[0] as usize],
                p[pts[k] as usize],
                p[pts[k + 1] as usize],
            ]);
        }
    }
    tris
}

/// +1 where the ray from `q` along +X leaves through the triangle, -1 where
/// it enters, 0 if it misses (ties on shared edges go to exactly one side).
fn crossing(t: &[Vec3; 3], q: Vec3) -> i32 {
    let p = t.map(|v| DVec2::new(v.y as f64 - q.y as f64, v.z as f64 - q.z as f64));
    let area = (p[1] - p[0]).perp_dot(p[2] - p[0]);
    if area == 0.0 {
        return 0;
    }
    // Work with the triangle counter-clockwise in the Y-Z plane.
    let (order, sign) = if area > 0.0 {
        ([0, 1, 2], 1)
    } else {
        ([0, 2, 1], -1)
    };
    let mut bary = [0.0f64; 3];
    for k in 0..3 {
        let (a, b) = (p[order[k]], p[order[(k + 1) % 3]]);
        // Edge function of the origin against edge a -> b (> 0: inside).
        let e = a.perp_dot(b);
        let d = b - a;
        let top_left = d.y < 0.0 || (d.y == 0.0 && d.x > 0.0);
        if e < 0.0 || (e == 0.0 && !top_left) {
            return 0;
        }
        bary[(k + 2) % 3] = e;
    }
    let total: f64 = bary.iter().sum();
    let x: f64 = (0..3).map(|k| bary[k] * t[order[k]].x as f64).sum::<f64>() / total;
    if x <= q.x as f64 {
        return 0;
    }
    // Counter-clockwise in Y-Z means the normal points along +X: leaving.
    sign
}

#[cfg(test)]
mod tests {
    use super::*;
    use geode_geo::primitives;

    #[test]
    fn voxels_answer_exactly_what_the_ray_count_answers() {
        use geode_geo::random::unit;
        let mut nested = primitives::torus(1.0, 0.4, 48, 24);
        let inner = primitives::uv_sphere(0.2, 16, 8);
        nested = geode_geo::ops::merge(&[&nested, &inner]).unwrap();
        for (name, g) in [
            ("sphere", primitives::uv_sphere(1.0, 64, 32)),
            ("cube", primitives::cube(2.0)),
            ("torus and sphere", nested),
        ] {
            let test = InsideTest::from_geometry(&g);
            let v = test.voxels.as_ref().expect("closed meshes get voxels");
            let touched = v.state.iter().filter(|&&s| s == TOUCHED).count();
            assert!(touched < v.state.len(), "{name}: some voxels decide alone");
            // Random points, and points on voxel corners and faces.
            let b = geode_geo::ops::bounds(&g).unwrap();
            let mut points: Vec<Vec3> = (0..200_000u64)
                .map(|i| {
                    let u = Vec3::new(unit(3, i, 0), unit(3, i, 1), unit(3, i, 2));
                    b.min - Vec3::splat(0.1) + u * (b.max - b.min + Vec3::splat(0.2))
                })
                .collect();
            points.extend((0..20_000u64).map(|i| {
                let c = Vec3::new(
                    (i % 40) as f32,
                    (i / 40 % 25) as f32,
                    (i / 1000) as f32 + 0.5,
                );
                v.lo + c / v.per_unit
            }));
            for q in points {
                assert_eq!(test.winding(q), test.exact_winding(q), "{name} at {q}");
            }
        }
        // An open mesh keeps the ray count alone.
        let mut open = primitives::cube(2.0);
        geode_geo::ops::delete_prims(&mut open, &geode_geo::Group::from_members(6, vec![0]), true);
        assert!(InsideTest::from_geometry(&open).voxels.is_none());
    }

    #[test]
    fn cube_inside_outside_and_on_grid_lines() {
        let test = InsideTest::from_geometry(&primitives::cube(2.0));
        assert_eq!(test.winding(Vec3::ZERO), 1);
        assert_eq!(test.winding(Vec3::new(0.5, 0.5, 0.5)), 1);
        assert_eq!(test.winding(Vec3::new(1.5, 0.0, 0.0)), 0);
        assert_eq!(test.winding(Vec3::new(-1.5, 0.0, 0.0)), 0);
        // Rays through the shared diagonal edges and vertices of the faces'
        // triangulation count once.
        for y in [-0.5f32, 0.0, 0.25] {
            assert_eq!(test.winding(Vec3::new(0.0, y, y)), 1, "{y}");
            assert_eq!(test.winding(Vec3::new(-3.0, y, -y)), 0, "{y}");
        }
    }
}
