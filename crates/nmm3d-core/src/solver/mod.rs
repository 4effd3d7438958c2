//! Sparse symmetric positive-definite solves behind one interface, so other backends (an
//! iterative PCG, PETSc for one huge model) can be added without touching the stepper.

mod amg;
mod block_pcg;
mod factor_work;
mod faer_cholesky;
pub mod ordering;
pub mod pcg;
mod permuted;
mod reuse;
mod single;
mod subnormals;

pub use amg::{AmgParams, AmgSolver};
pub use block_pcg::{BlockParams, BlockPcg};
pub use faer_cholesky::FaerCholesky;
use pcg::PcgOutcome;
pub use reuse::{FactorReuse, FactorSnapshot, FactorSource, ReusingSolver, SolveCounts, Solved};

use nmm3d_geom::Vec3;

use crate::assembly::SparsityPattern;

/// Why a factorisation failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SolverFailure {
    /// A non-positive pivot at this equation (original numbering): not positive definite.
    NotPositiveDefinite {
        /// The equation.
        equation: usize,
    },
    /// The symbolic analysis failed.
    Analysis(String),
}

/// A factorise-then-solve linear solver for a fixed sparsity pattern.
pub trait LinearSolver: Send {
    /// Factorise the matrix with the given pattern (lower triangle) and values. The symbolic
    /// analysis (ordering, elimination tree) is done on the first call and reused.
    fn factorize(&mut self, pattern: &SparsityPattern, values: &[f64]) -> Result<(), SolverFailure>;
    /// The pattern changed: the next factorisation redoes the symbolic analysis (the time
    /// counters keep running).
    fn new_pattern(&mut self);
    /// The pattern changed (contact pairs came or went): take `p` as the pattern of the next
    /// factorisations without a new symbolic analysis if every entry of it lies in the
    /// structure of the current analysis's factor; false (nothing changed) if not.
    fn adopt(&mut self, _p: &SparsityPattern) -> bool {
        false
    }
    /// The pattern the current symbolic analysis was made of (checkpoints: adopted patterns
    /// are factorised on it) when another pattern was adopted on it since; when none was (it is
    /// the last factorised pattern), only if `always` (it costs a copy of the pattern).
    fn analysed_pattern(&self, _always: bool) -> Option<SparsityPattern> {
        None
    }
    /// Make the symbolic analysis of `p` now (restoring a checkpoint).
    fn analyse_pattern(&mut self, _p: &SparsityPattern) -> Result<(), SolverFailure> {
        Ok(())
    }
    /// Solve in place with the last factorisation.
    fn solve(&mut self, rhs: &mut [f64]);
    /// [`LinearSolver::solve`] to a relative `tolerance` (in the factor's norm) where the
    /// solve is iterative (a factor in single precision refined); exact otherwise.
    fn solve_to(&mut self, rhs: &mut [f64], _tolerance: f64) {
        self.solve(rhs);
    }
    /// Apply the last factorisation as a preconditioner, in place: its solve, or for a factor
    /// in single precision its triangular solves alone (the caller's PCG refines).
    fn precondition(&mut self, r: &mut [f64]) {
        self.solve(r);
    }
    /// Factorisations made in single precision and their refinement iterations so far.
    fn single_precision(&self) -> (u64, u64) {
        (0, 0)
    }
    /// Stored entries of the factor of the current pattern (0 before the first factorisation).
    fn factor_nonzeros(&self) -> usize;
    /// Seconds spent in symbolic analysis and in numeric factorisation so far.
    fn timings(&self) -> (f64, f64);
    /// Solve a matrix near the last factorised one by this solver's own iterations on that
    /// factorisation (an iterative solver: its preconditioner serves nearby matrices), to the
    /// relative `tolerance` where the solver takes it; `None`: the caller's PCG with
    /// [`LinearSolver::solve`] as the preconditioner does it.
    fn solve_nearby(
        &mut self,
        _pattern: &SparsityPattern,
        _values: &[f64],
        _rhs: &mut [f64],
        _tolerance: f64,
    ) -> Option<PcgOutcome> {
        None
    }
    /// The nodes (free covers, three equations each) are now at `positions()` [m]: a solver
    /// whose preconditioner is built on the model's geometry follows it (the others never ask).
    fn moved(&mut self, _positions: &dyn Fn() -> Vec<Vec3>) {}
    /// The node positions the current factorisation was made at, if it depends on them (a
    /// checkpoint restores them before re-making it) [m].
    fn built_at(&self) -> &[Vec3] {
        &[]
    }
    /// "direct", "amg" or "blocks" (the summary's `linear_solver`).
    fn name(&self) -> &'static str {
        "direct"
    }
    /// Its solve of the factorised matrix is exact (a direct factor). An iterative solver's is
    /// not: its systems on that matrix keep going through its own nearby solves.
    fn exact(&self) -> bool {
        true
    }
    /// What a numeric factorisation of the current analysis costs in PCG iterations on its
    /// factor (arithmetic of LLᵀ over that of two triangular solves and a product); `None`:
    /// not known (iterative solvers), never weighed.
    fn factorization_cost(&self) -> Option<f64> {
        None
    }
    /// Iterations the solver made inside its own solves so far (an iterative solver's).
    fn iterations(&self) -> u64 {
        0
    }
}
