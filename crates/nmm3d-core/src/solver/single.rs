//! A Cholesky factor in single precision, and solves refined to double precision on it.
//!
//! Mixed-precision iterative refinement (Carson & Higham, SIAM J. Sci. Comput. 40, 2018;
//! Higham & Mary, Acta Numerica 31, 2022): the numeric factorisation, which dominates where the
//! factor fills (a jointed rock mass's contact springs couple whole joint faces), runs in `f32`
//! on the same symbolic analysis — its dense kernels move half the bytes and take twice the
//! lanes — and each solve is conjugate gradients on the `f64` matrix preconditioned by that
//! factor, to [`REFINED_TOLERANCE`]: the answer of a double-precision factor, not of a single
//! one. It pays where a factorisation costs many triangular solves (`faer_cholesky.rs` decides).
//! Its kernels run with subnormal numbers flushed to zero (`subnormals.rs`).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::sparse::linalg::cholesky::{LltRef, SymbolicCholesky};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par, Side};

use super::factor_work::factor_par;
use super::pcg::pcg;
use super::subnormals::flushed;
use crate::assembly::SparsityPattern;

/// Relative error, in the preconditioner's norm, at which a refined solve stops [-]: the
/// direct `f64` solve's accuracy on these systems (the Goodman tunnel's roof block after 0.3 s:
/// the same to 2·10⁻⁶ m, a path-level difference).
pub const REFINED_TOLERANCE: f64 = 1e-13;

/// Iterations after which a refined solve gives up and the factor is made in `f64` instead
/// (a matrix too ill-conditioned for single precision: its iterations grow with κ·2⁻²⁴).
pub const MAX_REFINEMENT: u32 = 40;

/// The single-precision factor and its buffers (kept across factorisations of one analysis).
#[derive(Default)]
pub struct SingleFactor {
    values: Vec<f32>,
    gathered: Vec<f32>,
    scratch: Option<MemBuffer>,
    solve_scratch: Option<MemBuffer>,
    vector: Vec<f32>,
    /// Refinement iterations made so far.
    pub iterations: u64,
    /// Factorisations made in single precision so far.
    pub factorizations: u64,
}

impl SingleFactor {
    /// A new analysis: the buffers are sized again.
    pub fn reset(&mut self) {
        (self.scratch, self.solve_scratch) = (None, None);
        self.values = Vec::new();
    }

    /// Factorise the permuted lower triangle `lower` with values `gathered` in `f32`; false if
    /// a pivot was not positive in single precision (nothing kept).
    /// `work`: the factorisation's ([`super::factor_work::column_flops`]).
    pub fn factorize(
        &mut self,
        s: &SymbolicCholesky<u32>,
        work: f64,
        lower: &SparsityPattern,
        gathered: &[f64],
    ) -> bool {
        self.gathered.clear();
        self.gathered.extend(gathered.iter().map(|&v| v as f32));
        self.values.resize(s.len_val(), 0.0);
        let par = factor_par::<f32>(work);
        let need = s.factorize_numeric_llt_scratch::<f32>(par, Default::default());
        let mem = self.scratch.get_or_insert_with(|| MemBuffer::new(need));
        let (a, factor) = (&self.gathered, &mut self.values);
        let ok = flushed(par, || numeric_llt(s, lower, a, factor, (par, mem)).is_ok());
        self.factorizations += u64::from(ok);
        ok
    }

    /// Apply the single-precision factor's inverse to `r` in place (factor order).
    pub fn precondition(&mut self, s: &SymbolicCholesky<u32>, r: &mut [f64]) {
        let n = r.len();
        let need = s.solve_in_place_scratch::<f32>(1, Par::Seq);
        let mem = self.solve_scratch.get_or_insert_with(|| MemBuffer::new(need));
        self.vector.clear();
        self.vector.extend(r.iter().map(|&v| v as f32));
        let (factor, v) = (LltRef::<'_, u32, f32>::new(s, &self.values), &mut self.vector);
        flushed(Par::Seq, || {
            let v = MatMut::from_column_major_slice_mut(v, n, 1);
            factor.solve_in_place_with_conj(Conj::No, v, Par::Seq, MemStack::new(mem))
        });
        r.iter_mut().zip(&self.vector).for_each(|(r, v)| *r = f64::from(*v));
    }

    /// Solve A x = `b` in place (factor order; A: `lower` with `values` in `f64`) by conjugate
    /// gradients on the single-precision factor to the relative `tolerance` (at least
    /// [`REFINED_TOLERANCE`]); false if they did not reach it within [`MAX_REFINEMENT`]
    /// iterations (`b` then untouched, unless `anyway`: the last iterate).
    pub fn solve(
        &mut self,
        s: &SymbolicCholesky<u32>,
        (lower, values): (&SparsityPattern, &[f64]),
        b: &mut [f64],
        (tolerance, anyway): (f64, bool),
    ) -> bool {
        let mut x = vec![0.0; b.len()];
        let tol = tolerance.max(REFINED_TOLERANCE);
        let out = pcg(lower, values, b, &mut x, |r| self.precondition(s, r), tol, MAX_REFINEMENT);
        self.iterations += u64::from(out.iterations);
        // The criterion is in the factor's norm: a factor that lost the matrix (entries beyond
        // f32's range or below its subnormals) can meet it with a wrong x — the true residual
        // tells.
        let converged = out.converged && residual(lower, values, b, &x) <= RESIDUAL_CHECK.max(tol.sqrt());
        if converged || anyway {
            b.copy_from_slice(&x);
        }
        converged
    }
}

/// faer's numeric LLᵀ, on the symbolic analysis `s`, of the permuted lower triangle `lower`
/// with `values`, into `factor`, on `par` threads in the scratch `mem` (either precision).
pub fn numeric_llt<T: ComplexField>(
    s: &SymbolicCholesky<u32>,
    lower: &SparsityPattern,
    values: &[T],
    factor: &mut [T],
    (par, mem): (Par, &mut MemBuffer),
) -> Result<(), LltError> {
    let sym = SymbolicSparseColMatRef::new_checked(lower.n, lower.n, &lower.col_ptr, None, &lower.row_idx);
    let mat = SparseColMatRef::new(sym, values);
    let stack = MemStack::new(mem);
    s.factorize_numeric_llt::<T>(factor, mat, Side::Lower, Default::default(), par, stack, Default::default())
        .map(|_| ())
}

/// Relative residual ‖b − A x‖ / ‖b‖ a refined solve must reach besides its own criterion [-],
/// or the square root of its tolerance if larger (a step's equilibrium corrections are solved
/// to 10⁻⁴ only): a sanity bound, far above what the criterion leaves, far below the 1 of
/// x = 0 or the NaN of a factor that overflowed.
const RESIDUAL_CHECK: f64 = 1e-6;

/// ‖b − A x‖ / ‖b‖ (0 for b = 0), NaN-safe: NaN compares false against any bound.
fn residual(lower: &SparsityPattern, values: &[f64], b: &[f64], x: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    lower.symmetric_times(values, x, &mut ax);
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let nb = norm(&mut b.iter().copied());
    let nr = norm(&mut b.iter().zip(&ax).map(|(b, a)| b - a));
    if nb > 0.0 {
        nr / nb
    } else if nr == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}
