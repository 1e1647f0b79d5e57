//! Hierarchical B-spline surfaces (Forsey and Bartels 1988): a uniform
//! bicubic surface of plane, cylinder (wrapped in v) or torus topology,
//! refined level by level; each finer level's control vertices are the
//! refined coarser ones plus offsets stored in the coarser surface's local
//! frame (normal, u tangent, v tangent) at the vertex's parameter, so
//! detail follows when a coarser level is edited. Offsets live only inside
//! a level's overlay rectangle and only on its movable vertices (at least
//! two from the overlay's edge, so the surface stays continuous).

use geode_geo::glam::{DQuat, DVec3};

use crate::skin::{skin, Joint, Rigid, Skeleton, SkinMethod};

pub mod attach;
pub mod file;

/// How the control grid wraps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Topology {
    Plane,
    /// Wrapped in v.
    Cylinder,
    /// Wrapped in u and v.
    Torus,
}

impl Topology {
    fn wraps(self) -> (bool, bool) {
        match self {
            Topology::Plane => (false, false),
            Topology::Cylinder => (false, true),
            Topology::Torus => (true, true),
        }
    }
}

/// A control grid, `v` fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub nu: usize,
    pub nv: usize,
    pub points: Vec<DVec3>,
}

impl Grid {
    pub fn at(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.nv + j]
    }
}

/// A refined level's editable rectangle (in its own indices, half-open)
/// and the offsets of its vertices (local frame: normal, u, v).
#[derive(Clone, Debug, PartialEq)]
pub struct Overlay {
    pub u: (usize, usize),
    pub v: (usize, usize),
    pub offsets: Vec<DVec3>,
}

impl Overlay {
    fn index(&self, i: usize, j: usize) -> Option<usize> {
        let inside = (self.u.0..self.u.1).contains(&i) && (self.v.0..self.v.1).contains(&j);
        inside.then(|| (i - self.u.0) * (self.v.1 - self.v.0) + (j - self.v.0))
    }
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum HsplineError {
    #[error("level {0} does not exist (the hierarchy has {1})")]
    NoLevel(usize, usize),
    #[error("vertex ({i}, {j}) of level {level} is not movable (outside its overlay or within two of its edge)")]
    NotMovable { level: usize, i: usize, j: usize },
    #[error("the region is empty or outside the level")]
    BadRegion,
    #[error("a {0:?} needs at least {1} control vertices each way")]
    TooSmall(Topology, usize),
    #[error("level {0} would pass 16M vertices a side")]
    TooLarge(usize),
}

/// Refines one row of uniform cubic control points (Lane-Riesenfeld):
/// edge points (P_i + P_i+1) / 2 and vertex points (P_i-1 + 6 P_i + P_i+1) / 8.
/// A closed row of n gives 2n; an open one 2n - 3 (E0 V1 E1 ... V(n-2) E(n-2)).
pub fn refine_row(p: &[DVec3], closed: bool) -> Vec<DVec3> {
    let n = p.len();
    let e = |i: usize| (p[i % n] + p[(i + 1) % n]) * 0.5;
    let v = |i: usize| (p[(i + n - 1) % n] + p[i] * 6.0 + p[(i + 1) % n]) / 8.0;
    if closed {
        (0..n).flat_map(|i| [v(i), e(i)]).collect()
    } else {
        let mut out = vec![e(0)];
        for i in 1..n - 1 {
            out.push(v(i));
            out.push(e(i));
        }
        out
    }
}

/// Refines a grid in both directions.
fn refine_grid(g: &Grid, wrap: (bool, bool)) -> Grid {
    let rows: Vec<Vec<DVec3>> = (0..g.nu)
        .map(|i| refine_row(&g.points[i * g.nv..(i + 1) * g.nv], wrap.1))
        .collect();
    let nv = rows[0].len();
    let cols: Vec<Vec<DVec3>> = (0..nv)
        .map(|j| refine_row(&rows.iter().map(|r| r[j]).collect::<Vec<_>>(), wrap.0))
        .collect();
    let nu = cols[0].len();
    let mut points = vec![DVec3::ZERO; nu * nv];
    for (j, col) in cols.iter().enumerate() {
        for (i, p) in col.iter().enumerate() {
            points[i * nv + j] = *p;
        }
    }
    Grid { nu, nv, points }
}

/// The uniform cubic B-spline weights of the four vertices m-1..m+2 at
/// fraction t of span m.
fn weights(t: f64) -> ([f64; 4], [f64; 4]) {
    let (t2, t3) = (t * t, t * t * t);
    let w = [
        (1.0 - t).powi(3) / 6.0,
        (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
        (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
        t3 / 6.0,
    ];
    let d = [
        -(1.0 - t).powi(2) / 2.0,
        (3.0 * t2 - 4.0 * t) / 2.0,
        (-3.0 * t2 + 2.0 * t + 1.0) / 2.0,
        t2 / 2.0,
    ];
    (w, d)
}

/// Position along one direction: the span and fraction of normalized `s`
/// (0..1), and the scale from s to vertex units.
fn locate(s: f64, n: usize, closed: bool) -> (isize, f64, f64) {
    let (x, scale) = if closed {
        (s * n as f64, n as f64)
    } else {
        (1.0 + s * (n as f64 - 3.0), n as f64 - 3.0)
    };
    let hi = if closed { n as f64 } else { n as f64 - 2.0 };
    let m = x.floor().min(hi - 1.0);
    (m as isize, x - m, scale)
}

/// Vertex `k` (0..4) of span `m` among `n` (wrapping; an open direction's
/// spans never reach past its ends).
fn span_vertex(m: isize, k: usize, n: usize) -> usize {
    (m - 1 + k as isize).rem_euclid(n as isize) as usize
}

/// Point and derivatives (per unit normalized parameter) of a grid's surface.
pub fn evaluate(g: &Grid, wrap: (bool, bool), s: f64, t: f64) -> (DVec3, DVec3, DVec3) {
    let (mu, fu, su) = locate(s, g.nu, wrap.0);
    let (mv, fv, sv) = locate(t, g.nv, wrap.1);
    let ((wu, du), (wv, dv)) = (weights(fu), weights(fv));
    let (mut p, mut pu, mut pv) = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
    for a in 0..4 {
        for b in 0..4 {
            let q = g.at(span_vertex(mu, a, g.nu), span_vertex(mv, b, g.nv));
            p += q * (wu[a] * wv[b]);
            pu += q * (du[a] * wv[b] * su);
            pv += q * (wu[a] * dv[b] * sv);
        }
    }
    (p, pu, pv)
}

/// Vertex counts after refining a `base` grid `level` times: a wrapped
/// direction doubles, an open one becomes 2n - 3; None past 2^24.
pub(crate) fn level_size(
    base: (usize, usize),
    wrap: (bool, bool),
    level: usize,
) -> Option<(usize, usize)> {
    let (mut nu, mut nv) = base;
    for _ in 0..level {
        nu = if wrap.0 { 2 * nu } else { 2 * nu - 3 };
        nv = if wrap.1 { 2 * nv } else { 2 * nv - 3 };
        if nu > 1 << 24 || nv > 1 << 24 {
            return None;
        }
    }
    Some((nu, nv))
}

/// An orthonormal frame (normal, u tangent, v tangent) from derivatives.
fn frame(pu: DVec3, pv: DVec3) -> [DVec3; 3] {
    let n = pu.cross(pv).normalize_or_zero();
    let tu = pu.normalize_or_zero();
    [n, tu, n.cross(tu)]
}

/// Normalized parameter of vertex `k` of an `n`-vertex direction.
fn parameter(k: usize, n: usize, closed: bool) -> f64 {
    if closed {
        k as f64 / n as f64
    } else {
        ((k as f64 - 1.0) / (n as f64 - 3.0)).clamp(0.0, 1.0)
    }
}

/// The enveloping a hierarchy carries: the level whose control vertices
/// are skinned, the method, the skeleton at rest and every vertex's joint
/// weights (v fastest). The pose is animation and lives in the network.
#[derive(Clone, Debug, PartialEq)]
pub struct Envelope {
    pub level: usize,
    pub method: SkinMethod,
    pub joints: Vec<Joint>,
    pub weights: Vec<Vec<(usize, f64)>>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Hspline {
    pub topology: Topology,
    pub base: Grid,
    /// Overlay `k` belongs to level `k + 1`.
    pub overlays: Vec<Overlay>,
    pub envelope: Option<Envelope>,
}

impl Hspline {
    /// A surface of `nu` x `nv` control vertices: a plane in XZ of the given
    /// size, a cylinder (radius size.x / 2, height size.y) or a torus (major
    /// size.x / 2, minor size.y / 2).
    pub fn new(
        topology: Topology,
        nu: usize,
        nv: usize,
        size: [f64; 2],
    ) -> Result<Hspline, HsplineError> {
        // A uniform cubic needs four vertices per span, wrapped or not.
        let min = 4;
        if nu < min || nv < min {
            return Err(HsplineError::TooSmall(topology, min));
        }
        let tau = std::f64::consts::TAU;
        let points = (0..nu * nv)
            .map(|k| {
                let (i, j) = (k / nv, k % nv);
                let (a, b) = (i as f64 / nu as f64, j as f64 / nv as f64);
                match topology {
                    Topology::Plane => DVec3::new(
                        size[0] * (i as f64 / (nu - 1) as f64 - 0.5),
                        0.0,
                        size[1] * (j as f64 / (nv - 1) as f64 - 0.5),
                    ),
                    Topology::Cylinder => DVec3::new(
                        0.5 * size[0] * (tau * b).cos(),
                        size[1] * (i as f64 / (nu - 1) as f64 - 0.5),
                        0.5 * size[0] * (tau * b).sin(),
                    ),
                    Topology::Torus => {
                        let r = 0.5 * size[0] + 0.5 * size[1] * (tau * a).cos();
                        DVec3::new(
                            r * (tau * b).cos(),
                            0.5 * size[1] * (tau * a).sin(),
                            r * (tau * b).sin(),
                        )
                    }
                }
            })
            .collect();
        Ok(Hspline {
            topology,
            base: Grid { nu, nv, points },
            overlays: Vec::new(),
            envelope: None,
        })
    }

    pub fn levels(&self) -> usize {
        self.overlays.len() + 1
    }

    fn wrap(&self) -> (bool, bool) {
        self.topology.wraps()
    }

    /// World control grid of `level`: the coarser level refined, plus each
    /// offset turned into world space by the coarser surface's frame.
    pub fn grid(&self, level: usize) -> Result<Grid, HsplineError> {
        self.grid_from(0, self.base.clone(), level)
    }

    /// The world grid of `level`, starting from `start` taken as the world
    /// grid of level `from` (for example a deformed one: enveloping a
    /// coarse level lets the finer offsets follow in the deformed frames).
    pub fn grid_from(&self, from: usize, start: Grid, level: usize) -> Result<Grid, HsplineError> {
        if level >= self.levels() || from > level {
            return Err(HsplineError::NoLevel(level, self.levels()));
        }
        let wrap = self.wrap();
        let mut g = start;
        for overlay in &self.overlays[from..level] {
            let parent = g;
            g = refine_grid(&parent, wrap);
            for i in overlay.u.0..overlay.u.1 {
                for j in overlay.v.0..overlay.v.1 {
                    let o = overlay.offsets[overlay.index(i, j).expect("inside")];
                    if o == DVec3::ZERO {
                        continue;
                    }
                    let (_, pu, pv) = evaluate(
                        &parent,
                        wrap,
                        parameter(i, g.nu, wrap.0),
                        parameter(j, g.nv, wrap.1),
                    );
                    let [n, tu, tv] = frame(pu, pv);
                    g.points[i * g.nv + j] += n * o.x + tu * o.y + tv * o.z;
                }
            }
        }
        Ok(g)
    }

    /// Refines the finest level over the rectangle `u` x `v` of its vertex
    /// indices (None: everywhere), adding a level with zero offsets there.
    pub fn refine(
        &mut self,
        region: Option<((usize, usize), (usize, usize))>,
    ) -> Result<(), HsplineError> {
        if level_size((self.base.nu, self.base.nv), self.wrap(), self.levels()).is_none() {
            return Err(HsplineError::TooLarge(self.levels()));
        }
        let finest = self.grid(self.levels() - 1)?;
        let child = refine_grid(&finest, self.wrap());
        let (u, v) = match region {
            None => ((0, child.nu), (0, child.nv)),
            Some(((u0, u1), (v0, v1))) => {
                if u0 >= u1 || v0 >= v1 || u1 > finest.nu || v1 > finest.nv {
                    return Err(HsplineError::BadRegion);
                }
                // Child vertices over the parent range, with the support margin.
                let map =
                    |a: usize, b: usize, n: usize| ((2 * a).saturating_sub(2), (2 * b + 1).min(n));
                (map(u0, u1, child.nu), map(v0, v1, child.nv))
            }
        };
        let count = (u.1 - u.0) * (v.1 - v.0);
        self.overlays.push(Overlay {
            u,
            v,
            offsets: vec![DVec3::ZERO; count],
        });
        Ok(())
    }

    /// Whether vertex (i, j) of `level` may carry an offset: inside the
    /// overlay and at least two vertices from any of its edges that is not
    /// the (wrapping or outer) edge of the whole surface.
    pub fn movable(&self, level: usize, i: usize, j: usize) -> bool {
        if level == 0 {
            return i < self.base.nu && j < self.base.nv;
        }
        let Some(o) = self.overlays.get(level - 1) else {
            return false;
        };
        let Ok(g) = self.grid_size(level) else {
            return false;
        };
        let ok = |k: usize, (lo, hi): (usize, usize), n: usize| {
            (lo..hi).contains(&k) && (lo == 0 || k >= lo + 2) && (hi == n || k + 2 < hi)
        };
        ok(i, o.u, g.0) && ok(j, o.v, g.1)
    }

    /// Vertex counts of `level`.
    pub fn grid_size(&self, level: usize) -> Result<(usize, usize), HsplineError> {
        if level >= self.levels() {
            return Err(HsplineError::NoLevel(level, self.levels()));
        }
        Ok(level_size((self.base.nu, self.base.nv), self.wrap(), level)
            .expect("levels that exist fit in memory"))
    }

    /// Moves vertex (i, j) of `level` by the world vector `delta` (level 0:
    /// the vertex itself; finer: its offset, in the local frame).
    pub fn move_cv(
        &mut self,
        level: usize,
        i: usize,
        j: usize,
        delta: DVec3,
    ) -> Result<(), HsplineError> {
        if !self.movable(level, i, j) {
            return Err(HsplineError::NotMovable { level, i, j });
        }
        if level == 0 {
            let nv = self.base.nv;
            self.base.points[i * nv + j] += delta;
            return Ok(());
        }
        let parent = self.grid(level - 1)?;
        let (nu, nv) = self.grid_size(level)?;
        let wrap = self.wrap();
        let (_, pu, pv) = evaluate(
            &parent,
            wrap,
            parameter(i, nu, wrap.0),
            parameter(j, nv, wrap.1),
        );
        let [n, tu, tv] = frame(pu, pv);
        let o = &mut self.overlays[level - 1];
        let k = o.index(i, j).expect("movable means inside");
        o.offsets[k] += DVec3::new(delta.dot(n), delta.dot(tu), delta.dot(tv));
        Ok(())
    }

    /// Moves the surface point at normalized (s, t) by the world vector
    /// `delta`, exactly, through the movable vertex of `level` with the most
    /// weight there (its edit point): that vertex moves by delta / weight.
    pub fn move_surface_point(
        &mut self,
        level: usize,
        s: f64,
        t: f64,
        delta: DVec3,
    ) -> Result<(usize, usize), HsplineError> {
        let (nu, nv) = self.grid_size(level)?;
        let wrap = self.wrap();
        let (mu, fu, _) = locate(s, nu, wrap.0);
        let (mv, fv, _) = locate(t, nv, wrap.1);
        let ((wu, _), (wv, _)) = (weights(fu), weights(fv));
        let mut best: Option<(f64, usize, usize)> = None;
        for (a, wa) in wu.iter().enumerate() {
            for (b, wb) in wv.iter().enumerate() {
                let (i, j, w) = (span_vertex(mu, a, nu), span_vertex(mv, b, nv), wa * wb);
                if self.movable(level, i, j) && best.is_none_or(|x| w > x.0) {
                    best = Some((w, i, j));
                }
            }
        }
        let (w, i, j) = best.ok_or(HsplineError::NotMovable {
            level,
            i: mu.max(0) as usize,
            j: mv.max(0) as usize,
        })?;
        self.move_cv(level, i, j, delta / w)?;
        Ok((i, j))
    }

    /// The vertices next to (i, j) on `level` (four at most; wrapping where
    /// the topology wraps).
    pub fn neighbours(&self, level: usize, i: usize, j: usize) -> Vec<(usize, usize)> {
        let Ok((nu, nv)) = self.grid_size(level) else {
            return Vec::new();
        };
        let (wu, wv) = self.wrap();
        let mut out = Vec::new();
        let step = |k: usize, d: isize, n: usize, wraps: bool| -> Option<usize> {
            let x = k as isize + d;
            if wraps {
                Some(x.rem_euclid(n as isize) as usize)
            } else {
                (0..n as isize).contains(&x).then_some(x as usize)
            }
        };
        for (du, dv) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
            if let (Some(a), Some(b)) = (step(i, du, nu, wu), step(j, dv, nv, wv)) {
                if (a, b) != (i, j) && !out.contains(&(a, b)) {
                    out.push((a, b));
                }
            }
        }
        out
    }

    /// The vertices of row `i` (along v) or column `j` (along u) of `level`.
    pub fn along_v(&self, level: usize, i: usize) -> Vec<(usize, usize)> {
        self.grid_size(level)
            .map(|(_, nv)| (0..nv).map(|j| (i, j)).collect())
            .unwrap_or_default()
    }

    pub fn along_u(&self, level: usize, j: usize) -> Vec<(usize, usize)> {
        self.grid_size(level)
            .map(|(nu, _)| (0..nu).map(|i| (i, j)).collect())
            .unwrap_or_default()
    }

    /// Whether the region under vertex (i, j) of `level` is refined: it
    /// lies in the next level's overlay.
    pub fn refined(&self, level: usize, i: usize, j: usize) -> bool {
        let Some(o) = self.overlays.get(level) else {
            return false;
        };
        let (wu, wv) = self.wrap();
        // Child index of parent vertex k: 2k closed, 2k - 1 open.
        let child = |k: usize, wraps: bool| {
            if wraps {
                2 * k
            } else {
                (2 * k).saturating_sub(1)
            }
        };
        (o.u.0..o.u.1).contains(&child(i, wu)) && (o.v.0..o.v.1).contains(&child(j, wv))
    }

    /// The offset of vertex (i, j) of a refined level, if it is in the overlay.
    pub fn offset(&self, level: usize, i: usize, j: usize) -> Option<DVec3> {
        let o = self.overlays.get(level.checked_sub(1)?)?;
        o.index(i, j).map(|k| o.offsets[k])
    }

    /// Vertices of `level` with a non-zero offset.
    pub fn nonzero_offsets(&self, level: usize) -> Vec<(usize, usize)> {
        let Some(o) = level.checked_sub(1).and_then(|l| self.overlays.get(l)) else {
            return Vec::new();
        };
        (o.u.0..o.u.1)
            .flat_map(|i| (o.v.0..o.v.1).map(move |j| (i, j)))
            .filter(|&(i, j)| o.offsets[o.index(i, j).expect("inside")] != DVec3::ZERO)
            .collect()
    }

    pub fn zero_offsets(&mut self, level: usize) {
        if let Some(o) = level.checked_sub(1).and_then(|l| self.overlays.get_mut(l)) {
            o.offsets.iter_mut().for_each(|x| *x = DVec3::ZERO);
        }
    }

    /// Removes what carries no detail: every finest level whose offsets
    /// are all zero, and on the others the overlay rows and columns beyond
    /// the support (two vertices) of their non-zero offsets. The surface
    /// does not change.
    pub fn unrefine(&mut self) {
        while self
            .overlays
            .last()
            .is_some_and(|o| o.offsets.iter().all(|x| *x == DVec3::ZERO))
        {
            self.overlays.pop();
        }
        for level in 1..self.levels() {
            let nz = self.nonzero_offsets(level);
            if nz.is_empty() {
                continue;
            }
            let (nu, nv) = self.grid_size(level).expect("a level");
            let o = &self.overlays[level - 1];
            let (u0, u1) = (
                nz.iter().map(|x| x.0).min().unwrap_or(0),
                nz.iter().map(|x| x.0).max().unwrap_or(0),
            );
            let (v0, v1) = (
                nz.iter().map(|x| x.1).min().unwrap_or(0),
                nz.iter().map(|x| x.1).max().unwrap_or(0),
            );
            let nu_range = (u0.saturating_sub(2).max(o.u.0), (u1 + 3).min(o.u.1).min(nu));
            let nv_range = (v0.saturating_sub(2).max(o.v.0), (v1 + 3).min(o.v.1).min(nv));
            let mut offsets =
                Vec::with_capacity((nu_range.1 - nu_range.0) * (nv_range.1 - nv_range.0));
            for i in nu_range.0..nu_range.1 {
                for j in nv_range.0..nv_range.1 {
                    offsets.push(o.offsets[o.index(i, j).expect("inside")]);
                }
            }
            self.overlays[level - 1] = Overlay {
                u: nu_range,
                v: nv_range,
                offsets,
            };
        }
    }

    /// Carries `skeleton` (at rest) and automatic weights for the vertices
    /// of `level` (clamped to the finest), skinned by `method`.
    pub fn set_envelope(&mut self, level: usize, method: SkinMethod, skeleton: &Skeleton) {
        let level = level.min(self.levels() - 1);
        let grid = self.grid(level).expect("the level exists");
        self.envelope = Some(Envelope {
            level,
            method,
            joints: skeleton
                .joints
                .iter()
                .map(|j| Joint {
                    rotation: DQuat::IDENTITY,
                    ..j.clone()
                })
                .collect(),
            weights: skeleton.auto_weights(&grid.points),
        });
    }

    /// The finest grid with the envelope level's vertices moved by
    /// `motions` (one per envelope joint) and the finer offsets following
    /// in the deformed frames; vertices without weights stay.
    pub fn enveloped_grid(&self, motions: &[Rigid]) -> Result<Grid, HsplineError> {
        let Some(e) = &self.envelope else {
            return self.grid(self.levels() - 1);
        };
        let coarse = self.grid(e.level)?;
        let moved = skin(&coarse.points, &e.weights, motions, e.method);
        let points = moved
            .into_iter()
            .zip(&coarse.points)
            .zip(&e.weights)
            .map(|((m, p), w)| if w.is_empty() { *p } else { m })
            .collect();
        self.grid_from(e.level, Grid { points, ..coarse }, self.levels() - 1)
    }

    /// The surface point and normal at normalized (s, t), on the finest level.
    pub fn point(&self, s: f64, t: f64) -> (DVec3, DVec3) {
        let g = self
            .grid(self.levels() - 1)
            .expect("the finest level exists");
        let (p, pu, pv) = evaluate(&g, self.wrap(), s, t);
        (p, frame(pu, pv)[0])
    }
}

impl Hspline {
    /// A level's grid as a cubic B-spline patch primitive: the indices of
    /// its control points (into `grid.points`, v fastest) and the knots. A
    /// wrapped direction repeats its first three vertices so the patch
    /// closes on the same points; the knots are uniform, so the patch is
    /// the hspline surface itself (knot `3 + s * spans` is parameter `s`).
    pub fn patch_layout(&self, grid: &Grid) -> (Vec<u32>, geode_geo::PatchBasis) {
        let wrap = self.wrap();
        let side = |n: usize, closed: bool| {
            let count = if closed { n + 3 } else { n };
            let index: Vec<usize> = (0..count)
                .map(|k| if closed { (k + n - 1) % n } else { k })
                .collect();
            let knots = geode_geo::KnotVector {
                order: 4,
                knots: (0..count + 4).map(|k| k as f64).collect(),
            };
            (index, knots)
        };
        let ((iu, ku), (iv, kv)) = (side(grid.nu, wrap.0), side(grid.nv, wrap.1));
        let indices = iu
            .iter()
            .flat_map(|&i| iv.iter().map(move |&j| (i * grid.nv + j) as u32))
            .collect();
        (indices, geode_geo::PatchBasis { u: ku, v: kv })
    }

    /// The finest level as quads: `su` x `sv` samples (a wrapped direction
    /// closes on itself, so a torus is a closed mesh), with unit normals and
    /// the normalized parameters as uv. One level is tessellated, so no
    /// coarser level shows through and no crack opens.
    pub fn tessellate(&self, su: usize, sv: usize) -> crate::bspline::Tessellation {
        let g = self
            .grid(self.levels() - 1)
            .expect("the finest level exists");
        self.tessellate_grid(&g, su, sv)
    }

    /// Tessellates a finest-level grid computed elsewhere (e.g. enveloped).
    pub fn tessellate_grid(&self, g: &Grid, su: usize, sv: usize) -> crate::bspline::Tessellation {
        use geode_geo::glam::Vec2;
        let wrap = self.wrap();
        let (su, sv) = (su.max(3), sv.max(3));
        let param = |k: usize, n: usize, closed: bool| {
            if closed {
                k as f64 / n as f64
            } else {
                k as f64 / (n - 1) as f64
            }
        };
        let mut t = crate::bspline::Tessellation::default();
        for i in 0..su {
            for j in 0..sv {
                let (s, v) = (param(i, su, wrap.0), param(j, sv, wrap.1));
                let (p, pu, pv) = evaluate(g, wrap, s, v);
                t.positions.push(p.as_vec3());
                t.normals.push(frame(pu, pv)[0].as_vec3());
                t.uvs.push(Vec2::new(s as f32, v as f32));
            }
        }
        let (cu, cv) = (
            if wrap.0 { su } else { su - 1 },
            if wrap.1 { sv } else { sv - 1 },
        );
        let id = |i: usize, j: usize| ((i % su) * sv + j % sv) as u32;
        for i in 0..cu {
            for j in 0..cv {
                t.quads
                    .push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        t
    }
}

#[cfg(test)]
mod tests;
