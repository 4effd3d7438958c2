//! Compressed sparse rows: the operators of the multigrid hierarchy (A on each level, P and
//! its transpose) with the products the hierarchy is built from. Rows are computed
//! independently (in parallel), so results do not depend on the thread count.

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

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.idx.len()
    }

    /// Entries of row r.
    pub fn row(&self, r: usize) -> (&[u32], &[f64]) {
        let (lo, hi) = (self.ptr[r], self.ptr[r + 1]);
        (&self.idx[lo..hi], &self.val[lo..hi])
    }

    /// The diagonal (0 where absent).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.rows)
            .map(|r| {
                let (idx, val) = self.row(r);
                idx.binary_search(&(r as u32)).map_or(0.0, |k| val[k])
            })
            .collect()
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

    /// y += A x.
    pub fn add_times(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(CHUNK).enumerate().for_each(|(c, ys)| {
            for (k, y) in ys.iter_mut().enumerate() {
                let (idx, val) = self.row(c * CHUNK + k);
                *y += idx.iter().zip(val).map(|(&j, v)| v * x[j as usize]).sum::<f64>();
            }
        });
    }

    /// Aᵀ.
    pub fn transpose(&self) -> Self {
        let mut count = vec![0usize; self.cols + 1];
        for &j in &self.idx {
            count[j as usize + 1] += 1;
        }
        for c in 0..self.cols {
            count[c + 1] += count[c];
        }
        let ptr = count.clone();
        let (mut idx, mut val) = (vec![0u32; self.nnz()], vec![0.0; self.nnz()]);
        for r in 0..self.rows {
            let (ri, rv) = self.row(r);
            for (&j, &v) in ri.iter().zip(rv) {
                let j = j as usize;
                (idx[count[j]], val[count[j]]) = (r as u32, v);
                count[j] += 1;
            }
        }
        Self { rows: self.cols, cols: self.rows, ptr, idx, val }
    }

    /// A B (Gustavson's row-by-row product with a dense accumulator per task).
    pub fn times_matrix(&self, b: &Csr) -> Self {
        debug_assert_eq!(self.cols, b.rows);
        let chunks: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = (0..self.rows.div_ceil(CHUNK))
            .into_par_iter()
            // The dense accumulator of a row, once per rayon job rather than per chunk: the kernel
            // zeroes every fresh page, and per chunk that was 4–5 % of a 10⁵-ME static run.
            .map_init(
                || (vec![0.0; b.cols], vec![false; b.cols], Vec::new()),
                |(acc, seen, touched): &mut (Vec<f64>, Vec<bool>, Vec<u32>), c| {
                    let (mut lens, mut idx, mut val) = (Vec::new(), Vec::new(), Vec::new());
                    for r in c * CHUNK..((c + 1) * CHUNK).min(self.rows) {
                        let (ai, av) = self.row(r);
                        for (&k, &a) in ai.iter().zip(av) {
                            let (bi, bv) = b.row(k as usize);
                            for (&j, &v) in bi.iter().zip(bv) {
                                if !seen[j as usize] {
                                    seen[j as usize] = true;
                                    touched.push(j);
                                }
                                acc[j as usize] += a * v;
                            }
                        }
                        touched.sort_unstable();
                        for &j in touched.iter() {
                            idx.push(j);
                            val.push(acc[j as usize]);
                            (acc[j as usize], seen[j as usize]) = (0.0, false);
                        }
                        lens.push(touched.len());
                        touched.clear();
                    }
                    (lens, idx, val)
                },
            )
            .collect();
        let mut ptr = Vec::with_capacity(self.rows + 1);
        ptr.push(0);
        let total = chunks.iter().map(|c| c.1.len()).sum();
        let (mut idx, mut val) = (Vec::with_capacity(total), Vec::with_capacity(total));
        for (lens, i, v) in chunks {
            for l in lens {
                ptr.push(ptr.last().unwrap() + l);
            }
            idx.extend(i);
            val.extend(v);
        }
        Self { rows: self.rows, cols: b.cols, ptr, idx, val }
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

    fn from_dense(d: &[Vec<f64>]) -> Csr {
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        for row in d {
            for (j, &x) in row.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                idx.push(j as u32);
                val.push(x);
            }
            ptr.push(idx.len());
        }
        Csr { rows: d.len(), cols: d[0].len(), ptr, idx, val }
    }

    #[test]
    fn products_and_transposes_match_dense_arithmetic() {
        let a: Vec<Vec<f64>> = (0..7)
            .map(|i| (0..5).map(|j| if (i * 3 + j) % 4 == 0 { (i + 2 * j) as f64 - 3.5 } else { 0.0 }).collect())
            .collect();
        let b: Vec<Vec<f64>> = (0..5)
            .map(|i| (0..6).map(|j| if (i + j) % 3 == 1 { 1.0 + (i * j) as f64 } else { 0.0 }).collect())
            .collect();
        let (sa, sb) = (from_dense(&a), from_dense(&b));
        let ab = dense(&sa.times_matrix(&sb));
        for i in 0..7 {
            for j in 0..6 {
                let want: f64 = (0..5).map(|k| a[i][k] * b[k][j]).sum();
                assert!((ab[i][j] - want).abs() < 1e-12);
            }
        }
        let t = dense(&sa.transpose());
        (0..7).for_each(|i| (0..5).for_each(|j| assert_eq!(t[j][i], a[i][j])));
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
