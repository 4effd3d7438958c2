//! Block sparse rows: the multigrid hierarchy's operators, in double precision while it is built
//! (`bsr_algebra.rs`) and in single precision as the V-cycle reads them.
//!
//! A V-cycle reads every operator of the hierarchy three or four times per PCG iteration and
//! little else, so its time is the memory it streams. Elasticity couples nodes by dense 3 × 3
//! blocks (and the aggregates of rigid-body modes by 6 × 6 ones): stored by blocks, one column
//! index serves a whole block instead of one entry, and values in `f32` halve the rest — about
//! 4.4 instead of 12 bytes per entry. A preconditioner needs no more precision than that: the
//! V-cycle stays a fixed symmetric linear operator (all arithmetic in `f64`, only the stored
//! values rounded), and PCG's own products stay in double precision on the finest level
//! (mixed-precision multigrid preconditioning: Tsai, Luszczek & Dongarra, *ScalA* 2021).

use rayon::prelude::*;

use super::csr::Csr;

/// Block rows in one parallel task.
pub(super) const CHUNK: usize = 1024;
/// Largest block side stored by blocks; a larger one is stored entry by entry.
const MAX_SIDE: usize = 8;

/// A stored value: `f64` while the hierarchy is built, `f32` in the V-cycle.
pub trait Value: Copy + Default + PartialEq + Send + Sync + 'static {
    /// `v` rounded to this type.
    fn of(v: f64) -> Self;
    /// This value in double precision.
    fn get(self) -> f64;
}

impl Value for f64 {
    fn of(v: f64) -> Self {
        v
    }
    fn get(self) -> f64 {
        self
    }
}

impl Value for f32 {
    fn of(v: f64) -> Self {
        v as f32
    }
    fn get(self) -> f64 {
        f64::from(self)
    }
}

/// A sparse matrix of `br` × `bc` blocks by block rows, block columns sorted within each.
#[derive(Debug, Clone, PartialEq)]
pub struct Bsr<T: Value> {
    /// Rows of scalars.
    pub rows: usize,
    /// Columns of scalars.
    pub cols: usize,
    /// Block height.
    pub br: usize,
    /// Block width.
    pub bc: usize,
    /// Block-row pointers (rows / br + 1).
    pub(super) ptr: Vec<usize>,
    /// Block column of each block.
    pub(super) idx: Vec<u32>,
    /// Each block's values row by row.
    pub(super) val: Vec<T>,
}

impl<T: Value> Bsr<T> {
    /// `a` by `br` × `bc` blocks (entry by entry when they do not tile it); entries absent from
    /// a stored block are zeros.
    pub fn from_csr(a: &Csr, br: usize, bc: usize) -> Self {
        let tiles = br <= MAX_SIDE && bc <= MAX_SIDE && a.rows.is_multiple_of(br) && a.cols.is_multiple_of(bc);
        let (br, bc) = if tiles { (br, bc) } else { (1, 1) };
        let block_rows = a.rows / br;
        let chunks: Vec<(Vec<usize>, Vec<u32>, Vec<T>)> = (0..block_rows.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let (mut lens, mut idx, mut val) = (Vec::new(), Vec::new(), Vec::new());
                for b in c * CHUNK..((c + 1) * CHUNK).min(block_rows) {
                    let start = idx.len();
                    block_columns(a, b * br..(b + 1) * br, bc as u32, &mut idx);
                    let (cols, n) = (&idx[start..], idx.len() - start);
                    let first = val.len();
                    val.resize(first + n * br * bc, T::default());
                    for (i, r) in (b * br..(b + 1) * br).enumerate() {
                        // Both sorted: walk the row's entries along the blocks.
                        let (ri, rv) = a.row(r);
                        let mut k = 0;
                        for (&j, &v) in ri.iter().zip(rv) {
                            while cols[k] != j / bc as u32 {
                                k += 1;
                            }
                            val[first + (k * br + i) * bc + j as usize % bc] = T::of(v);
                        }
                    }
                    lens.push(n);
                }
                (lens, idx, val)
            })
            .collect();
        Self::from_chunks(a.rows, a.cols, (br, bc), chunks)
    }

    /// The matrix whose block rows, in order, are the chunks' (block counts, columns, values).
    pub(super) fn from_chunks(
        rows: usize,
        cols: usize,
        (br, bc): (usize, usize),
        chunks: Vec<(Vec<usize>, Vec<u32>, Vec<T>)>,
    ) -> Self {
        let mut ptr = Vec::with_capacity(rows / br + 1);
        ptr.push(0);
        let total = chunks.iter().map(|c| c.1.len()).sum();
        let (mut idx, mut val) = (Vec::with_capacity(total), Vec::with_capacity(total * br * bc));
        for (lens, i, v) in chunks {
            for l in lens {
                ptr.push(ptr.last().unwrap() + l);
            }
            idx.extend(i);
            val.extend(v);
        }
        Self { rows, cols, br, bc, ptr, idx, val }
    }

    /// The same matrix with its values rounded to `U`.
    pub fn to<U: Value>(&self) -> Bsr<U> {
        let val = self.val.par_iter().map(|v| U::of(v.get())).collect();
        Bsr {
            rows: self.rows,
            cols: self.cols,
            br: self.br,
            bc: self.bc,
            ptr: self.ptr.clone(),
            idx: self.idx.clone(),
            val,
        }
    }

    /// The same matrix entry by entry (a stored block's zeros included).
    pub fn to_csr(&self) -> Csr {
        let (br, bc) = (self.br, self.bc);
        let (mut ptr, mut idx, mut val) =
            (vec![0], Vec::with_capacity(self.val.len()), Vec::with_capacity(self.val.len()));
        for b in 0..self.rows / br {
            let (bi, bv) = self.block_row(b);
            for i in 0..br {
                for (&j, block) in bi.iter().zip(bv.chunks_exact(br * bc)) {
                    idx.extend((0..bc).map(|c| j * bc as u32 + c as u32));
                    val.extend(block[i * bc..(i + 1) * bc].iter().map(|v| v.get()));
                }
                ptr.push(idx.len());
            }
        }
        Csr { rows: self.rows, cols: self.cols, ptr, idx, val }
    }

    /// Stored values (blocks × br × bc).
    pub fn stored(&self) -> usize {
        self.val.len()
    }

    /// Block columns and values of block row `b`.
    pub(super) fn block_row(&self, b: usize) -> (&[u32], &[T]) {
        let (lo, hi) = (self.ptr[b], self.ptr[b + 1]);
        (&self.idx[lo..hi], &self.val[lo * self.br * self.bc..hi * self.br * self.bc])
    }

    /// The diagonal of a matrix of square blocks (0 where absent).
    pub fn diagonal(&self) -> Vec<f64> {
        let b = self.br;
        (0..self.rows)
            .map(|r| {
                let (idx, val) = self.block_row(r / b);
                let i = r % b;
                idx.binary_search(&((r / b) as u32)).map_or(0.0, |k| val[(k * b + i) * b + i].get())
            })
            .collect()
    }

    /// y = A x.
    pub fn times(&self, x: &[f64], y: &mut [f64]) {
        self.product(x, y, false);
    }

    /// y += A x.
    pub fn add_times(&self, x: &[f64], y: &mut [f64]) {
        self.product(x, y, true);
    }

    fn product(&self, x: &[f64], y: &mut [f64], add: bool) {
        match (self.br, self.bc) {
            (3, 3) => self.product_by::<3, 3>(x, y, add),
            (6, 6) => self.product_by::<6, 6>(x, y, add),
            (3, 6) => self.product_by::<3, 6>(x, y, add),
            (6, 3) => self.product_by::<6, 3>(x, y, add),
            _ => self.product_any(x, y, add),
        }
    }

    /// The product with the block shape known at compile time (unrolled inner loops, no bounds
    /// checks: one runtime-shape kernel for all shapes made the 10⁵-ME static run's solves
    /// 15–20 % slower, measured back to back).
    fn product_by<const R: usize, const C: usize>(&self, x: &[f64], y: &mut [f64], add: bool) {
        y.par_chunks_mut(CHUNK * R).enumerate().for_each(|(c, ys)| {
            for (k, yb) in ys.chunks_exact_mut(R).enumerate() {
                let (idx, val) = self.block_row(c * CHUNK + k);
                let mut acc = [0.0f64; R];
                for (&j, block) in idx.iter().zip(val.chunks_exact(R * C)) {
                    let xs = &x[j as usize * C..j as usize * C + C];
                    for (i, a) in acc.iter_mut().enumerate() {
                        *a += block[i * C..i * C + C].iter().zip(xs).map(|(&v, x)| v.get() * x).sum::<f64>();
                    }
                }
                yb.iter_mut().zip(acc).for_each(|(y, a)| *y = if add { *y + a } else { a });
            }
        });
    }

    fn product_any(&self, x: &[f64], y: &mut [f64], add: bool) {
        let (br, bc) = (self.br, self.bc);
        y.par_chunks_mut(CHUNK * br).enumerate().for_each(|(c, ys)| {
            for (k, yb) in ys.chunks_exact_mut(br).enumerate() {
                let (idx, val) = self.block_row(c * CHUNK + k);
                let mut acc = [0.0f64; MAX_SIDE];
                for (&j, block) in idx.iter().zip(val.chunks_exact(br * bc)) {
                    let xs = &x[j as usize * bc..(j as usize + 1) * bc];
                    for (i, a) in acc[..br].iter_mut().enumerate() {
                        *a += block[i * bc..(i + 1) * bc].iter().zip(xs).map(|(&v, x)| v.get() * x).sum::<f64>();
                    }
                }
                yb.iter_mut().zip(acc).for_each(|(y, a)| *y = if add { *y + a } else { a });
            }
        });
    }

    /// Σ_j A_rj x_j over scalar row `r`, taking x_j from `near` (x[lo..lo + near.len()]) where
    /// the block of j lies there and from `far` elsewhere: Gauss–Seidel's row product, whose
    /// ranges begin and end at block boundaries (square blocks).
    pub fn row_times(&self, r: usize, lo: usize, near: &[f64], far: &[f64]) -> f64 {
        match self.bc {
            1 => self.row_times_by::<1>(r, lo, near, far),
            3 => self.row_times_by::<3>(r, lo, near, far),
            6 => self.row_times_by::<6>(r, lo, near, far),
            _ => self.row_times_any(r, lo, near, far),
        }
    }

    /// [`Bsr::row_times`] for blocks `C` wide.
    #[inline(always)]
    pub fn row_times_by<const C: usize>(&self, r: usize, lo: usize, near: &[f64], far: &[f64]) -> f64 {
        let (idx, val) = self.block_row(r / self.br);
        let start = (r % self.br) * C;
        let hi = lo + near.len();
        let mut sum = 0.0;
        for (&j, block) in idx.iter().zip(val.chunks_exact(self.br * C)) {
            let j0 = j as usize * C;
            let row: &[T; C] = block[start..start + C].try_into().expect("C values");
            let xs: &[f64; C] = if (lo..hi).contains(&j0) { &near[j0 - lo..j0 - lo + C] } else { &far[j0..j0 + C] }
                .try_into()
                .expect("C values");
            for c in 0..C {
                sum += row[c].get() * xs[c];
            }
        }
        sum
    }

    fn row_times_any(&self, r: usize, lo: usize, near: &[f64], far: &[f64]) -> f64 {
        let (br, bc) = (self.br, self.bc);
        let (idx, val) = self.block_row(r / br);
        let i = r % br;
        let hi = lo + near.len();
        let mut sum = 0.0;
        for (&j, block) in idx.iter().zip(val.chunks_exact(br * bc)) {
            let j0 = j as usize * bc;
            let row = &block[i * bc..(i + 1) * bc];
            let xs = if (lo..hi).contains(&j0) { &near[j0 - lo..j0 - lo + bc] } else { &far[j0..j0 + bc] };
            sum += row.iter().zip(xs).map(|(&v, x)| v.get() * x).sum::<f64>();
        }
        sum
    }
}

/// Append the sorted block columns (width `bc`) of `a`'s rows `rows` to `out`. Rows of one
/// block row usually share them (elasticity's node couplings): the first row's are kept when
/// every other row's lie among them.
fn block_columns(a: &Csr, rows: std::ops::Range<usize>, bc: u32, out: &mut Vec<u32>) {
    let start = out.len();
    let of_row = |r: usize| a.row(r).0.iter().map(move |&j| j / bc);
    out.extend(of_row(rows.start));
    dedup_from(out, start);
    let first = &out[start..];
    let within = |r: usize| {
        let mut k = 0;
        of_row(r).all(|c| {
            while k < first.len() && first[k] < c {
                k += 1;
            }
            k < first.len() && first[k] == c
        })
    };
    let shared = rows.clone().skip(1).all(within);
    if !shared {
        out.extend(rows.skip(1).flat_map(of_row));
        out[start..].sort_unstable();
        dedup_from(out, start);
    }
}

/// Remove repeats from the sorted `v[start..]`.
fn dedup_from(v: &mut Vec<u32>, start: usize) {
    let mut n = start;
    for k in start..v.len() {
        if n == start || v[k] != v[n - 1] {
            v[n] = v[k];
            n += 1;
        }
    }
    v.truncate(n);
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::solver::amg) fn dense(a: &Csr) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; a.cols]; a.rows];
        for (r, row) in d.iter_mut().enumerate() {
            let (i, v) = a.row(r);
            i.iter().zip(v).for_each(|(&j, &x)| row[j as usize] += x);
        }
        d
    }

    /// A 12 × 18 matrix with a pattern that leaves some 3 × 6 blocks partly empty.
    pub(in crate::solver::amg) fn sample() -> Csr {
        let (rows, cols) = (12, 18);
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        for r in 0..rows {
            for j in 0..cols {
                if (r * 7 + j * 3) % 5 < 2 {
                    idx.push(j as u32);
                    val.push(0.25 * (r as f64 + 1.0) - 0.125 * j as f64);
                }
            }
            ptr.push(idx.len());
        }
        Csr { rows, cols, ptr, idx, val }
    }

    #[test]
    fn products_by_blocks_equal_the_entry_by_entry_ones() {
        let a = sample();
        let x: Vec<f64> = (0..a.cols).map(|i| (i as f64 * 0.7).cos()).collect();
        let mut want = vec![0.0; a.rows];
        a.times(&x, &mut want);
        // Values that f32 holds exactly: the products agree to round-off.
        for (br, bc) in [(3, 6), (6, 3), (3, 3), (6, 6), (2, 2), (4, 9), (5, 5)] {
            let b = Bsr::<f32>::from_csr(&a, br, bc);
            let mut y = vec![1.0; a.rows];
            b.times(&x, &mut y);
            assert!(y.iter().zip(&want).all(|(y, w)| (y - w).abs() < 1e-12), "{br} × {bc}");
            b.add_times(&x, &mut y);
            assert!(y.iter().zip(&want).all(|(y, w)| (y - 2.0 * w).abs() < 1e-12), "{br} × {bc}");
            for r in 0..a.rows {
                let s = b.row_times(r, 0, &x, &[]);
                assert!((s - want[r]).abs() < 1e-12);
            }
        }
        assert_eq!(Bsr::<f64>::from_csr(&a, 5, 5).br, 1, "5 × 5 does not tile 12 × 18");
        // Round trips: entry by entry (with the blocks' zeros) and back.
        let b = Bsr::<f64>::from_csr(&a, 3, 6);
        assert_eq!(Bsr::<f64>::from_csr(&b.to_csr(), 3, 6), b);
        let want = dense(&a);
        assert_eq!(dense(&b.to_csr()), want);
    }
}
