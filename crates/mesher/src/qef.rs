//! The quadratic error function of dual contouring: the point closest (in
//! least squares) to a set of tangent planes, solved with a truncated
//! pseudo-inverse around the planes' mass point so flat regions stay stable.

/// Accumulates planes `n . x = n . p`.
#[derive(Clone, Copy, Debug, Default)]
pub struct Qef {
    ata: [[f64; 3]; 3],
    atb: [f64; 3],
    btb: f64,
    mass: [f64; 3],
    count: u32,
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations:
/// eigenvalues and the matrix whose columns are the eigenvectors.
fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    // Converged when the off-diagonal is a 1e-12 part of the diagonal:
    // eigenvalues are then exact to rounding (their error is quadratic in
    // it) and eigenvectors to 1e-12, far below what ranks and vertices
    // read; relative, so tiny and huge matrices stop as early as unit ones.
    let scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
    for _sweep in 0..32 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off <= 1e-24 * scale || off < 1e-300 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A <- J^T A J for the rotation J in the (p, q) plane.
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

impl Qef {
    /// Adds the plane through `p` with normal `n` (unit length).
    pub fn add(&mut self, p: [f64; 3], n: [f64; 3]) {
        let d = n[0] * p[0] + n[1] * p[1] + n[2] * p[2];
        for i in 0..3 {
            for j in 0..3 {
                self.ata[i][j] += n[i] * n[j];
            }
            self.atb[i] += n[i] * d;
            self.mass[i] += p[i];
        }
        self.btb += d * d;
        self.count += 1;
    }

    /// The planes of both (QEFs are sums of squares, so they add).
    pub fn merge(&mut self, o: &Qef) {
        for i in 0..3 {
            for j in 0..3 {
                self.ata[i][j] += o.ata[i][j];
            }
            self.atb[i] += o.atb[i];
            self.mass[i] += o.mass[i];
        }
        self.btb += o.btb;
        self.count += o.count;
    }

    /// The sum of squared distances from `x` to the planes.
    pub fn error(&self, x: [f64; 3]) -> f64 {
        let mut e = self.btb;
        for i in 0..3 {
            let ax: f64 = (0..3).map(|j| self.ata[i][j] * x[j]).sum();
            e += x[i] * ax - 2.0 * x[i] * self.atb[i];
        }
        e.max(0.0)
    }

    pub fn count(&self) -> u32 {
        self.count
    }

    pub fn mass_point(&self) -> [f64; 3] {
        let k = 1.0 / self.count.max(1) as f64;
        self.mass.map(|m| m * k)
    }

    /// The eigen-decomposition the minimisers of every rank are read from.
    pub fn solver(&self) -> Solver {
        let c = self.mass_point();
        // Minimisers are x = c + y with A^T A y = A^T b - A^T A c.
        let mut rhs = self.atb;
        for (i, r) in rhs.iter_mut().enumerate() {
            *r -= self.ata[i][0] * c[0] + self.ata[i][1] * c[1] + self.ata[i][2] * c[2];
        }
        let (w, v) = symmetric_eigen(self.ata);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| w[b].abs().total_cmp(&w[a].abs()));
        Solver {
            mass: c,
            rhs,
            w: order.map(|k| w[k]),
            v: order.map(|k| [v[0][k], v[1][k], v[2][k]]),
        }
    }

    /// The minimiser, with singular values below `truncate` times the
    /// largest treated as zero (those directions stay at the mass point).
    #[cfg(test)]
    pub fn solve(&self, truncate: f64) -> [f64; 3] {
        let s = self.solver();
        s.solve(s.rank(truncate))
    }
}

/// A QEF's minimisers by rank, around its mass point: rank 0 is the mass
/// point, each further rank adds the next strongest direction (rank 3 of a
/// box corner's planes is the corner, rank 2 a point on an edge's line).
#[derive(Clone, Copy, Debug)]
pub struct Solver {
    mass: [f64; 3],
    rhs: [f64; 3],
    /// Eigenvalues, strongest first, and their unit eigenvectors.
    w: [f64; 3],
    v: [[f64; 3]; 3],
}

impl Solver {
    /// How many directions the planes pin down: eigenvalues at least
    /// `truncate` times the largest (1 on a face, 2 on an edge, 3 at a corner).
    pub fn rank(&self, truncate: f64) -> usize {
        let wmax = self.w[0].abs();
        if wmax.is_nan() || wmax <= 0.0 {
            return 0;
        }
        self.w.iter().filter(|x| x.abs() >= truncate * wmax).count()
    }

    /// The direction left free at rank 2 (along an edge's line).
    pub fn free_direction(&self) -> [f64; 3] {
        self.v[2]
    }

    /// The least-squares point moving only along the `rank` strongest directions.
    pub fn solve(&self, rank: usize) -> [f64; 3] {
        let mut x = self.mass;
        for k in 0..rank.min(3) {
            let v = self.v[k];
            let proj = v[0] * self.rhs[0] + v[1] * self.rhs[1] + v[2] * self.rhs[2];
            for i in 0..3 {
                x[i] += v[i] * proj / self.w[k];
            }
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_of_three_planes_is_found() {
        let mut q = Qef::default();
        // Three faces of a box meeting at (1, 2, 3), sampled off the corner.
        q.add([1.0, 0.5, 0.2], [1.0, 0.0, 0.0]);
        q.add([0.3, 2.0, 0.1], [0.0, 1.0, 0.0]);
        q.add([0.1, 0.4, 3.0], [0.0, 0.0, 1.0]);
        let x = q.solve(0.1);
        assert!(
            (x[0] - 1.0).abs() < 1e-9 && (x[1] - 2.0).abs() < 1e-9 && (x[2] - 3.0).abs() < 1e-9,
            "{x:?}"
        );
    }

    #[test]
    fn an_edge_keeps_the_free_direction_at_the_mass_point() {
        let mut q = Qef::default();
        let s = std::f64::consts::FRAC_1_SQRT_2;
        q.add([0.0, 1.0, 0.2], [0.0, 1.0, 0.0]);
        q.add([1.0, 0.0, 0.6], [1.0, 0.0, 0.0]);
        q.add([1.5, 0.5, 0.4], [s, s, 0.0]);
        let x = q.solve(0.1);
        assert!(
            (x[0] - 1.0).abs() < 1e-9 && (x[1] - 1.0).abs() < 1e-9,
            "{x:?}"
        );
        assert!((x[2] - 0.4).abs() < 1e-9, "z free: the mass point's");
    }

    #[test]
    fn jacobi_diagonalises() {
        let a = [[4.0, 1.0, 2.0], [1.0, 3.0, 0.5], [2.0, 0.5, 5.0]];
        let (w, v) = symmetric_eigen(a);
        for k in 0..3 {
            for i in 0..3 {
                let av = a[i][0] * v[0][k] + a[i][1] * v[1][k] + a[i][2] * v[2][k];
                assert!((av - w[k] * v[i][k]).abs() < 1e-9);
            }
        }
    }
}
