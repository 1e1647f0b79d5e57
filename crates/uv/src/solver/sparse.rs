//! Complex sparse matrices in compressed rows, with deterministic parallel
//! products: each output row is computed by one task in one order.

use rayon::prelude::*;

use super::{Complex, CHUNK};

/// Row `i` holds columns `cols[offsets[i]..offsets[i+1]]` (ascending,
/// unique) and their values.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Csr {
    pub ncols: usize,
    pub offsets: Vec<usize>,
    pub cols: Vec<u32>,
    pub values: Vec<Complex>,
}

impl Csr {
    pub fn rows(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Row `i`'s columns and values.
    pub fn row(&self, i: usize) -> (&[u32], &[Complex]) {
        let span = self.offsets[i]..self.offsets[i + 1];
        (&self.cols[span.clone()], &self.values[span])
    }

    /// The real parts of the diagonal (0 where a row has none).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.rows())
            .map(|i| {
                let (cols, values) = self.row(i);
                cols.binary_search(&(i as u32))
                    .map_or(0.0, |k| values[k].re)
            })
            .collect()
    }

    /// `y = A x`, and with it the real inner product `<x, A x>` (square
    /// matrices only) summed chunk by chunk in order.
    pub fn multiply_and_dot(&self, x: &[Complex], y: &mut [Complex]) -> f64 {
        let partials: Vec<f64> = y
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(chunk, y_chunk)| {
                let first = chunk * CHUNK;
                let mut dot = 0.0;
                for (k, out) in y_chunk.iter_mut().enumerate() {
                    let row = first + k;
                    *out = self.row_times(row, x);
                    if let Some(xr) = x.get(row) {
                        dot += xr.dot(*out);
                    }
                }
                dot
            })
            .collect();
        partials.iter().sum()
    }

    /// `y = A x`.
    pub fn multiply(&self, x: &[Complex], y: &mut [Complex]) {
        y.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(chunk, y_chunk)| {
                for (k, out) in y_chunk.iter_mut().enumerate() {
                    *out = self.row_times(chunk * CHUNK + k, x);
                }
            });
    }

    fn row_times(&self, row: usize, x: &[Complex]) -> Complex {
        let (cols, values) = self.row(row);
        let mut sum = Complex::ZERO;
        for (&col, &value) in cols.iter().zip(values) {
            sum += value * x[col as usize];
        }
        sum
    }

    /// The conjugate transpose (rows in order, so columns stay sorted).
    pub fn adjoint(&self) -> Csr {
        let mut offsets = vec![0usize; self.ncols + 1];
        for &c in &self.cols {
            offsets[c as usize + 1] += 1;
        }
        for i in 0..self.ncols {
            offsets[i + 1] += offsets[i];
        }
        let mut cursor = offsets.clone();
        let mut cols = vec![0u32; self.cols.len()];
        let mut values = vec![Complex::ZERO; self.cols.len()];
        for row in 0..self.rows() {
            let (rc, rv) = self.row(row);
            for (&c, &v) in rc.iter().zip(rv) {
                let at = cursor[c as usize];
                cols[at] = row as u32;
                values[at] = v.conj();
                cursor[c as usize] += 1;
            }
        }
        Csr {
            ncols: self.rows(),
            offsets,
            cols,
            values,
        }
    }

    /// The product `A B`, rows in parallel (each accumulated in the order
    /// of A's row and then B's rows).
    pub fn times(&self, b: &Csr) -> Csr {
        let blocks: Vec<(Vec<usize>, Vec<u32>, Vec<Complex>)> = (0..self.rows())
            .collect::<Vec<_>>()
            .par_chunks(CHUNK)
            .map(|rows| {
                let mut accumulator = vec![Complex::ZERO; b.ncols];
                let mut touched = vec![false; b.ncols];
                let mut lens = Vec::with_capacity(rows.len());
                let (mut cols, mut values) = (Vec::new(), Vec::new());
                let mut row_cols: Vec<u32> = Vec::new();
                for &i in rows {
                    row_cols.clear();
                    let (ac, av) = self.row(i);
                    for (&j, &a) in ac.iter().zip(av) {
                        let (bc, bv) = b.row(j as usize);
                        for (&k, &bk) in bc.iter().zip(bv) {
                            if !touched[k as usize] {
                                touched[k as usize] = true;
                                row_cols.push(k);
                            }
                            accumulator[k as usize] += a * bk;
                        }
                    }
                    row_cols.sort_unstable();
                    for &k in &row_cols {
                        cols.push(k);
                        values.push(accumulator[k as usize]);
                        accumulator[k as usize] = Complex::ZERO;
                        touched[k as usize] = false;
                    }
                    lens.push(row_cols.len());
                }
                (lens, cols, values)
            })
            .collect();
        let mut out = Csr {
            ncols: b.ncols,
            offsets: vec![0],
            ..Csr::default()
        };
        for (lens, cols, values) in blocks {
            for len in lens {
                let last = out.offsets[out.offsets.len() - 1];
                out.offsets.push(last + len);
            }
            out.cols.extend(cols);
            out.values.extend(values);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [[2, 1+i], [1-i, 3]]
    fn small() -> Csr {
        Csr {
            ncols: 2,
            offsets: vec![0, 2, 4],
            cols: vec![0, 1, 0, 1],
            values: vec![
                Complex::new(2.0, 0.0),
                Complex::new(1.0, 1.0),
                Complex::new(1.0, -1.0),
                Complex::new(3.0, 0.0),
            ],
        }
    }

    #[test]
    fn product_of_a_small_hermitian_matrix() {
        let a = small();
        let x = [Complex::new(1.0, 0.0), Complex::new(0.0, 1.0)];
        let mut y = [Complex::ZERO; 2];
        let xax = a.multiply_and_dot(&x, &mut y);
        // y0 = 2 + (1+i) i = 1 + i; y1 = (1-i) + 3i = 1 + 2i.
        assert_eq!(y, [Complex::new(1.0, 1.0), Complex::new(1.0, 2.0)]);
        assert_eq!(xax, 1.0 + 2.0);
        assert_eq!(a.diagonal(), vec![2.0, 3.0]);
    }

    #[test]
    fn adjoint_and_product() {
        let a = small();
        assert_eq!(a.adjoint(), a, "Hermitian");
        // A A: [[4 + 2, 2(1+i) + 3(1+i)], [..., 2 + 9]]
        let aa = a.times(&a);
        assert_eq!(
            aa.row(0).1,
            &[Complex::new(6.0, 0.0), Complex::new(5.0, 5.0)]
        );
        assert_eq!(aa.row(1).1[1], Complex::new(11.0, 0.0));
    }
}
