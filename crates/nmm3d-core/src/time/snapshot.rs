//! The stepper's caches as data (checkpoints): the matrix pattern grown by contacts and the
//! matrix of the factor in use (re-factorised on resume: later solves are preconditioned by
//! it). With the run's [`super::State`] they restart a run bit for bit where it stopped; the
//! solver, the work buffers and the contact surfaces are rebuilt from the model.

use serde::{Deserialize, Serialize};

use super::contact_pattern::{ContactPattern, PatternSnapshot};
use super::stepper::Stepper;
use super::vectors::solver_error;
use crate::error::Result;
use crate::solver::FactorSnapshot;
use crate::system::System;

/// A [`Stepper`]'s caches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepperSnapshot {
    /// The matrix pattern grown by contacts.
    pub pattern: PatternSnapshot,
    /// The matrix of the factor in use and the solver's counters.
    #[serde(default)]
    pub factor: FactorSnapshot,
}

impl Stepper {
    /// The stepper's caches.
    pub fn snapshot(&self) -> StepperSnapshot {
        StepperSnapshot { pattern: self.pattern.snapshot(), factor: self.solver.snapshot() }
    }

    /// A stepper continuing from caches saved on the same model (no initial detection: the
    /// contact points are the run's state's).
    pub fn resume(sys: &System, s: StepperSnapshot) -> Result<Self> {
        let mut stepper = Self::on_model(sys);
        stepper.solver.restore(s.factor).map_err(|f| solver_error(sys, 0, f))?;
        stepper.pattern = ContactPattern::restore(sys, &s.pattern);
        Ok(stepper)
    }
}
