//! Sparsity of the global matrix: lower triangle in compressed sparse columns, from the
//! cliques of free covers coupled by each ME (tied covers replaced by their masters). Built
//! once; values are refilled every step (the symbolic factorisation is reused). Contacts grow
//! it by further cliques ([`SparsityPattern::with_cliques`]); values on the elements' pattern
//! reach the grown one through an embedding map ([`SparsityPattern::embedding`]).
//!
//! Layout: a free cover owns three consecutive equations 3b, 3b + 1, 3b + 2 (block b), and the
//! three columns of block b hold the same blocks of rows. So entry (3a + i, 3b + j), a ≥ b,
//! sits at `col_ptr[3b + j] + off(a, b) + i − j`, with off(a, b) the offset of row 3a in
//! column 3b (valid for a > b and all i, j; for a = b when i ≥ j) — one search per pair of
//! blocks finds nine entries ([`SparsityPattern::block_offset`]).

use super::dof_map::DofMap;

/// Marks an entry of one pattern missing from another (see [`SparsityPattern::embedding`]).
pub const ABSENT: u32 = u32::MAX;

/// Lower-triangular CSC pattern.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SparsityPattern {
    /// Matrix order.
    pub n: usize,
    /// Column pointers (n + 1).
    #[serde(with = "crate::packed::u32s")]
    pub col_ptr: Vec<u32>,
    /// Row indices, sorted within each column, all ≥ the column.
    #[serde(with = "crate::packed::u32s")]
    pub row_idx: Vec<u32>,
}

impl SparsityPattern {
    /// Pattern of the union of the cliques (lists of covers coupled together; fixed and tied
    /// covers are skipped — pass the masters of tied ones).
    pub fn from_cliques<'a>(dofs: &DofMap, cliques: impl Iterator<Item = &'a [usize]>) -> Self {
        let mut rows = vec![Vec::new(); dofs.n_eq / 3];
        add_cliques(&mut rows, dofs, cliques);
        Self::from_block_rows(dofs.n_eq, rows)
    }

    /// This pattern with the couplings of further cliques added.
    pub fn with_cliques<'a>(&self, dofs: &DofMap, cliques: impl Iterator<Item = &'a [usize]>) -> Self {
        let mut rows: Vec<Vec<u32>> = (0..self.n / 3).map(|b| self.block_rows(b).collect()).collect();
        add_cliques(&mut rows, dofs, cliques);
        Self::from_block_rows(self.n, rows)
    }

    /// Where each entry of this pattern sits in `into`: `map[old] = new`, or [`ABSENT`] for an
    /// entry `into` does not hold (a contact coupling dropped).
    pub fn embedding(&self, into: &Self) -> Vec<u32> {
        debug_assert_eq!(self.n, into.n);
        let mut map = Vec::with_capacity(self.nnz());
        for col in 0..self.n {
            let (lo, hi) = (into.col_ptr[col] as usize, into.col_ptr[col + 1] as usize);
            let target = &into.row_idx[lo..hi];
            let mut k = 0;
            for &r in &self.row_idx[self.col_ptr[col] as usize..self.col_ptr[col + 1] as usize] {
                while k < target.len() && target[k] < r {
                    k += 1;
                }
                map.push(if k < target.len() && target[k] == r { (lo + k) as u32 } else { ABSENT });
            }
        }
        map
    }

    /// Offset of row 3a within column 3b (a ≥ b are blocks), if the blocks are coupled.
    pub fn block_offset(&self, a: usize, b: usize) -> Option<u32> {
        let (lo, hi) = (self.col_ptr[3 * b] as usize, self.col_ptr[3 * b + 1] as usize);
        self.row_idx[lo..hi].binary_search(&(3 * a as u32)).ok().map(|k| k as u32)
    }

    /// Position of entry (row, col) with row ≥ col in the value array.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (lo, hi) = (self.col_ptr[col] as usize, self.col_ptr[col + 1] as usize);
        self.row_idx[lo..hi].binary_search(&(row as u32)).ok().map(|k| lo + k)
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// xᵀ A x for the symmetric matrix whose lower triangle `values` holds on this pattern.
    pub fn quadratic_form(&self, values: &[f64], x: &[f64]) -> f64 {
        let mut sum = 0.0;
        for j in 0..self.n {
            for p in self.col_ptr[j] as usize..self.col_ptr[j + 1] as usize {
                let i = self.row_idx[p] as usize;
                let v = values[p] * x[i] * x[j];
                sum += if i == j { v } else { 2.0 * v };
            }
        }
        sum
    }

    /// Blocks of rows (≥ b) coupled to block b.
    fn block_rows(&self, b: usize) -> impl Iterator<Item = u32> + '_ {
        self.row_idx[self.col_ptr[3 * b] as usize..self.col_ptr[3 * b + 1] as usize].iter().step_by(3).map(|r| r / 3)
    }

    /// The pattern whose block column b couples the blocks `rows[b]` (each block with itself).
    fn from_block_rows(n: usize, mut rows: Vec<Vec<u32>>) -> Self {
        let mut col_ptr = vec![0u32; n + 1];
        let mut row_idx = Vec::with_capacity(rows.iter().map(|r| 9 * r.len()).sum());
        for (b, r) in rows.iter_mut().enumerate() {
            r.push(b as u32);
            r.sort_unstable();
            r.dedup();
            for j in 0..3 {
                let col = 3 * b + j;
                for &a in r.iter() {
                    row_idx.extend((0..3).map(|i| 3 * a + i).filter(|&row| row as usize >= col));
                }
                col_ptr[col + 1] = row_idx.len() as u32;
            }
        }
        Self { n, col_ptr, row_idx }
    }
}

/// Append to `rows[b]` the blocks a ≥ b each clique couples to b.
fn add_cliques<'a>(rows: &mut [Vec<u32>], dofs: &DofMap, cliques: impl Iterator<Item = &'a [usize]>) {
    let mut blocks = Vec::new();
    for clique in cliques {
        blocks.clear();
        blocks.extend(clique.iter().filter_map(|&c| dofs.eq(c, 0)).map(|e| (e / 3) as u32));
        for &b in &blocks {
            rows[b as usize].extend(blocks.iter().filter(|&&a| a >= b));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dofs(n: usize) -> DofMap {
        DofMap::new(&vec![false; n], &vec![None; n])
    }

    #[test]
    fn block_offsets_find_every_entry() {
        let d = dofs(5);
        let p = SparsityPattern::from_cliques(&d, [&[0usize, 2, 4][..], &[1, 2]].into_iter());
        for (a, b) in [(0, 0), (2, 0), (4, 0), (4, 2), (2, 1), (2, 2)] {
            let off = p.block_offset(a, b).expect("coupled") as usize;
            for j in 0..3 {
                for i in (0..3).filter(|&i| a > b || i >= j) {
                    let at = p.col_ptr[3 * b + j] as usize + off + i - j;
                    assert_eq!(Some(at), p.position(3 * a + i, 3 * b + j), "({a}, {b}) entry ({i}, {j})");
                }
            }
        }
        assert_eq!(p.block_offset(3, 0), None);
        assert_eq!(p.block_offset(4, 1), None);
    }

    #[test]
    fn growing_keeps_every_entry() {
        let d = dofs(6);
        let p = SparsityPattern::from_cliques(&d, [&[0usize, 1][..], &[2, 3], &[4, 5]].into_iter());
        let grown = p.with_cliques(&d, [&[1usize, 4][..], &[0, 5]].into_iter());
        assert!(grown.nnz() > p.nnz());
        let map = p.embedding(&grown);
        for col in 0..p.n {
            let (lo, hi) = (p.col_ptr[col] as usize, p.col_ptr[col + 1] as usize);
            for (&row, &at) in p.row_idx[lo..hi].iter().zip(&map[lo..hi]) {
                assert_eq!(Some(at as usize), grown.position(row as usize, col), "entry ({row}, {col})");
            }
        }
        assert!(grown.position(3 * 4, 3).is_some() && grown.position(3 * 5, 0).is_some());
        // Entries the other pattern lacks are marked absent.
        let back = grown.embedding(&p);
        assert_eq!(back.iter().filter(|&&k| k == ABSENT).count(), grown.nnz() - p.nnz());
        // Growing by couplings already present changes nothing.
        assert_eq!(p.with_cliques(&d, [&[0usize, 1][..]].into_iter()).row_idx, p.row_idx);
    }

    #[test]
    fn the_product_uses_both_triangles() {
        let d = dofs(3);
        let p = SparsityPattern::from_cliques(&d, [&[0usize, 2][..], &[1, 2]].into_iter());
        let values: Vec<f64> = (0..p.nnz()).map(|k| 1.0 + k as f64 * 0.37).collect();
        let x: Vec<f64> = (0..p.n).map(|i| (i as f64 * 1.3).sin()).collect();
        let mut dense = vec![vec![0.0; p.n]; p.n];
        for j in 0..p.n {
            for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                let i = p.row_idx[k] as usize;
                (dense[i][j], dense[j][i]) = (values[k], values[k]);
            }
        }
        let mut y = vec![f64::NAN; p.n];
        p.symmetric_times(&values, &x, &mut y);
        for i in 0..p.n {
            let expected: f64 = (0..p.n).map(|j| dense[i][j] * x[j]).sum();
            assert!((y[i] - expected).abs() <= 1e-12 * expected.abs().max(1.0), "row {i}");
        }
        let xax: f64 = x.iter().zip(&y).map(|(a, b)| a * b).sum();
        assert!((p.quadratic_form(&values, &x) - xax).abs() <= 1e-12 * xax.abs());
    }
}
