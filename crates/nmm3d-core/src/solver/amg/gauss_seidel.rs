//! Gauss–Seidel smoothing, hybrid across a fixed number of row ranges: within a range rows are
//! relaxed in order with the newest values, across ranges with the values of the sweep's start
//! (block Jacobi between them; hypre's "hybrid Gauss–Seidel", Baker et al., *SIAM J. Sci.
//! Comput.* 33, 2011). The ranges run in parallel; their number is fixed, not the thread
//! count's, so results do not depend on the machine.

use rayon::prelude::*;

use super::bsr::Bsr;

/// Row ranges relaxed independently.
pub const PARTS: usize = 8;

/// One sweep on A x = b, forward or `backward` within each range; `old` is scratch of x's size.
/// The ranges hold whole block rows of A (square blocks).
pub fn sweep(a: &Bsr<f32>, inv_diag: &[f64], b: &[f64], x: &mut [f64], old: &mut [f64], backward: bool) {
    match a.bc {
        3 => sweep_with(a, inv_diag, b, x, old, backward, |r, lo, near, far| a.row_times_by::<3>(r, lo, near, far)),
        6 => sweep_with(a, inv_diag, b, x, old, backward, |r, lo, near, far| a.row_times_by::<6>(r, lo, near, far)),
        _ => sweep_with(a, inv_diag, b, x, old, backward, |r, lo, near, far| a.row_times(r, lo, near, far)),
    }
}

/// [`sweep`] with the row product `row_times` (the block width known to the compiler).
fn sweep_with(
    a: &Bsr<f32>,
    inv_diag: &[f64],
    b: &[f64],
    x: &mut [f64],
    old: &mut [f64],
    backward: bool,
    row_times: impl Fn(usize, usize, &[f64], &[f64]) -> f64 + Sync,
) {
    let part = (a.rows / a.br).div_ceil(PARTS).max(1) * a.br;
    old.copy_from_slice(x);
    let old = &*old;
    x.par_chunks_mut(part).enumerate().for_each(|(k, xs)| {
        let (lo, n) = (k * part, xs.len());
        let mut relax = |r: usize| {
            let sum = row_times(r, lo, xs, old);
            xs[r - lo] += (b[r] - sum) * inv_diag[r];
        };
        if backward {
            (lo..lo + n).rev().for_each(&mut relax);
        } else {
            (lo..lo + n).for_each(&mut relax);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::amg::csr::Csr;

    #[test]
    fn sweeps_converge_on_a_diagonally_dominant_matrix_and_leave_its_solution_alone() {
        // Tridiagonal 4, −1 of order 50 (spans all the ranges).
        let n: usize = 50;
        let (mut ptr, mut idx, mut val) = (vec![0], Vec::new(), Vec::new());
        for r in 0..n {
            for (j, v) in [(r.wrapping_sub(1), -1.0), (r, 4.0), (r + 1, -1.0f64)] {
                if j < n {
                    idx.push(j as u32);
                    val.push(v);
                }
            }
            ptr.push(idx.len());
        }
        let a = Bsr::<f32>::from_csr(&Csr { rows: n, cols: n, ptr, idx, val }, 1, 1);
        let want: Vec<f64> = (0..n).map(|i| (i as f64 * 0.4).sin()).collect();
        let mut b = vec![0.0; n];
        a.times(&want, &mut b);
        let inv: Vec<f64> = vec![0.25; n];
        let (mut x, mut old) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..40 {
            sweep(&a, &inv, &b, &mut x, &mut old, k % 2 == 1);
        }
        assert!(x.iter().zip(&want).all(|(x, w)| (x - w).abs() < 1e-12));
        let mut y = want.clone();
        sweep(&a, &inv, &b, &mut y, &mut old, false);
        assert!(y.iter().zip(&want).all(|(y, w)| (y - w).abs() < 1e-15));
    }
}
