//! Sparsity of the global matrix: lower triangle in compressed sparse columns, from the
//! cliques of free covers coupled by each ME (tied covers replaced by their masters). Built
//! once; values are refilled every step (the symbolic factorisation is reused).

use std::collections::BTreeSet;

use super::dof_map::DofMap;

/// Lower-triangular CSC pattern.
#[derive(Debug, Clone)]
pub struct SparsityPattern {
    /// Matrix order.
    pub n: usize,
    /// Column pointers (n + 1).
    pub col_ptr: Vec<u32>,
    /// Row indices, sorted within each column, all ≥ the column.
    pub row_idx: Vec<u32>,
}

impl SparsityPattern {
    /// Pattern of the union of the cliques (lists of free covers coupled together).
    pub fn from_cliques<'a>(dofs: &DofMap, n_covers: usize, cliques: impl Iterator<Item = &'a [usize]>) -> Self {
        let mut nbr: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n_covers];
        for clique in cliques {
            for &a in clique {
                for &b in clique {
                    if let (Some(ea), Some(eb)) = (dofs.eq(a, 0), dofs.eq(b, 0)) {
                        if eb >= ea {
                            let _ = nbr[a].insert(b);
                        }
                    }
                }
            }
        }
        let n = dofs.n_eq;
        let mut col_ptr = vec![0u32; n + 1];
        let mut row_idx = Vec::new();
        let mut order: Vec<usize> = (0..n_covers).filter(|&c| dofs.eq(c, 0).is_some()).collect();
        order.sort_by_key(|&c| dofs.eq(c, 0));
        for &c in &order {
            let first = dofs.eq(c, 0).expect("free");
            let mut rows: Vec<usize> = nbr[c].iter().flat_map(|&d| (0..3).map(move |i| dofs.eq(d, i).expect("free"))).collect();
            rows.sort_unstable();
            for j in 0..3 {
                let col = first + j;
                row_idx.extend(rows.iter().filter(|&&r| r >= col).map(|&r| r as u32));
                col_ptr[col + 1] = row_idx.len() as u32;
            }
        }
        Self { n, col_ptr, row_idx }
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
}
