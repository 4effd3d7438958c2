//! How much work a numeric Cholesky factorisation on a symbolic analysis is, and whether it is
//! worth running on several threads.

use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::Par;

/// Flops of a left-looking column count Σ_{k=1..w} (k + m)² for a supernode of `w` columns
/// above `m` rows (column k from its end holds k + m entries; George and Liu 1981, §2.2).
pub fn supernode_flops(w: f64, m: f64) -> f64 {
    w * m * m + m * w * (w + 1.0) + w * (w + 1.0) * (2.0 * w + 1.0) / 6.0
}

/// Σ c_j² over the factor's columns (c_j: the entries of column j): a numeric factorisation's
/// floating-point work, up to a constant.
pub fn column_flops(s: &SymbolicCholesky<u32>) -> f64 {
    match s.raw() {
        SymbolicCholeskyRaw::Supernodal(sn) => (0..sn.n_supernodes())
            .map(|node| {
                let w = (sn.supernode_end()[node] - sn.supernode_begin()[node]) as f64;
                supernode_flops(w, sn.supernode(node).pattern().len() as f64)
            })
            .sum(),
        SymbolicCholeskyRaw::Simplicial(sm) => sm.col_ptr().windows(2).map(|c| ((c[1] - c[0]) as f64).powi(2)).sum(),
    }
}

/// A factorisation in double precision of at least this much work ([`column_flops`]) runs on
/// the run's threads (faer's parallel supernodal kernels), a smaller one on one; in single
/// precision, whose kernels take twice the lanes, twice as much. Measured back to back on two
/// cores (2026-11-30, per factorisation, sequential → parallel): double — Goodman's tunnel
/// (1.0·10⁹) 37.6–40.7 → 38.8–53.2 ms, the packed pile of 300 cubes (1.9·10⁹) 57.6–74.3 → 53.4–
/// 57.0 ms, of 600 (7.5·10⁹) 196–200 → 150–161 ms; single — the thesis tunnel (6.2·10⁸) 20.3–
/// 26.2 → 22.6–26.7 ms, the pile of 250 cubes (1.2·10⁹) 25.5–25.7 → 28.4–28.8 ms, of 300 37.9–
/// 38.0 → 38.6–39.4 ms, of 600 118–126 → 103–111 ms, of 1 000 (1.7·10¹⁰) 269–279 → 207–219 ms.
/// (A threshold of 10⁶ factor entries, used before, made Goodman's and the thesis tunnel's
/// factors in parallel: the one no faster, the other slower.)
pub const PARALLEL_FACTOR_FLOPS: f64 = 1.5e9;

/// How a numeric factorisation of `work` ([`column_flops`], counted once per analysis) in
/// precision `T` runs: [`PARALLEL_FACTOR_FLOPS`].
pub fn factor_par<T>(work: f64) -> Par {
    if work * std::mem::size_of::<T>() as f64 / 8.0 >= PARALLEL_FACTOR_FLOPS && rayon::current_num_threads() > 1 {
        Par::rayon(0)
    } else {
        Par::Seq
    }
}
