//! The stepper's run state as data (checkpoints): with the [`State`] it restarts a run exactly
//! where it stopped. The solver, the work buffers and the contact surfaces are rebuilt from the
//! model; the contact points, the matrix pattern they grew, the matrix of the factor in use
//! (re-factorised on resume: later solves are preconditioned by it), the penalties as raised,
//! the force scale, the counters and the energy accounts are kept.

use nmm3d_geom::Vec3;
use serde::{Deserialize, Serialize};

use super::contact_pattern::{ContactPattern, PatternSnapshot};
use super::setup::{contact_params, solver};
use super::stepper::{PhaseTimes, Stepper};
use super::vectors::{lumped_mass, solver_error};
use super::{Energy, Newmark};
use crate::contact::snapshot::ContactSnapshot;
use crate::contact::ContactSet;
use crate::error::Result;
use crate::solver::FactorSnapshot;
use crate::system::System;

/// A [`Stepper`]'s state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepperSnapshot {
    /// Contact points and their history (`None` without contact).
    pub contacts: Option<ContactSnapshot>,
    /// The matrix pattern grown by contacts.
    pub pattern: PatternSnapshot,
    /// The matrix of the factor in use and the solver's counters.
    #[serde(default)]
    pub factor: FactorSnapshot,
    /// Force scale of the unbalanced force ratio [N].
    pub force_scale: f64,
    /// Contacts locked.
    pub locked: bool,
    /// Steps carry inertia.
    pub inertia: bool,
    /// Penetration cuts so far.
    pub penetration_cuts: u64,
    /// Penalty raises so far.
    pub penalty_raises: u32,
    /// Equilibrium iterations of dynamic steps so far.
    #[serde(default)]
    pub equilibrium_iterations: u64,
    /// Energy accounts so far.
    pub energy: Option<Energy>,
    /// Largest displacement summed over the steps since the last contact detection [m]; a
    /// checkpoint without it detects at its first step.
    #[serde(default = "never_detected")]
    pub undetected: f64,
    /// Contact forces on the covers at the end of the last step [N] (energy accounts; a
    /// checkpoint without them takes the next step's start forces).
    #[serde(default)]
    pub contact_end: Vec<Vec3>,
}

fn never_detected() -> f64 {
    f64::MAX
}

impl Stepper {
    /// The stepper's state.
    pub fn snapshot(&self) -> StepperSnapshot {
        StepperSnapshot {
            contacts: self.contacts.as_ref().map(ContactSet::snapshot),
            pattern: self.pattern.snapshot(),
            factor: self.solver.snapshot(),
            force_scale: self.force_scale,
            locked: self.locked,
            inertia: self.inertia,
            penetration_cuts: self.penetration_cuts,
            penalty_raises: self.penalty_raises,
            equilibrium_iterations: self.equilibrium_iterations,
            energy: self.energy,
            // Finite: JSON has no infinity.
            undetected: self.undetected.min(f64::MAX),
            contact_end: self.contact_end.clone(),
        }
    }

    /// A stepper continuing from a snapshot taken on the same model (no initial detection: the
    /// contact points are the snapshot's).
    pub fn resume(sys: &System, s: StepperSnapshot) -> Result<Self> {
        let nnz = sys.assembler.pattern.nnz();
        let contacts = match (s.contacts, sys.scenario.contact.enabled) {
            (Some(snap), true) => ContactSet::new(sys, contact_params(sys)).map(|mut c| {
                c.restore(snap);
                c
            }),
            _ => None,
        };
        let mut solver = solver(sys);
        solver.restore(s.factor).map_err(|f| solver_error(sys, 0, f))?;
        Ok(Self {
            solver,
            pattern: ContactPattern::restore(sys, &s.pattern),
            contacts,
            newmark: Newmark::from_analysis(&sys.scenario.analysis),
            tangent: vec![0.0; nnz],
            values: vec![0.0; nnz],
            force_scale: s.force_scale,
            locked: s.locked,
            inertia: s.inertia,
            penetration_cuts: s.penetration_cuts,
            penalty_raises: s.penalty_raises,
            equilibrium_iterations: s.equilibrium_iterations,
            times: PhaseTimes::default(),
            energy: s.energy,
            cuts: Vec::new(),
            undetected: s.undetected,
            loads: Vec::new(),
            contact_end: s.contact_end,
            lumped_mass: lumped_mass(sys),
        })
    }
}
