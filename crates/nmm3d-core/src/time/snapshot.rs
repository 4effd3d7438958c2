//! The stepper's caches as data (checkpoints): the matrix pattern grown by contacts, the
//! matrix of the factor in use (re-factorised on resume: later solves are preconditioned by
//! it) and the poses the kept tangent's shares were made at. With the run's [`super::State`]
//! they restart a run bit for bit where it stopped; the solver, the work buffers and the
//! contact surfaces are rebuilt from the model.

use serde::{Deserialize, Serialize};

use super::contact_pattern::{ContactPattern, PatternSnapshot};
use super::kept_tangent::{KeptTangent, TangentSnapshot};
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
    /// What the kept tangent's shares were made at (none in checkpoints written before it:
    /// every share is made afresh at the next step).
    #[serde(default)]
    pub tangent: TangentSnapshot,
}

impl Stepper {
    /// The stepper's caches.
    pub fn snapshot(&self) -> StepperSnapshot {
        let tangent = self.kept.as_ref().map(KeptTangent::snapshot).unwrap_or_default();
        StepperSnapshot { pattern: self.pattern.snapshot(), factor: self.solver.snapshot(), tangent }
    }

    /// A stepper continuing from caches saved on the same model (no initial detection: the
    /// contact points are the run's state's).
    pub fn resume(sys: &System, s: StepperSnapshot) -> Result<Self> {
        let mut stepper = Self::on_model(sys);
        stepper.solver.restore(s.factor).map_err(|f| solver_error(sys, 0, f))?;
        stepper.pattern = ContactPattern::restore(sys, &s.pattern);
        stepper.kept = KeptTangent::restore(sys, &s.tangent);
        Ok(stepper)
    }
}
