//! Compressed sparse rows: the finest level's operator as assembled (the whole symmetric
//! matrix from its lower triangle), PCG's products with it, and the way back to a lower
//! triangle for a direct factorisation. The hierarchy itself is stored by blocks (`bsr.rs`).

use rayon::prelude::*;

use crate::assembly::SparsityPattern;

/// A sparse matrix by rows, column indices sorted within each row.
#[derive(Debug, Clone, PartialEq)]
pub struct Csr {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Row pointers (rows + 1).
    pub ptr: Vec<usize>,
    /// Column indices.
    pub idx: Vec<u32>,
    /// Values.
    pub val: Vec<f64>,
}

/// Rows in one parallel task (rows are cheap; tasks must not be).
const CHUNK: usize = 4096;

impl Csr {
    /// The whole symmetric matrix whose lower triangle `values` holds on `p` (by columns).
    pub fn from_lower(p: &SparsityPattern, values: &[f64]) -> Self {
        let n = p.n;
        let mut count = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
                count[i as usize + 1] += 1;
                if i as usize != j {
                    count[j + 1] += 1;
                }
            }
        }
        for r in 0..n {
            count[r + 1] += count[r];
        }
        let ptr = count.clone();
        let (mut idx, mut val) = (vec![0u32; ptr[n]], vec![0.0; ptr[n]]);
        // Column by column: row i receives column j in increasing j, and row j its own column's
        // entries (i ≥ j) after every earlier column's — each row comes out sorted.
        for j in 0..n {
            let (lo, hi) = (p.col_ptr[j] as usize, p.col_ptr[j + 1] as usize);
            for (&i, &v) in p.row_idx[lo..hi].iter().zip(&values[lo..hi]) {
                let i = i as usize;
                (idx[count[i]], val[count[i]]) = (j as u32, v);
                count[i] += 1;
                if i != j {
                    (idx[count[j]], val[count[j]]) = (i as u32, v);
                    count[j] += 1;
                }
            }
        }
        Self { rows: n, cols: n, ptr, idx, val }
    }

    /// The lower triangle by columns (= the upper triangle by rows) of this symmetric matrix.
    pub fn to_lower(&self) -> (SparsityPattern, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for r in 0..self.rows {
            for k in self.ptr[r]..self.ptr[r + 1] {
                if self.idx[k] as usize >= r {
                    row_idx.push(self.idx[k]);
                    values.push(self.val[k]);
                }
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (SparsityPattern { n: self.rows, col_ptr, row_idx }, values)
    }

    /// Entries of row r.
    pub fn row(&self, r: usize) -> (&[u32], &[f64]) {
        let (lo, hi) = (self.ptr[r], self.ptr[r + 1]);
        (&self.idx[lo..hi], &self.val[lo..hi])
    }

    /// y = A x.
    pub fn times(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, ys)| {
            for (k, y) in ys.iter_mut().enumerate() {
                let (idx, val) = self.row(c * CHUNK + k);
                *y = idx.iter().zip(val).map(|(&j, v)| v * x[j as usize]).sum();
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dense(a: &Csr) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; a.cols]; a.rows];
        for (r, row) in d.iter_mut().enumerate() {
            let (i, v) = a.row(r);
            i.iter().zip(v).for_each(|(&j, &x)| row[j as usize] += x);
        }
        d
    }

    #[test]
    fn the_whole_symmetric_matrix_round_trips_through_its_lower_triangle() {
        let p = SparsityPattern { n: 3, col_ptr: vec![0, 3, 4, 5], row_idx: vec![0, 1, 2, 1, 2] };
        let v = vec![4.0, -1.0, 0.5, 3.0, 2.0];
        let a = Csr::from_lower(&p, &v);
        assert_eq!(dense(&a), vec![vec![4.0, -1.0, 0.5], vec![-1.0, 3.0, 0.0], vec![0.5, 0.0, 2.0]]);
        assert_eq!(a.to_lower(), (p.clone(), v.clone()));
        let (x, mut y, mut z) = ([1.0, 2.0, -1.0], vec![0.0; 3], vec![0.0; 3]);
        a.times(&x, &mut y);
        p.symmetric_times(&v, &x, &mut z);
        assert_eq!(y, z);
    }
}
