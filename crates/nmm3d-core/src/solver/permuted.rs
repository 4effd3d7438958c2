//! The matrix in the factor's order: the fill-reducing permutation applied once to the pattern
//! (lower triangle, sorted columns), with the source entry of each of its entries. A numeric
//! factorisation then gathers the values along that map; handed the unpermuted matrix, faer
//! permutes it by a counting sort on every call (6 % of the fine-cover dominos' run, issue 10).

use super::ordering::Permutation;
use crate::assembly::SparsityPattern;

/// A lower-triangle pattern permuted symmetrically, and where its values come from.
pub struct Permuted {
    /// The permutation (`forward[new] = old`).
    pub perm: Permutation,
    /// The permuted lower triangle, rows sorted within each column.
    pub lower: SparsityPattern,
    /// For each entry of `lower`, the index of its entry in the source's values.
    source: Vec<u32>,
}

impl Permuted {
    /// Permute pattern `p` by `perm`: entry (i, j) goes to (max(i′, j′), min(i′, j′)).
    pub fn new(p: &SparsityPattern, perm: Permutation) -> Self {
        let (n, inv) = (p.n, &perm.inverse);
        let moved = |e: usize, j: usize| {
            let (a, b) = (inv[p.row_idx[e] as usize], inv[j]);
            (a.max(b), a.min(b))
        };
        let mut col_ptr = vec![0u32; n + 1];
        for j in 0..n {
            for e in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                col_ptr[moved(e, j).1 as usize + 1] += 1;
            }
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut next: Vec<u32> = col_ptr[..n].to_vec();
        let mut entries = vec![(0u32, 0u32); p.row_idx.len()];
        for j in 0..n {
            for e in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                let (row, col) = moved(e, j);
                entries[next[col as usize] as usize] = (row, e as u32);
                next[col as usize] += 1;
            }
        }
        for c in 0..n {
            entries[col_ptr[c] as usize..col_ptr[c + 1] as usize].sort_unstable();
        }
        let (row_idx, source) = entries.into_iter().unzip();
        Self { perm, lower: SparsityPattern { n, col_ptr, row_idx }, source }
    }

    /// The pattern in the source's order again (lower triangle, sorted columns).
    pub fn original(&self) -> SparsityPattern {
        let back = Permutation { forward: self.perm.inverse.clone(), inverse: self.perm.forward.clone() };
        Permuted::new(&self.lower, back).lower
    }

    /// The upper triangle (the transpose of `lower`; rows sorted), which faer's symbolic
    /// analysis reads.
    pub fn upper(&self) -> SparsityPattern {
        let SparsityPattern { n, col_ptr, row_idx } = &self.lower;
        let mut up_ptr = vec![0u32; n + 1];
        for &r in row_idx {
            up_ptr[r as usize + 1] += 1;
        }
        for c in 0..*n {
            up_ptr[c + 1] += up_ptr[c];
        }
        let mut next: Vec<u32> = up_ptr[..*n].to_vec();
        let mut up_rows = vec![0u32; row_idx.len()];
        // Columns in increasing order: each upper column's rows come out sorted.
        for j in 0..*n {
            for &r in &row_idx[col_ptr[j] as usize..col_ptr[j + 1] as usize] {
                up_rows[next[r as usize] as usize] = j as u32;
                next[r as usize] += 1;
            }
        }
        SparsityPattern { n: *n, col_ptr: up_ptr, row_idx: up_rows }
    }

    /// The source's `values` in the permuted order.
    pub fn gather(&self, values: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.source.iter().map(|&s| values[s as usize]));
    }

    /// `x` (original order) into `out` in the permuted order.
    pub fn permute_into(&self, x: &[f64], out: &mut [f64]) {
        out.iter_mut().zip(&self.perm.forward).for_each(|(o, &old)| *o = x[old as usize]);
    }

    /// `y` (permuted order) back into `x` in the original order.
    pub fn unpermute_into(&self, y: &[f64], x: &mut [f64]) {
        y.iter().zip(&self.perm.forward).for_each(|(&v, &old)| x[old as usize] = v);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense symmetric matrix of a lower pattern with values.
    fn dense(p: &SparsityPattern, v: &[f64]) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; p.n]; p.n];
        for j in 0..p.n {
            for e in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                let i = p.row_idx[e] as usize;
                (a[i][j], a[j][i]) = (v[e], v[e]);
            }
        }
        a
    }

    #[test]
    fn the_permuted_matrix_is_p_a_p_transposed_with_sorted_columns() {
        // A random lower pattern (seeded), with the diagonal, and a scrambled order.
        let n = 40;
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 33) as usize
        };
        let (mut col_ptr, mut row_idx) = (vec![0u32], Vec::new());
        for j in 0..n {
            let mut rows: Vec<u32> = (0..4).map(|_| (j + next() % (n - j)) as u32).chain([j as u32]).collect();
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend(rows);
            col_ptr.push(row_idx.len() as u32);
        }
        let p = SparsityPattern { n, col_ptr, row_idx };
        let values: Vec<f64> = (0..p.row_idx.len()).map(|e| 1.0 + e as f64).collect();
        let forward: Vec<u32> = (0..n as u32).map(|i| (7 * i + 3) % n as u32).collect();
        let mut inverse = vec![0u32; n];
        forward.iter().enumerate().for_each(|(new, &old)| inverse[old as usize] = new as u32);
        let q = Permuted::new(&p, Permutation { forward: forward.clone(), inverse });
        let mut permuted = Vec::new();
        q.gather(&values, &mut permuted);
        let (a, b) = (dense(&p, &values), dense(&q.lower, &permuted));
        for (r, row) in b.iter().enumerate() {
            for (c, &x) in row.iter().enumerate() {
                assert_eq!(x, a[forward[r] as usize][forward[c] as usize]);
            }
        }
        for j in 0..n {
            let rows = &q.lower.row_idx[q.lower.col_ptr[j] as usize..q.lower.col_ptr[j + 1] as usize];
            assert!(rows.windows(2).all(|w| w[0] < w[1]) && rows.iter().all(|&r| r as usize >= j));
        }
        // The upper triangle is the transpose, sorted too.
        let up = q.upper();
        for j in 0..n {
            let rows = &up.row_idx[up.col_ptr[j] as usize..up.col_ptr[j + 1] as usize];
            assert!(rows.windows(2).all(|w| w[0] < w[1]) && rows.iter().all(|&r| r as usize <= j));
            assert!(rows.iter().all(|&r| b[r as usize][j] != 0.0));
        }
        assert_eq!(up.row_idx.len(), q.lower.row_idx.len());
        // Vectors go there and back.
        let x: Vec<f64> = (0..n).map(|i| i as f64 * 0.5).collect();
        let (mut y, mut back) = (vec![0.0; n], vec![0.0; n]);
        q.permute_into(&x, &mut y);
        q.unpermute_into(&y, &mut back);
        assert_eq!(back, x);
        assert_eq!(y[0], x[forward[0] as usize]);
    }
}
