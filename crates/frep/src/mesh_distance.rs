//! A triangle mesh as an exact signed distance field: the distance to the
//! nearest point of any triangle (through `geode-geo`'s triangle
//! hierarchy), positive inside (the generalized winding number's magnitude
//! above one half, so small holes, gaps, self-overlaps and a mesh wound
//! inside out still give a side), negative outside. The distance is 1-Lipschitz, so a box's values lie within half
//! its diagonal of its centre's: that is the interval bound, one point query
//! per box, exact enough that the mesher prunes as for native fields.

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::ops::{TriangleBvh, WindingBvh};

use crate::codec::{FieldDecodeError, Reader};
use crate::interval::Interval;

/// Why triangles do not make a field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshFieldError {
    #[error("the mesh has no triangles")]
    Empty,
    #[error("triangle {triangle} names point {point}, but there are {points} points")]
    BadIndex {
        triangle: usize,
        point: u32,
        points: usize,
    },
    #[error("point {0} is not a finite position")]
    NotFinite(usize),
    #[error("cancelled")]
    Cancelled,
}

/// Balls of known side kept per thread.
const BALLS: usize = 16;

#[derive(Clone, Copy, Default)]
struct Ball {
    centre: DVec3,
    radius2: f64,
    side: f64,
}

#[derive(Default)]
struct SideBalls {
    identity: u128,
    balls: [Ball; BALLS],
    next: usize,
}

thread_local! {
    /// The last balls of known side on this thread, for the mesh named
    /// (see `MeshDistance::side`).
    static SIDE_BALLS: std::cell::RefCell<SideBalls> = std::cell::RefCell::new(SideBalls::default());
}

/// Triangles with their hierarchy; immutable once built.
pub struct MeshDistance {
    positions: Vec<[f32; 3]>,
    triangles: Vec<[u32; 3]>,
    tree: WindingBvh,
    identity: u128,
    /// The triangles' bounding box.
    lo: [f64; 3],
    hi: [f64; 3],
    /// Distances up to this read as on the surface (see `ON_SURFACE`).
    on_surface: f64,
    /// Every edge (by its ends' positions) is used as often in one
    /// direction as in the other: the winding number is then constant off
    /// the surface, which lets known sides spread (see `side`).
    closed: bool,
}

/// Points this close to the surface, relative to the mesh's coordinates
/// (single-precision positions round at 6e-8 of them), are on it: their
/// value is +0, inside, as a native field's exact zero is. Their winding
/// number is one half to rounding, and a side picked by rounding would
/// checker a face lying on a grid plane with signs, which meshes as
/// sheets meeting at edges.
const ON_SURFACE: f64 = 1e-7;

impl std::fmt::Debug for MeshDistance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshDistance")
            .field("points", &self.positions.len())
            .field("triangles", &self.triangles.len())
            .field("identity", &format_args!("{:032x}", self.identity))
            .finish()
    }
}

impl PartialEq for MeshDistance {
    fn eq(&self, other: &MeshDistance) -> bool {
        self.identity == other.identity
    }
}

impl MeshDistance {
    /// The field of `triangles` (indices into `positions`), built with
    /// `cancel` polled while the hierarchy grows.
    pub fn new(
        positions: Vec<[f32; 3]>,
        triangles: Vec<[u32; 3]>,
        cancel: &(dyn Fn() -> bool + Sync),
    ) -> Result<MeshDistance, MeshFieldError> {
        if triangles.is_empty() {
            return Err(MeshFieldError::Empty);
        }
        if let Some(i) = positions
            .iter()
            .position(|p| p.iter().any(|v| !v.is_finite()))
        {
            return Err(MeshFieldError::NotFinite(i));
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&point) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshFieldError::BadIndex {
                    triangle: t,
                    point,
                    points: positions.len(),
                });
            }
        }
        let identity = {
            use xxhash_rust::xxh3::Xxh3;
            let mut h = Xxh3::new();
            h.update(b"mesh distance");
            h.update(&(positions.len() as u64).to_le_bytes());
            for p in &positions {
                p.iter().for_each(|v| h.update(&v.to_le_bytes()));
            }
            for t in &triangles {
                t.iter().for_each(|v| h.update(&v.to_le_bytes()));
            }
            h.digest128()
        };
        let points: Vec<Vec3> = positions.iter().map(|&p| Vec3::from(p)).collect();
        let bvh = TriangleBvh::new_cancellable(&points, &triangles, cancel)
            .ok_or(MeshFieldError::Cancelled)?;
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for t in &triangles {
            for &i in t {
                for k in 0..3 {
                    lo[k] = lo[k].min(positions[i as usize][k] as f64);
                    hi[k] = hi[k].max(positions[i as usize][k] as f64);
                }
            }
        }
        let scale = (0..3)
            .map(|k| lo[k].abs().max(hi[k].abs()).max(hi[k] - lo[k]))
            .fold(0.0, f64::max);
        let closed = geode_geo::ops::is_closed_soup(
            triangles
                .iter()
                .map(|t| t.map(|i| Vec3::from(positions[i as usize]))),
        );
        Ok(MeshDistance {
            closed,
            positions,
            triangles,
            tree: WindingBvh::new(bvh),
            identity,
            lo,
            hi,
            on_surface: ON_SURFACE * scale,
        })
    }

    /// Structural identity: equal for equal points and triangles.
    pub fn identity(&self) -> u128 {
        self.identity
    }

    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    pub fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    /// The triangles' bounding box.
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        (self.lo, self.hi)
    }

    /// Bytes held: the triangles as given and their hierarchy.
    pub fn memory_bytes(&self) -> usize {
        self.positions.len() * 12 + self.triangles.len() * 12 + self.tree.memory_bytes()
    }

    /// A step for central differences: a millionth of the mesh's extent
    /// (its values are exact distances, smooth off the medial axis).
    pub fn difference_step(&self) -> f64 {
        let extent = (0..3).map(|k| self.hi[k] - self.lo[k]).fold(0.0, f64::max);
        1e-6 * extent.max(1e-3)
    }

    /// The nearest point of the mesh and its triangle.
    fn nearest(&self, p: DVec3) -> (DVec3, u32) {
        let c = self
            .tree
            .bvh()
            .closest_f64(p, f64::INFINITY)
            .expect("a mesh field has triangles");
        (c.point, c.triangle)
    }

    /// +1 inside, -1 outside by the winding number alone (see
    /// [`WindingBvh::contains`]: a mesh turned inside out is the same solid).
    fn winding_side(&self, p: DVec3) -> f64 {
        if self.tree.contains(p) {
            1.0
        } else {
            -1.0
        }
    }

    /// +1 inside, -1 outside, for `p` at distance `d` from the surface.
    /// A ball around a point whose side is known, of its distance's
    /// radius, holds no surface, so every point inside it is on the same
    /// side: this thread's last few such balls answer most of a mesher's
    /// queries (neighbouring corners of a lattice) without a winding
    /// number, the costly part. The balls are a hint: on a closed mesh the
    /// winding number is constant inside each, so a side they give is the
    /// side the winding number gives (an open mesh's varies smoothly
    /// across its holes, so there they are not used).
    fn side(&self, p: DVec3, d: f64) -> f64 {
        if !self.closed {
            return self.winding_side(p);
        }
        let known = SIDE_BALLS.with(|b| {
            let b = b.borrow();
            (b.identity == self.identity)
                .then(|| {
                    b.balls
                        .iter()
                        .find(|ball| ball.centre.distance_squared(p) < ball.radius2)
                        .map(|ball| ball.side)
                })
                .flatten()
        });
        if let Some(side) = known {
            return side;
        }
        let side = self.winding_side(p);
        SIDE_BALLS.with(|b| {
            let mut b = b.borrow_mut();
            if b.identity != self.identity {
                *b = SideBalls {
                    identity: self.identity,
                    ..SideBalls::default()
                };
            }
            let at = b.next;
            // A hair inside the distance: rounding never reaches the surface.
            b.balls[at] = Ball {
                centre: p,
                radius2: (d * (1.0 - 1e-9)).powi(2),
                side,
            };
            b.next = (at + 1) % BALLS;
        });
        side
    }

    /// The signed distance at `p`.
    pub fn value(&self, p: [f64; 3]) -> f64 {
        let q = DVec3::from(p);
        if !q.is_finite() {
            return f64::NAN;
        }
        let (near, _) = self.nearest(q);
        let d = q.distance(near);
        if d <= self.on_surface {
            return 0.0;
        }
        self.side(q, d) * d
    }

    /// The signed distance and its gradient at `p`: along the direction
    /// from the nearest point (into the solid), or against the nearest
    /// triangle's normal on the surface itself.
    pub fn value_gradient(&self, p: [f64; 3]) -> (f64, [f64; 3]) {
        let q = DVec3::from(p);
        if !q.is_finite() {
            return (f64::NAN, [f64::NAN; 3]);
        }
        let (near, tri) = self.nearest(q);
        let away = q - near;
        let d = away.length();
        if d <= self.on_surface {
            let [a, b, c] = self.triangles[tri as usize]
                .map(|i| DVec3::from(self.positions[i as usize].map(f64::from)));
            return (0.0, (-(b - a).cross(c - a).normalize_or_zero()).to_array());
        }
        let side = self.side(q, d);
        (side * d, (side * away / d).to_array())
    }

    /// Bounds over the box the three intervals span, `r` its half
    /// diagonal. With surface within `2 r` of the centre: the centre's
    /// value plus or minus `r` (the distance is 1-Lipschitz). Without, the
    /// box holds no surface and every point of it is at least `r` from it:
    /// the centre's side times `[r, U]`, `U` the farthest any point of the
    /// box can be from a triangle (the far corner of the mesh's box). The
    /// search bounded by `2 r` visits a few dozen nodes even at the middle
    /// of a closed mesh, where an unbounded one meets every triangle at
    /// nearly the same distance and visits them all.
    pub fn interval(&self, x: Interval, y: Interval, z: Interval) -> Interval {
        let spans = [x, y, z];
        if spans
            .iter()
            .any(|s| !(s.lo.is_finite() && s.hi.is_finite()))
        {
            return Interval::new(f64::NEG_INFINITY, f64::INFINITY);
        }
        let centre = DVec3::from(spans.map(|s| 0.5 * (s.lo + s.hi)));
        let half = DVec3::from(spans.map(|s| 0.5 * (s.hi - s.lo)));
        let r = half.length();
        match self.tree.bvh().closest_f64(centre, 2.0 * r) {
            Some(near) => {
                let d = near.dist2.sqrt();
                let v = if d <= self.on_surface {
                    0.0
                } else {
                    self.side(centre, d) * d
                };
                Interval::new(v - r, v + r)
            }
            None => {
                let (lo, hi) = (DVec3::from(self.lo), DVec3::from(self.hi));
                let far = (centre - lo).abs().max((hi - centre).abs()) + half;
                let side = self.side(centre, 2.0 * r);
                let (a, b) = (side * r, side * far.length());
                Interval::new(a.min(b), a.max(b))
            }
        }
    }

    /// Values at many points (`out[i]` at `(xs[i], ys[i], zs[i])`).
    pub fn values(&self, xs: &[f32], ys: &[f32], zs: &[f32], out: &mut [f32]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.value([xs[i], ys[i], zs[i]].map(f64::from)) as f32;
        }
    }

    /// Appends the points and triangles (the hierarchy is rebuilt on
    /// decoding: it is a deterministic function of them).
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.identity.to_le_bytes());
        out.extend_from_slice(&(self.positions.len() as u64).to_le_bytes());
        for p in &self.positions {
            p.iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        }
        out.extend_from_slice(&(self.triangles.len() as u64).to_le_bytes());
        for t in &self.triangles {
            t.iter()
                .for_each(|v| out.extend_from_slice(&v.to_le_bytes()));
        }
    }

    /// Reads a mesh [`MeshDistance::encode`] wrote; indices are checked
    /// and the identity must be the one recorded.
    pub(crate) fn decode(r: &mut Reader) -> Result<MeshDistance, FieldDecodeError> {
        let identity = u128::from_le_bytes(r.take(16)?.try_into().expect("sixteen bytes"));
        let n_points = r.count(12)?;
        let mut positions = Vec::with_capacity(n_points);
        for _ in 0..n_points {
            positions.push([r.f32()?, r.f32()?, r.f32()?]);
        }
        let n_triangles = r.count(12)?;
        let mut triangles = Vec::with_capacity(n_triangles);
        for _ in 0..n_triangles {
            triangles.push([r.u32()?, r.u32()?, r.u32()?]);
        }
        let mesh = MeshDistance::new(positions, triangles, &|| false)
            .map_err(|e| FieldDecodeError::Invalid(format!("mesh: {e}")))?;
        if mesh.identity != identity {
            return Err(FieldDecodeError::Invalid("mesh identity".into()));
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cube `[-1, 1]^3`, outward-facing.
    fn cube() -> MeshDistance {
        let p: Vec<[f32; 3]> = (0..8)
            .map(|i| [i & 1, (i >> 1) & 1, (i >> 2) & 1].map(|b| b as f32 * 2.0 - 1.0))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        MeshDistance::new(p, t, &|| false).unwrap()
    }

    /// The box's exact signed distance (positive inside).
    fn box_distance(p: [f64; 3]) -> f64 {
        let q = p.map(|v| v.abs() - 1.0);
        let outside = q.map(|v| v.max(0.0));
        let out = (outside[0].powi(2) + outside[1].powi(2) + outside[2].powi(2)).sqrt();
        -(out + q[0].max(q[1]).max(q[2]).min(0.0))
    }

    #[test]
    fn a_cube_mesh_is_the_box_distance_with_gradients_and_bounds() {
        let m = cube();
        let mut s = 17u64;
        let mut next = || {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 4.0 - 2.0
        };
        for _ in 0..2000 {
            let p = [next(), next(), next()];
            let want = box_distance(p);
            assert!((m.value(p) - want).abs() < 1e-6, "{p:?}");
            let (v, g) = m.value_gradient(p);
            assert_eq!(v, m.value(p));
            let h = 1e-5;
            for k in 0..3 {
                let (mut a, mut b) = (p, p);
                a[k] += h;
                b[k] -= h;
                let fd = (box_distance(a) - box_distance(b)) / (2.0 * h);
                assert!((g[k] - fd).abs() < 1e-3 || want.abs() < 1e-3, "{p:?} {g:?}");
            }
            let r = 0.1 * next().abs();
            let iv = m.interval(
                Interval::new(p[0] - r, p[0] + r),
                Interval::new(p[1] - r, p[1] + r),
                Interval::new(p[2] - r, p[2] + r),
            );
            for corner in 0..8 {
                let c: [f64; 3] =
                    std::array::from_fn(|k| p[k] + if corner >> k & 1 == 1 { r } else { -r });
                let v = box_distance(c);
                assert!(iv.lo - 1e-9 <= v && v <= iv.hi + 1e-9);
            }
        }
    }

    #[test]
    fn bad_meshes_are_refused_and_encoding_round_trips() {
        assert_eq!(
            MeshDistance::new(vec![[0.0; 3]], vec![], &|| false).unwrap_err(),
            MeshFieldError::Empty
        );
        assert!(matches!(
            MeshDistance::new(vec![[0.0; 3]], vec![[0, 0, 3]], &|| false),
            Err(MeshFieldError::BadIndex { point: 3, .. })
        ));
        assert_eq!(
            MeshDistance::new(vec![[f32::NAN; 3]], vec![[0, 0, 0]], &|| false).unwrap_err(),
            MeshFieldError::NotFinite(0)
        );
        let m = cube();
        let mut bytes = Vec::new();
        m.encode(&mut bytes);
        let back = MeshDistance::decode(&mut Reader {
            bytes: &bytes,
            at: 0,
        })
        .unwrap();
        assert_eq!(back.identity(), m.identity());
        assert_eq!(back.value([0.3, 0.2, 0.1]), m.value([0.3, 0.2, 0.1]));
        bytes[20] ^= 1;
        assert!(MeshDistance::decode(&mut Reader {
            bytes: &bytes,
            at: 0
        })
        .is_err());
    }
}
