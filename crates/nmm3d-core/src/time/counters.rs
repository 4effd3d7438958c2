//! What a stepper reports to the run's summary: its contact surfaces, its solver and what the
//! solver did.

use super::stepper::Stepper;
use crate::contact::ContactSurfaces;
use crate::solver::{ReusingSolver, SolveCounts};

impl Stepper {
    /// The contact surfaces (`None` without contact).
    pub fn contacts(&self) -> Option<&ContactSurfaces> {
        self.contacts.as_ref()
    }

    /// Times the sparsity pattern grew for new contacts.
    pub fn pattern_rebuilds(&self) -> u64 {
        self.pattern.rebuilds
    }

    /// Stored entries of the current factor.
    pub fn factor_nonzeros(&self) -> usize {
        self.solver.factor_nonzeros()
    }

    /// The linear solver (what it did so far).
    pub fn solver(&self) -> &ReusingSolver {
        &self.solver
    }

    /// Factorisations and PCG solves so far.
    pub fn solve_counts(&self) -> SolveCounts {
        self.solver.counts
    }

    /// Symbolic and numeric factorisation seconds of the solver.
    pub fn solver_timings(&self) -> (f64, f64) {
        self.solver.timings()
    }
}
