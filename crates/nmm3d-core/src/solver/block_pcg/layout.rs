//! Where the block solver's matrices come from: the block-diagonal part of a pattern, the
//! coarse pattern of the blocks' pairs, and AΦ (A applied to the blocks' rigid motions) with
//! A_c = Φᵀ(AΦ) made from it (see the parent module).

use nmm3d_geom::Vec3;

use crate::assembly::SparsityPattern;

/// Where each entry of a pattern goes: the block-diagonal part's entry, or the coarse pair.
pub(super) struct Layout {
    /// The pattern this layout was made for.
    pub(super) pattern: SparsityPattern,
    /// The block-diagonal part of the pattern (entries whose two nodes share a block).
    pub(super) local: SparsityPattern,
    /// For each entry of `pattern`, its index in `local` (`u32::MAX`: between blocks).
    pub(super) local_of: Vec<u32>,
    /// The coarse pattern (lower triangle, 6 × 6 per pair of blocks coupled).
    pub(super) coarse: SparsityPattern,
    /// For each coupled pair of blocks (by column block, then row block), the value index of
    /// its first stored entry in each of its six coarse columns.
    pair_start: Vec<[u32; 6]>,
    /// For each slot of AΦ (a row's block), the pair of the row's block and it in `pair_start`.
    slot_pair: Vec<u32>,
    /// AΦ on this pattern (its values those of the last matrix, [`Layout::fill_a_phi`]).
    pub(super) a_phi: APhi,
    /// For each entry (i, j) of `pattern`: where row i meets block(j), and row j block(i).
    a_phi_slot: Vec<[u32; 2]>,
}

/// AΦ (n × 6 per block), by rows: A applied to the blocks' rigid motions.
pub(super) struct APhi {
    /// Row i holds six values for each block in `blocks[rows[i]..rows[i + 1]]`.
    rows: Vec<u32>,
    /// The blocks each row of A couples to (sorted within a row).
    blocks: Vec<u32>,
    values: Vec<f64>,
}

impl APhi {
    /// out = AΦ c.
    pub(super) fn times(&self, c: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            let (lo, hi) = (self.rows[i] as usize, self.rows[i + 1] as usize);
            *o = (lo..hi)
                .map(|s| {
                    let (v, b) = (&self.values[6 * s..6 * s + 6], 6 * self.blocks[s] as usize);
                    v.iter().zip(&c[b..b + 6]).map(|(v, c)| v * c).sum::<f64>()
                })
                .sum();
        }
    }

    /// out = (AΦ)ᵀ y.
    pub(super) fn transpose_times(&self, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for (i, &yi) in y.iter().enumerate() {
            for s in self.rows[i] as usize..self.rows[i + 1] as usize {
                let b = 6 * self.blocks[s] as usize;
                out[b..b + 6].iter_mut().zip(&self.values[6 * s..6 * s + 6]).for_each(|(o, v)| *o += v * yi);
            }
        }
    }
}

impl Layout {
    /// The block-diagonal part and the coarse pattern of `p` for nodes in `node_block`.
    pub(super) fn new(p: &SparsityPattern, node_block: &[u32]) -> Self {
        let n = p.n;
        let blocks = node_block.iter().map(|&b| b as usize + 1).max().unwrap_or(0);
        let block = |eq: u32| node_block[eq as usize / 3];
        // The block-diagonal part.
        let (mut col_ptr, mut row_idx) = (vec![0u32], Vec::new());
        let mut local_of = vec![u32::MAX; p.nnz()];
        for j in 0..n {
            for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                if block(p.row_idx[k]) == block(j as u32) {
                    local_of[k] = row_idx.len() as u32;
                    row_idx.push(p.row_idx[k]);
                }
            }
            col_ptr.push(row_idx.len() as u32);
        }
        let local = SparsityPattern { n, col_ptr, row_idx };
        // Coupled pairs of blocks (row block ≥ column block), by column block.
        let mut rows: Vec<Vec<u32>> = vec![Vec::new(); blocks];
        for j in 0..n {
            for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
                let (a, b) = (block(i), block(j as u32));
                rows[a.min(b) as usize].push(a.max(b));
            }
        }
        rows.iter_mut().for_each(|r| {
            r.sort_unstable();
            r.dedup();
        });
        // Every block couples to itself (its diagonal), so each has its six columns.
        for (b, r) in rows.iter_mut().enumerate() {
            if r.first() != Some(&(b as u32)) {
                r.insert(0, b as u32);
            }
        }
        let (mut col_ptr, mut row_idx) = (vec![0u32], Vec::new());
        let mut pair_start = Vec::new();
        let mut first_pair = vec![0u32; blocks];
        for (b, r) in rows.iter().enumerate() {
            first_pair[b] = pair_start.len() as u32;
            let base = pair_start.len();
            pair_start.extend(r.iter().map(|_| [0u32; 6]));
            for q in 0..6 {
                for (k, &a) in r.iter().enumerate() {
                    pair_start[base + k][q] = row_idx.len() as u32;
                    let from = if a as usize == b { q } else { 0 };
                    row_idx.extend((from..6).map(|i| 6 * a + i as u32));
                }
                col_ptr.push(row_idx.len() as u32);
            }
        }
        let coarse = SparsityPattern { n: 6 * blocks, col_ptr, row_idx };
        let (rows_of, blocks_of, a_phi_slot) = a_phi_structure(p, node_block);
        let slot_pair = (0..p.n)
            .flat_map(|i| (rows_of[i]..rows_of[i + 1]).map(move |s| (i, s as usize)))
            .map(|(i, s)| {
                let (a, b) = (node_block[i / 3], blocks_of[s]);
                let (hi, lo) = (a.max(b), a.min(b));
                first_pair[lo as usize] + rows[lo as usize].binary_search(&hi).expect("coupled") as u32
            })
            .collect();
        Self {
            pattern: p.clone(),
            local,
            local_of,
            coarse,
            pair_start,
            slot_pair,
            a_phi: APhi { values: vec![0.0; 6 * blocks_of.len()], rows: rows_of, blocks: blocks_of },
            a_phi_slot,
        }
    }

    /// AΦ from A's lower triangle `values`: entry (i, j) adds a φ_j to row i at block(j), and
    /// (for i ≠ j) a φ_i to row j at block(i).
    pub(super) fn fill_a_phi(&mut self, values: &[f64], phi: &[[f64; 6]]) {
        let p = &self.pattern;
        let out = &mut self.a_phi.values;
        out.fill(0.0);
        for j in 0..p.n {
            for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                let (i, v) = (p.row_idx[k] as usize, values[k]);
                let [si, sj] = self.a_phi_slot[k];
                let at = 6 * si as usize;
                out[at..at + 6].iter_mut().zip(&phi[j]).for_each(|(o, f)| *o += v * f);
                if i != j {
                    let at = 6 * sj as usize;
                    out[at..at + 6].iter_mut().zip(&phi[i]).for_each(|(o, f)| *o += v * f);
                }
            }
        }
    }

    /// A_c = Φᵀ (AΦ) on the coarse pattern: row i of AΦ at block b adds φ_i ⊗ (AΦ)_ib into
    /// the pair (block(i), b), kept where that lies in A_c's lower triangle.
    pub(super) fn coarse_values(&self, node_block: &[u32], phi: &[[f64; 6]]) -> Vec<f64> {
        let a_phi = &self.a_phi;
        let mut out = vec![0.0; self.coarse.nnz()];
        for (i, f) in phi.iter().enumerate() {
            let bi = node_block[i / 3];
            for s in a_phi.rows[i] as usize..a_phi.rows[i + 1] as usize {
                let b = a_phi.blocks[s];
                if bi < b {
                    continue;
                }
                let pair = &self.pair_start[self.slot_pair[s] as usize];
                let column = &a_phi.values[6 * s..6 * s + 6];
                for (c, &w) in column.iter().enumerate() {
                    let (from, start) = (if bi == b { c } else { 0 }, pair[c] as usize);
                    for r in from..6 {
                        out[start + r - from] += f[r] * w;
                    }
                }
            }
        }
        // A rotation no node of its block moves (a block of one node, or of two along an
        // axis) is a zero column of Φ: its equation of A_c is made the identity's.
        for j in 0..self.coarse.n {
            let diagonal = self.coarse.col_ptr[j] as usize;
            if out[diagonal] == 0.0 {
                out[diagonal] = 1.0;
            }
        }
        out
    }
}

/// Row `c` (0–2) of a node's Φ: the translation's unit c and the rotations' (e_a × arm)_c.
pub(super) fn phi_row(arm: &Vec3, c: usize) -> [f64; 6] {
    let mut row = [0.0; 6];
    row[c] = 1.0;
    for a in 0..3 {
        row[3 + a] = Vec3::ith(a, 1.0).cross(arm)[c];
    }
    row
}

/// AΦ's structure for pattern `p`: per equation the blocks its row couples to, and where each
/// entry of `p` adds into them (see [`Layout`]).
fn a_phi_structure(p: &SparsityPattern, node_block: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<[u32; 2]>) {
    let block = |eq: usize| node_block[eq / 3];
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); p.n];
    for j in 0..p.n {
        for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
            lists[i as usize].push(block(j));
            lists[j].push(block(i as usize));
        }
    }
    let (mut rows, mut blocks) = (vec![0u32], Vec::new());
    for l in &mut lists {
        l.sort_unstable();
        l.dedup();
        blocks.extend_from_slice(l);
        rows.push(blocks.len() as u32);
    }
    let slot = |row: usize, b: u32| rows[row] + lists[row].binary_search(&b).expect("listed above") as u32;
    let mut slots = Vec::with_capacity(p.nnz());
    for j in 0..p.n {
        for &i in &p.row_idx[p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize] {
            slots.push([slot(i as usize, block(j)), slot(j, block(i as usize))]);
        }
    }
    (rows, blocks, slots)
}
