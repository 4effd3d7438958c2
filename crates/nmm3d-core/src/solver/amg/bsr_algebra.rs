//! The products the hierarchy is built from, block by block: A T, A P, Pᵀ (A P) and Pᵀ.
//! One column index and one accumulator lookup serve a whole dense block product (3 × 3 by
//! 3 × 6 on the finest level) where entry-by-entry rows paid them per scalar. Block rows are
//! computed independently (in parallel), so results do not depend on the thread count.

use rayon::prelude::*;

use super::bsr::{Bsr, CHUNK};

/// out += a b for an r × k block `a` and a k × c block `b` (row by row). Inlined into callers
/// that fix the shape, whose loops the compiler then unrolls.
#[inline(always)]
fn multiply_into(a: &[f64], b: &[f64], out: &mut [f64], (r, k, c): (usize, usize, usize)) {
    for x in 0..r {
        for z in 0..k {
            let v = a[x * k + z];
            for y in 0..c {
                out[x * c + y] += v * b[z * c + y];
            }
        }
    }
}

/// [`multiply_into`] with the shapes of the three-displacement nodes and six rigid-body modes
/// made constant.
fn multiply_block(a: &[f64], b: &[f64], out: &mut [f64], shape: (usize, usize, usize)) {
    match shape {
        (3, 3, 6) => multiply_into(a, b, out, (3, 3, 6)),
        (6, 3, 6) => multiply_into(a, b, out, (6, 3, 6)),
        (6, 6, 6) => multiply_into(a, b, out, (6, 6, 6)),
        _ => multiply_into(a, b, out, shape),
    }
}

impl Bsr<f64> {
    /// Aᵀ (blocks c × r).
    pub fn transpose(&self) -> Self {
        let (br, bc, size) = (self.br, self.bc, self.br * self.bc);
        let block_cols = self.cols / bc;
        let mut count = vec![0usize; block_cols + 1];
        for &j in &self.idx {
            count[j as usize + 1] += 1;
        }
        for c in 0..block_cols {
            count[c + 1] += count[c];
        }
        let ptr = count.clone();
        let (mut idx, mut val) = (vec![0u32; self.idx.len()], vec![0.0; self.val.len()]);
        for b in 0..self.rows / br {
            let (bi, bv) = self.block_row(b);
            for (&j, block) in bi.iter().zip(bv.chunks_exact(size)) {
                let at = count[j as usize];
                idx[at] = b as u32;
                let out = &mut val[at * size..(at + 1) * size];
                for x in 0..br {
                    for y in 0..bc {
                        out[y * br + x] = block[x * bc + y];
                    }
                }
                count[j as usize] += 1;
            }
        }
        Self { rows: self.cols, cols: self.rows, br: bc, bc: br, ptr, idx, val }
    }

    /// A B (Gustavson's block-row by block-row product with a dense accumulator of blocks per
    /// rayon job).
    pub fn times_matrix(&self, b: &Self) -> Self {
        assert_eq!((self.cols, self.bc), (b.rows, b.br), "inner dimensions and blocks agree");
        let shape = (self.br, self.bc, b.bc);
        let (out_size, a_size, b_size) = (self.br * b.bc, self.br * self.bc, b.br * b.bc);
        let block_cols = b.cols / b.bc;
        let block_rows = self.rows / self.br;
        let chunks: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = (0..block_rows.div_ceil(CHUNK))
            .into_par_iter()
            .map_init(
                || (vec![0.0; block_cols * out_size], vec![false; block_cols], Vec::new()),
                |(acc, seen, touched): &mut (Vec<f64>, Vec<bool>, Vec<u32>), c| {
                    let (mut lens, mut idx, mut val) = (Vec::new(), Vec::new(), Vec::new());
                    for row in c * CHUNK..((c + 1) * CHUNK).min(block_rows) {
                        let (ai, av) = self.block_row(row);
                        for (&k, ablock) in ai.iter().zip(av.chunks_exact(a_size)) {
                            let (bi, bv) = b.block_row(k as usize);
                            for (&j, bblock) in bi.iter().zip(bv.chunks_exact(b_size)) {
                                let j = j as usize;
                                if !seen[j] {
                                    seen[j] = true;
                                    touched.push(j as u32);
                                }
                                multiply_block(ablock, bblock, &mut acc[j * out_size..(j + 1) * out_size], shape);
                            }
                        }
                        touched.sort_unstable();
                        for &j in touched.iter() {
                            let j = j as usize;
                            idx.push(j as u32);
                            let block = &mut acc[j * out_size..(j + 1) * out_size];
                            val.extend_from_slice(block);
                            block.fill(0.0);
                            seen[j] = false;
                        }
                        lens.push(touched.len());
                        touched.clear();
                    }
                    (lens, idx, val)
                },
            )
            .collect();
        Self::from_chunks(self.rows, b.cols, (self.br, b.bc), chunks)
    }

    /// Row r multiplied by `factor(r)`.
    pub fn scale_rows(&mut self, factor: impl Fn(usize) -> f64) {
        let (br, bc) = (self.br, self.bc);
        for b in 0..self.rows / br {
            let (lo, hi) = (self.ptr[b], self.ptr[b + 1]);
            for block in self.val[lo * br * bc..hi * br * bc].chunks_exact_mut(br * bc) {
                block.iter_mut().enumerate().for_each(|(e, v)| *v *= factor(b * br + e / bc));
            }
        }
    }

    /// self += t, t's blocks lying within self's.
    pub fn add_within(&mut self, t: &Self) {
        let size = self.br * self.bc;
        for b in 0..t.rows / t.br {
            let (lo, hi) = (self.ptr[b], self.ptr[b + 1]);
            let (ti, tv) = t.block_row(b);
            for (&j, block) in ti.iter().zip(tv.chunks_exact(size)) {
                let k = lo + self.idx[lo..hi].binary_search(&j).expect("t's blocks within self's");
                self.val[k * size..(k + 1) * size].iter_mut().zip(block).for_each(|(v, t)| *v += t);
            }
        }
    }

    /// Rows with nothing stored but zeros get a unit diagonal: the coarse equations of zero
    /// prolongator columns (dependent modes), which the correction never uses.
    pub fn unit_diagonal_where_empty(&mut self) {
        let (b, size) = (self.br, self.br * self.br);
        for row in 0..self.rows / b {
            let (lo, hi) = (self.ptr[row], self.ptr[row + 1]);
            let Ok(d) = self.idx[lo..hi].binary_search(&(row as u32)) else { continue };
            for i in 0..b {
                let empty =
                    (lo..hi).all(|k| self.val[k * size + i * b..k * size + (i + 1) * b].iter().all(|&v| v == 0.0));
                if empty {
                    self.val[(lo + d) * size + i * b + i] = 1.0;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::bsr::tests::{dense, sample};
    use super::*;

    #[test]
    fn block_products_and_transposes_match_dense_arithmetic() {
        let a = sample(); // 12 × 18
        let at = Bsr::<f64>::from_csr(&a, 3, 6).transpose();
        assert_eq!((at.br, at.bc), (6, 3));
        let (d, dt) = (dense(&a), dense(&at.to_csr()));
        (0..12).for_each(|i| (0..18).for_each(|j| assert_eq!(dt[j][i], d[i][j])));
        for (r, k) in [(3, 6), (6, 3), (3, 3), (1, 1)] {
            let (x, y) = (Bsr::<f64>::from_csr(&a, r, k), Bsr::<f64>::from_csr(&at.to_csr(), k, r));
            let p = dense(&x.times_matrix(&y).to_csr());
            for i in 0..12 {
                for j in 0..12 {
                    let want: f64 = (0..18).map(|m| d[i][m] * d[j][m]).sum();
                    assert!((p[i][j] - want).abs() < 1e-12, "{r} × {k}: ({i}, {j})");
                }
            }
        }
    }

    #[test]
    fn rows_are_scaled_sums_stay_in_the_pattern_and_empty_rows_get_a_unit_diagonal() {
        let a = sample();
        let mut x = Bsr::<f64>::from_csr(&a, 3, 6);
        let twice = x.clone();
        x.scale_rows(|r| r as f64);
        x.add_within(&twice);
        let (d, got) = (dense(&a), dense(&x.to_csr()));
        (0..12).for_each(|i| (0..18).for_each(|j| assert_eq!(got[i][j], d[i][j] * (i as f64 + 1.0))));
        let mut s = Bsr::<f64>::from_csr(&a, 3, 6).times_matrix(&Bsr::<f64>::from_csr(&a, 3, 6).transpose());
        s.scale_rows(|r| if r == 4 { 0.0 } else { 1.0 });
        s.unit_diagonal_where_empty();
        let got = dense(&s.to_csr());
        assert_eq!(got[4][4], 1.0);
        assert!((0..12).filter(|&j| j != 4).all(|j| got[4][j] == 0.0));
        assert_ne!(got[3][3], 1.0);
    }
}
