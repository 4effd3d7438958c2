//! y = A x for a symmetric matrix stored as its lower triangle by columns: every stored entry
//! adds to two rows (its own and, mirrored, its column's), so columns cannot simply be shared
//! out between threads. Columns are cut into `PARTS` ranges of equal entry counts; a range
//! writes the rows of its own columns directly and the rows below them into its own buffer,
//! added in range order at the end — the same sums in the same order for any thread count.

use rayon::prelude::*;

use super::sparsity::SparsityPattern;

/// Column ranges computed in parallel (fixed: results must not depend on the thread count).
const PARTS: usize = 4;
/// Below this many stored entries one range does it all (a parallel call costs more).
const PARALLEL_ENTRIES: usize = 1 << 17;

impl SparsityPattern {
    /// y = A x for the symmetric matrix whose lower triangle `values` holds on this pattern.
    pub fn symmetric_times(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        if self.nnz() < PARALLEL_ENTRIES {
            return self.columns_times(values, x, 0..self.n, y, &mut []);
        }
        let nnz = self.nnz() as u64;
        let mut cuts: Vec<usize> = (0..PARTS as u64)
            .map(|t| self.col_ptr.partition_point(|&p| u64::from(p) < t * nnz / PARTS as u64).min(self.n))
            .collect();
        cuts.push(self.n);
        // Each range's own rows of y, and a buffer for the rows below them.
        let mut own = Vec::with_capacity(PARTS);
        let mut rest = &mut y[..];
        for t in 0..PARTS {
            let (head, tail) = rest.split_at_mut(cuts[t + 1] - cuts[t]);
            own.push(head);
            rest = tail;
        }
        let mut below: Vec<Vec<f64>> = (0..PARTS).map(|t| vec![0.0; self.n - cuts[t + 1]]).collect();
        own.par_iter_mut().zip(below.par_iter_mut()).enumerate().for_each(|(t, (own, below))| {
            self.columns_times(values, x, cuts[t]..cuts[t + 1], own, below);
        });
        for (t, below) in below.iter().enumerate() {
            y[cuts[t + 1]..].iter_mut().zip(below).for_each(|(y, b)| *y += b);
        }
    }

    /// The products of `columns` (c0..c1) with x: rows c0..c1 into `own`, rows from c1 on into
    /// `below`.
    fn columns_times(
        &self,
        values: &[f64],
        x: &[f64],
        columns: std::ops::Range<usize>,
        own: &mut [f64],
        below: &mut [f64],
    ) {
        let (c0, c1) = (columns.start, columns.end);
        for j in columns {
            let (lo, hi) = (self.col_ptr[j] as usize, self.col_ptr[j + 1] as usize);
            let mut column = 0.0;
            for (&i, &v) in self.row_idx[lo..hi].iter().zip(&values[lo..hi]) {
                let i = i as usize;
                if i < c1 {
                    own[i - c0] += v * x[j];
                } else {
                    below[i - c1] += v * x[j];
                }
                if i != j {
                    column += v * x[i];
                }
            }
            own[j - c0] += column;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parallel_product_equals_the_dense_one() {
        // A banded SPD-like lower triangle large enough to be cut into ranges.
        let n = 3000;
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            for i in j..(j + 60).min(n) {
                row_idx.push(i as u32);
                values.push(if i == j { 100.0 } else { ((i * 7 + j * 3) % 11) as f64 - 5.0 });
            }
            col_ptr.push(row_idx.len() as u32);
        }
        let p = SparsityPattern { n, col_ptr, row_idx };
        assert!(p.nnz() >= PARALLEL_ENTRIES);
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut y = vec![1.0; n];
        p.symmetric_times(&values, &x, &mut y);
        let mut want = vec![0.0; n];
        for j in 0..n {
            for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                let i = p.row_idx[k] as usize;
                want[i] += values[k] * x[j];
                if i != j {
                    want[j] += values[k] * x[i];
                }
            }
        }
        assert!(y.iter().zip(&want).all(|(y, w)| (y - w).abs() <= 1e-12 * w.abs().max(1.0)));
    }

    #[test]
    fn columns_without_their_diagonal_multiply_like_the_dense_matrix() {
        // Every third column stores no diagonal; the rest store it first (rows sorted).
        let n = 40;
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        let mut dense = vec![vec![0.0; n]; n];
        for j in 0..n {
            for i in (j + usize::from(j % 3 == 0)..n).step_by(4) {
                let v = ((i * 5 + j * 13) % 17) as f64 - 8.0;
                (dense[i][j], dense[j][i]) = (v, v);
                row_idx.push(i as u32);
                values.push(v);
            }
            col_ptr.push(row_idx.len() as u32);
        }
        let p = SparsityPattern { n, col_ptr, row_idx };
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.61).cos()).collect();
        let mut y = vec![0.0; n];
        p.symmetric_times(&values, &x, &mut y);
        for (r, y) in dense.iter().zip(&y) {
            let want: f64 = r.iter().zip(&x).map(|(a, x)| a * x).sum();
            assert!((y - want).abs() <= 1e-12 * want.abs().max(1.0), "{y} against {want}");
        }
    }
}
