//! Scatter of a coupling between arbitrary covers — the two MEs of a contact — into the global
//! pattern. A contact point's matrix is w wᵀ ⊗ B over the covers of both MEs (w the
//! shape-function values, B 3 × 3): tied covers fold into their masters' weights (Tᵀ w) before
//! the product and fixed covers drop out, so the sum over a pair's points lives on the pair's
//! free nodes and is scattered with one offset per pair of nodes (the pattern's block layout).

use super::dof_map::{CoverDofs, DofMap};
use super::sparsity::SparsityPattern;

/// The scatter of one clique of covers.
#[derive(Debug, Clone, PartialEq)]
pub struct Coupling {
    /// Equation block (first equation / 3) of each node: the free covers and the free masters
    /// of the tied ones, in increasing order.
    blocks: Vec<u32>,
    /// (cover position, node, weight): a cover's value goes to the node times the weight.
    spread: Vec<(u32, u32, f64)>,
    /// Per node pair (p, q), row-major: offset of row 3·block[p] in column 3·block[q] when
    /// block[p] ≥ block[q] (the pattern's lower triangle), else `UPPER`.
    offsets: Vec<u32>,
}

const UPPER: u32 = u32::MAX;

impl Coupling {
    /// The scatter of `covers` into `pattern`, which must couple all their free nodes.
    pub fn new(pattern: &SparsityPattern, dofs: &DofMap, covers: &[usize]) -> Self {
        Self::try_new(pattern, dofs, covers).expect("the pattern holds the coupling")
    }

    /// The scatter of `covers` into `pattern`, or `None` when the pattern lacks a coupling of
    /// two of their free nodes.
    pub fn try_new(pattern: &SparsityPattern, dofs: &DofMap, covers: &[usize]) -> Option<Self> {
        let mut nodes: Vec<usize> = Vec::new();
        let mut spread = Vec::new();
        let node_of = |c: usize, nodes: &mut Vec<usize>| match nodes.iter().position(|&x| x == c) {
            Some(k) => k as u32,
            None => {
                nodes.push(c);
                (nodes.len() - 1) as u32
            }
        };
        for (a, &c) in covers.iter().enumerate() {
            match &dofs.kind[c] {
                CoverDofs::Free(_) => spread.push((a as u32, node_of(c, &mut nodes), 1.0)),
                CoverDofs::Tied(masters) => {
                    spread.extend(masters.iter().map(|&(m, w)| (a as u32, node_of(m, &mut nodes), w)))
                }
                CoverDofs::Fixed => {}
            }
        }
        // Nodes in equation order, so the lower triangle's node blocks are (p, q ≤ p).
        let block_of = |c: usize| (dofs.eq(c, 0).expect("nodes are free") / 3) as u32;
        let mut sorted: Vec<u32> = (0..nodes.len() as u32).collect();
        sorted.sort_by_key(|&k| block_of(nodes[k as usize]));
        let mut rank = vec![0u32; nodes.len()];
        sorted.iter().enumerate().for_each(|(r, &k)| rank[k as usize] = r as u32);
        spread.iter_mut().for_each(|s| s.1 = rank[s.1 as usize]);
        let blocks: Vec<u32> = sorted.iter().map(|&k| block_of(nodes[k as usize])).collect();
        let offsets = blocks
            .iter()
            .flat_map(|&p| blocks.iter().map(move |&q| (p, q)))
            .map(|(p, q)| if p >= q { pattern.block_offset(p as usize, q as usize) } else { Some(UPPER) })
            .collect::<Option<Vec<u32>>>()?;
        Some(Self { blocks, spread, offsets })
    }

    /// The same scatter in `new`, a pattern holding every entry of `old` (this scatter's
    /// pattern) at `moved[k]` for `old`'s entry k ([`SparsityPattern::embedding`]).
    pub fn move_to(&mut self, old: &SparsityPattern, new: &SparsityPattern, moved: &[u32]) {
        let m = self.nodes();
        for (k, off) in self.offsets.iter_mut().enumerate().filter(|(_, off)| **off != UPPER) {
            let col = 3 * self.blocks[k % m] as usize;
            let at = moved[(old.col_ptr[col] + *off) as usize];
            *off = at - new.col_ptr[col];
        }
    }

    /// Number of nodes m.
    pub fn nodes(&self) -> usize {
        self.blocks.len()
    }

    /// Per-node weights Tᵀ w from per-cover weights `w` (written to `out`, length m).
    pub fn node_weights(&self, w: &[f64], out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.nodes(), 0.0);
        for &(a, p, t) in &self.spread {
            out[p as usize] += t * w[a as usize];
        }
    }

    /// values += `local`, a symmetric matrix over the nodes stored by 3 × 3 node blocks: block
    /// (p, q) row-major at `local[9 (p m + q)..]`. Only the lower triangle is read: the blocks
    /// q ≤ p (nodes are in equation order), of the diagonal ones their lower parts.
    pub fn add(&self, pattern: &SparsityPattern, values: &mut [f64], local: &[f64]) {
        let m = self.nodes();
        for p in 0..m {
            for q in 0..=p {
                let off = self.offsets[p * m + q];
                let (bq, diagonal) = (self.blocks[q] as usize, p == q);
                let block = &local[9 * (p * m + q)..][..9];
                for j in 0..3 {
                    let start = pattern.col_ptr[3 * bq + j] as usize + off as usize;
                    for i in (0..3).filter(|&i| !diagonal || i >= j) {
                        values[start + i - j] += block[3 * i + j];
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense lower triangle of a pattern's values.
    fn dense(p: &SparsityPattern, values: &[f64]) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; p.n]; p.n];
        for col in 0..p.n {
            let (lo, hi) = (p.col_ptr[col] as usize, p.col_ptr[col + 1] as usize);
            for (&row, &v) in p.row_idx[lo..hi].iter().zip(&values[lo..hi]) {
                d[row as usize][col] = v;
            }
        }
        d
    }

    #[test]
    fn a_moved_scatter_is_the_scatter_made_in_the_grown_pattern() {
        // Covers 0..8 free but 6 tied to ½ (1 + 7); a coupling of {0, 3, 6}, then cliques that
        // insert rows before and between its entries.
        let mut tied = vec![None; 9];
        tied[6] = Some(vec![(1, 0.5), (7, 0.5)]);
        let dofs = DofMap::new(&[false; 9], &tied);
        let clique = [0usize, 3, 6];
        let p = SparsityPattern::from_cliques(&dofs, [&[0usize, 1, 3, 7][..], &[4, 5]].into_iter());
        let mut c = Coupling::new(&p, &dofs, &clique);
        let grown = p.with_cliques(&dofs, [&[0usize, 2][..], &[1, 2, 5], &[3, 4, 8]].into_iter());
        assert!(grown.nnz() > p.nnz());
        c.move_to(&p, &grown, &p.embedding(&grown));
        assert_eq!(c, Coupling::new(&grown, &dofs, &clique));
    }

    #[test]
    fn outer_product_lands_on_the_free_and_master_equations() {
        // Covers 0, 1, 3 free; 2 fixed; 4 tied to ½ (0 + 3).
        let tied = vec![None, None, None, None, Some(vec![(0, 0.5), (3, 0.5)])];
        let dofs = DofMap::new(&[false, false, true, false, false], &tied);
        let clique = [3usize, 2, 4, 1];
        let masters = [3usize, 0, 1];
        let p = SparsityPattern::from_cliques(&dofs, [&masters[..]].into_iter());
        let c = Coupling::new(&p, &dofs, &clique);
        assert_eq!(c.nodes(), 3);
        let w = [0.4, 0.7, -0.2, 1.0];
        let mut wm = Vec::new();
        c.node_weights(&w, &mut wm);
        let b = [[2.0, 0.5, 0.1], [0.5, 3.0, 0.2], [0.1, 0.2, 4.0]];
        let m = c.nodes();
        let mut local = vec![0.0; 9 * m * m];
        for (a, wa) in wm.iter().enumerate() {
            for (bn, wb) in wm.iter().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        local[9 * (a * m + bn) + 3 * i + j] = wa * wb * b[i][j];
                    }
                }
            }
        }
        let mut values = vec![0.0; p.nnz()];
        c.add(&p, &mut values, &local);
        // Expected: per free cover, its total weight (cover 4's weight split onto 0 and 3).
        let mut weq = vec![0.0; dofs.n_eq / 3];
        for (&cv, &wc) in clique.iter().zip(&w) {
            for (mc, t) in dofs.masters(cv) {
                weq[dofs.eq(mc, 0).expect("free") / 3] += t * wc;
            }
        }
        let d = dense(&p, &values);
        for r in 0..p.n {
            for col in 0..=r {
                let expected = weq[r / 3] * weq[col / 3] * b[r % 3][col % 3];
                assert!((d[r][col] - expected).abs() < 1e-14, "({r}, {col}): {} vs {expected}", d[r][col]);
            }
        }
    }
}
