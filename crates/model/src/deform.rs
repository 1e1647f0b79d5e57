//! Displacement of points along their normals: by a distance (peak) or by
//! fractal noise (mountain).
//!
//! Normals are the caller's (a point `N`) or `area_weighted_normals`: each
//! point's polygons' Newell vectors summed (a Newell vector's length is
//! twice the polygon's area, so larger faces weigh more) and normalised;
//! points of no polygon get a zero normal and stay. A point moves along
//! its unit normal, so the displacement has no tangential part.
//!
//! Mountain's fractal sum is `Σ_o r^o b(q_o) / Σ_o r^o` over octaves `o`
//! (`r` the roughness), with `q_o = (P + offset) / size · L^o + s_o`
//! (`L` the lacunarity) and `s_o` a shift of the noise domain per octave
//! drawn from the seed (so seeds and octaves are independent fields).
//! The basis `b` is a closure the caller supplies and is clamped to
//! [-1, 1]: this crate knows no noise function, the node passes
//! geode-vex's Perlin, simplex or Worley noise. Dividing by `Σ r^o` keeps
//! the sum in [-1, 1] at any octave count, so a point moves at most
//! `height`. Every point is computed alone from its position, so the
//! result is the same bytes on any thread count.

use geode_geo::glam::{DVec3, Vec3};
use geode_geo::{random, Geometry, Group, PrimKind};
use rayon::prelude::*;

use crate::ModelError;

/// Points per parallel task; `cancel` is polled once a task.
const CHUNK: usize = 1 << 14;

/// Each point's unit normal: the sum of its polygons' Newell vectors
/// (length twice the area), normalised; zero for points of no polygon.
pub fn area_weighted_normals(g: &Geometry) -> Vec<Vec3> {
    let p = g.positions();
    let weighted: Vec<DVec3> = (0..g.num_prims())
        .into_par_iter()
        .map(|prim| match g.prim_kind(prim) {
            PrimKind::Polygon => newell(p, g.prim_points(prim)),
            _ => DVec3::ZERO,
        })
        .collect();
    let (offsets, prims) = point_prims(g);
    (0..g.num_points())
        .into_par_iter()
        .map(|point| {
            let mut n = DVec3::ZERO;
            for &prim in &prims[offsets[point] as usize..offsets[point + 1] as usize] {
                n += weighted[prim as usize];
            }
            n.normalize_or_zero().as_vec3()
        })
        .collect()
}

/// Each point's primitives, in ascending order (a counting sort of the
/// vertices: cheaper than the geometry's full topology, and the sums run
/// in the same order on any thread count).
fn point_prims(g: &Geometry) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; g.num_points() + 1];
    for &p in g.vertex_points() {
        offsets[p as usize + 1] += 1;
    }
    for i in 0..g.num_points() {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut prims = vec![0u32; g.num_vertices()];
    for prim in 0..g.num_prims() {
        for &p in g.prim_points(prim) {
            prims[fill[p as usize] as usize] = prim as u32;
            fill[p as usize] += 1;
        }
    }
    (offsets, prims)
}

/// A polygon's Newell vector: its normal times twice its area.
fn newell(p: &[Vec3], pts: &[u32]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for i in 0..pts.len() {
        let a = p[pts[i] as usize].as_dvec3();
        let b = p[pts[(i + 1) % pts.len()] as usize].as_dvec3();
        n += a.cross(b);
    }
    n
}

/// Moves each point (of `group`, or all) along its unit `normals` entry by
/// `distance(point, position)`.
pub fn displace_along_normals(
    g: &mut Geometry,
    normals: &[Vec3],
    group: Option<&Group>,
    distance: impl Fn(usize, Vec3) -> f32 + Sync,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    let n = g.num_points();
    if normals.len() != n {
        return Err(ModelError::Invalid(format!(
            "{} normals for {n} points",
            normals.len()
        )));
    }
    if group.is_some_and(|grp| grp.len() != n) {
        return Err(ModelError::Invalid(
            "the group does not fit the points".into(),
        ));
    }
    let mut moved = g.positions().to_vec();
    moved
        .par_chunks_mut(CHUNK)
        .enumerate()
        .try_for_each(|(c, chunk)| {
            if cancel() {
                return Err(ModelError::Cancelled);
            }
            for (k, p) in chunk.iter_mut().enumerate() {
                let i = c * CHUNK + k;
                if group.is_some_and(|grp| !grp.contains(i)) {
                    continue;
                }
                let dir = normals[i].normalize_or_zero();
                if dir != Vec3::ZERO {
                    *p += dir * distance(i, *p);
                }
            }
            Ok(())
        })?;
    g.set_positions(moved);
    Ok(())
}

/// Peak: every point (of `group`) moves `distance` along its normal.
pub fn peak(
    g: &mut Geometry,
    normals: &[Vec3],
    group: Option<&Group>,
    distance: f32,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    displace_along_normals(g, normals, group, |_, _| distance, cancel)
}

/// Mountain's fractal noise.
#[derive(Clone, Copy, Debug)]
pub struct Fractal {
    /// Largest displacement (the sum is normalised to [-1, 1]).
    pub height: f32,
    /// The size of the noise's features at the first octave.
    pub element_size: f32,
    /// Shift of the noise domain (animate it to slide the noise).
    pub offset: Vec3,
    pub octaves: u32,
    /// Each octave's amplitude over the previous one's.
    pub roughness: f32,
    /// Each octave's frequency over the previous one's.
    pub lacunarity: f32,
    pub seed: u64,
}

/// A field of [`Fractal`], to name in an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FractalField {
    ElementSize,
    Octaves,
    Roughness,
    Lacunarity,
    Height,
    Offset,
}

impl Fractal {
    /// Refuses values that give no field (or an infinite one).
    pub fn check(&self) -> Result<(), ModelError> {
        self.check_field().map_err(|(_, e)| e)
    }

    /// [`Fractal::check`], saying which field is wrong.
    pub fn check_field(&self) -> Result<(), (FractalField, ModelError)> {
        let bad = |field, why: String| Err((field, ModelError::Invalid(why)));
        if !(self.element_size > 0.0 && self.element_size.is_finite()) {
            return bad(
                FractalField::ElementSize,
                format!("element size must be positive, not {}", self.element_size),
            );
        }
        if self.octaves == 0 || self.octaves > 32 {
            return bad(
                FractalField::Octaves,
                format!("octaves must be 1 to 32, not {}", self.octaves),
            );
        }
        if !(0.0..=1.0).contains(&self.roughness) {
            return bad(
                FractalField::Roughness,
                format!("roughness must be in [0, 1], not {}", self.roughness),
            );
        }
        if !(self.lacunarity >= 1.0 && self.lacunarity <= 16.0) {
            return bad(
                FractalField::Lacunarity,
                format!("lacunarity must be in [1, 16], not {}", self.lacunarity),
            );
        }
        // Single precision: past 3.4e38 a value is infinite.
        if !self.height.is_finite() {
            return bad(
                FractalField::Height,
                format!(
                    "height must be finite (at most 3.4e38 in size), not {}",
                    self.height
                ),
            );
        }
        if !self.offset.is_finite() {
            return bad(
                FractalField::Offset,
                format!(
                    "offset must be finite (at most 3.4e38 in size), not {}",
                    self.offset
                ),
            );
        }
        Ok(())
    }

    /// The fractal sum at `position`, in [-1, 1], over `basis` noise.
    pub fn value(&self, position: Vec3, basis: &(impl Fn([f32; 3]) -> f32 + ?Sized)) -> f32 {
        self.value_shifted(&self.domain_shifts(), position, basis)
    }

    /// Each octave's shift of the noise domain (`domain_shift`).
    pub fn domain_shifts(&self) -> Vec<Vec3> {
        (0..self.octaves).map(|o| self.domain_shift(o)).collect()
    }

    /// The fractal sum with the octaves' shifts drawn once for all points.
    pub fn value_shifted(
        &self,
        shifts: &[Vec3],
        position: Vec3,
        basis: &(impl Fn([f32; 3]) -> f32 + ?Sized),
    ) -> f32 {
        let base = (position + self.offset) / self.element_size;
        let (mut sum, mut weights) = (0.0f32, 0.0f32);
        let (mut amplitude, mut frequency) = (1.0f32, 1.0f32);
        for &shift in shifts {
            let q = base * frequency + shift;
            sum += amplitude * basis(q.to_array()).clamp(-1.0, 1.0);
            weights += amplitude;
            amplitude *= self.roughness;
            frequency *= self.lacunarity;
        }
        (sum / weights).clamp(-1.0, 1.0)
    }

    /// Where octave `octave` of this seed reads the noise: a shift of up
    /// to 256 lattice cells per axis (the lattice hashes repeat beyond).
    fn domain_shift(&self, octave: u32) -> Vec3 {
        Vec3::from_array(std::array::from_fn(|axis| {
            256.0 * random::unit(self.seed, u64::from(octave), axis as u64)
        }))
    }
}

/// Mountain: every point (of `group`) moves `height × fractal` along its
/// normal, the fractal summed over `basis` noise.
pub fn mountain(
    g: &mut Geometry,
    normals: &[Vec3],
    group: Option<&Group>,
    fractal: &Fractal,
    basis: &(dyn Fn([f32; 3]) -> f32 + Sync),
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(), ModelError> {
    fractal.check()?;
    let shifts = fractal.domain_shifts();
    displace_along_normals(
        g,
        normals,
        group,
        |_, p| fractal.height * fractal.value_shifted(&shifts, p, basis),
        cancel,
    )
}
