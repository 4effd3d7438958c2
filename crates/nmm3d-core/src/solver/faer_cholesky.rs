//! Supernodal sparse Cholesky (faer) with its fill-reducing AMD ordering; the symbolic
//! factorisation is computed once and reused for every numeric factorisation.
//! Runs sequentially (`Par::Seq`): results do not depend on the thread count, and on two
//! cores threads did not speed faer up (`research/ecosystem.md` §3).

use std::time::Instant;

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

use super::LinearSolver;
use crate::assembly::SparsityPattern;

/// faer's sparse LLᵀ.
#[derive(Default)]
pub struct FaerCholesky {
    symbolic: Option<SymbolicLlt<u32>>,
    numeric: Option<Llt<u32, f64>>,
    symbolic_seconds: f64,
    numeric_seconds: f64,
}

impl LinearSolver for FaerCholesky {
    fn factorize(&mut self, p: &SparsityPattern, values: &[f64]) -> Result<(), String> {
        faer::set_global_parallelism(faer::Par::Seq);
        let sym = SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx);
        if self.symbolic.is_none() {
            let t = Instant::now();
            self.symbolic = Some(SymbolicLlt::try_new(sym, Side::Lower).map_err(|e| format!("{e:?}"))?);
            self.symbolic_seconds += t.elapsed().as_secs_f64();
        }
        let t = Instant::now();
        let mat = SparseColMatRef::new(sym, values);
        let symbolic = self.symbolic.clone().expect("set above");
        let llt = Llt::try_new_with_symbolic(symbolic, mat, Side::Lower)
            .map_err(|e| format!("the system matrix is not positive definite ({e:?}): a body may be free to move without inertia, or a penalty may be far too large"))?;
        self.numeric = Some(llt);
        self.numeric_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    fn solve(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let llt = self.numeric.as_ref().expect("factorize before solve");
        llt.solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1));
    }

    fn timings(&self) -> (f64, f64) {
        (self.symbolic_seconds, self.numeric_seconds)
    }
}
