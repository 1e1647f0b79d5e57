//! Building a `Geometry`: points added, primitives appended with their
//! vertices (polygons, polylines, packed instances), attributes and groups
//! grown to match.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use crate::error::GeoError;

use super::{checked_u32, Geometry, PackedInstance, PrimKind, P};

impl Geometry {
    pub(super) fn resize_points(&mut self, n: usize) {
        self.points.resize(n);
        for g in self.point_groups.values_mut() {
            g.resize(n);
        }
        self.invalidate_topology();
    }

    /// Adds a point and returns its index.
    pub fn add_point(&mut self, p: Vec3) -> u32 {
        let i = self.num_points();
        self.resize_points(i + 1);
        self.positions_mut()[i] = p;
        i as u32
    }

    /// Adds points and returns the index of the first.
    pub fn add_points(&mut self, ps: &[Vec3]) -> u32 {
        let first = self.num_points();
        self.resize_points(first + ps.len());
        self.positions_mut()[first..].copy_from_slice(ps);
        first as u32
    }

    pub(crate) fn push_prim(&mut self, kind: PrimKind, points: &[u32]) -> Result<u32, GeoError> {
        self.push_prims(&[(kind, points.len() as u32)], points)
    }

    /// Appends primitives at once: each `(kind, count)` of `prims` over the
    /// next `count` points of `points`. Nothing is added on an error.
    fn push_prims(&mut self, prims: &[(PrimKind, u32)], points: &[u32]) -> Result<u32, GeoError> {
        let n = self.num_points();
        if let Some(&bad) = points.iter().find(|&&p| p as usize >= n) {
            return Err(GeoError::PointOutOfRange {
                index: bad,
                count: n,
            });
        }
        let first = checked_u32(self.num_prims(), "primitive count")?;
        checked_u32(self.num_prims() + prims.len(), "primitive count")?;
        let mut end = checked_u32(self.vertex_point.len() + points.len(), "vertex count")?;
        end -= points.len() as u32;
        self.vertex_point.make_mut().extend_from_slice(points);
        let offsets = self.prim_offsets.make_mut();
        offsets.reserve(prims.len());
        for (_, count) in prims {
            end += count;
            offsets.push(end);
        }
        let kinds = self.prim_kinds.make_mut();
        kinds.extend(prims.iter().map(|(kind, _)| *kind));
        self.vertices.resize(self.vertex_point.len());
        self.prims.resize(self.prim_kinds.len());
        for g in self.prim_groups.values_mut() {
            g.resize(self.prim_kinds.len());
        }
        self.invalidate_topology();
        Ok(first)
    }

    /// Adds polygons and polylines at once (a generator's thousands in one
    /// step rather than one resize of every column per primitive): each
    /// `(closed, count)` of `prims` over the next `count` points of
    /// `points`. Returns the first new primitive's number.
    pub fn add_polys(&mut self, prims: &[(bool, u32)], points: &[u32]) -> Result<u32, GeoError> {
        let mut total = 0usize;
        for &(closed, count) in prims {
            match (closed, count) {
                (true, c) if c < 3 => return Err(GeoError::PolygonTooSmall(c as usize)),
                (false, c) if c < 2 => return Err(GeoError::PolylineTooSmall(c as usize)),
                _ => total += count as usize,
            }
        }
        if total != points.len() {
            return Err(GeoError::VertexCountMismatch {
                counted: total,
                given: points.len(),
            });
        }
        let kinds: Vec<(PrimKind, u32)> = prims
            .iter()
            .map(|&(closed, count)| {
                let kind = if closed {
                    PrimKind::Polygon
                } else {
                    PrimKind::Polyline
                };
                (kind, count)
            })
            .collect();
        self.push_prims(&kinds, points)
    }

    /// Adds a closed polygon over existing points.
    pub fn add_polygon(&mut self, points: &[u32]) -> Result<u32, GeoError> {
        if points.len() < 3 {
            return Err(GeoError::PolygonTooSmall(points.len()));
        }
        self.push_prim(PrimKind::Polygon, points)
    }

    /// Adds an open polyline over existing points.
    pub fn add_polyline(&mut self, points: &[u32]) -> Result<u32, GeoError> {
        if points.len() < 2 {
            return Err(GeoError::PolylineTooSmall(points.len()));
        }
        self.push_prim(PrimKind::Polyline, points)
    }

    /// Adds a packed instance of `source` at point `point`.
    pub fn add_packed(
        &mut self,
        point: u32,
        source: Arc<Geometry>,
        transform: Mat4,
    ) -> Result<u32, GeoError> {
        let idx = checked_u32(self.packed.len(), "packed instance count")?;
        let prim = self.push_prim(PrimKind::Packed(idx), &[point])?;
        self.packed
            .make_mut()
            .push(PackedInstance { source, transform });
        Ok(prim)
    }

    /// Adds `count` packed instances of one source, each on a new point, with
    /// per-instance positions and local transforms. Bulk path for instancing.
    pub fn add_packed_many(
        &mut self,
        source: &Arc<Geometry>,
        positions: &[Vec3],
        transforms: &[Mat4],
    ) -> Result<(), GeoError> {
        if positions.len() != transforms.len() {
            return Err(GeoError::Invalid(format!(
                "{} positions but {} transforms for packed instances",
                positions.len(),
                transforms.len()
            )));
        }
        self.add_packed_rows(source, positions.len(), |k| (positions[k], transforms[k]))
    }

    /// Packed instances of `source`, the `k`-th at the position and with
    /// the linear part of `world(k)` (its translation is the point's).
    pub fn add_packed_with(
        &mut self,
        source: &Arc<Geometry>,
        n: usize,
        world: impl Fn(usize) -> Mat4 + Sync,
    ) -> Result<(), GeoError> {
        self.add_packed_rows(source, n, |k| {
            let m = world(k);
            let local = Mat4::from_cols(m.x_axis, m.y_axis, m.z_axis, glam::Vec4::W);
            (m.w_axis.truncate(), local)
        })
    }

    /// `n` packed instances of `source`, the `k`-th on a new point at
    /// `row(k).0` with local transform `row(k).1`; columns written whole,
    /// rows computed in parallel.
    fn add_packed_rows(
        &mut self,
        source: &Arc<Geometry>,
        n: usize,
        row: impl Fn(usize) -> (Vec3, Mat4) + Sync,
    ) -> Result<(), GeoError> {
        let first_point = self.num_points();
        let first_packed = self.packed.len();
        let first_prim = self.num_prims();
        checked_u32(first_point + n, "point count")?;
        checked_u32(first_packed + n, "packed instance count")?;
        checked_u32(self.vertex_point.len() + n, "vertex count")?;
        let first_vertex = self.vertex_point.len() as u32;
        // One vertex and one primitive per instance.
        self.vertex_point
            .make_mut()
            .extend((0..n as u32).map(|i| first_point as u32 + i));
        self.prim_offsets
            .make_mut()
            .extend((1..=n as u32).map(|i| first_vertex + i));
        self.prim_kinds
            .make_mut()
            .extend((0..n as u32).map(|i| PrimKind::Packed(first_packed as u32 + i)));
        // One thread: clones of one Arc from several contend for its count.
        let packed = self.packed.make_mut();
        packed.reserve(n);
        packed.extend((0..n).map(|_| PackedInstance {
            source: Arc::clone(source),
            transform: Mat4::IDENTITY,
        }));
        self.resize_points(first_point + n);
        self.invalidate_content();
        let positions = self
            .points
            .get_mut(P)
            .and_then(|a| a.as_vec3_mut())
            .expect("P is always a vector3 point attribute");
        let positions = &mut positions[first_point..];
        let packed = &mut self.packed.make_mut()[first_packed..];
        positions
            .par_iter_mut()
            .zip(packed.par_iter_mut())
            .enumerate()
            .with_min_len(1 << 12)
            .for_each(|(k, (p, inst))| (*p, inst.transform) = row(k));
        self.vertices.resize(self.vertex_point.len());
        self.prims.resize(self.prim_kinds.len());
        for g in self.prim_groups.values_mut() {
            g.resize(first_prim + n);
        }
        self.invalidate_topology();
        Ok(())
    }
}
