//! The whole mutable state of a run: the bodies' motion, the contact history and what the
//! steps so far leave to the next (counters, energy accounts, the lock of the initial
//! equilibrium). Cheap to clone (a step's trials restart from it), serialisable (checkpoints)
//! and compared for equality (a resumed run equals the run that never stopped). The
//! [`super::Stepper`] holds only the model's derived data, parameters and scratch.

use nmm3d_geom::Vec3;
use serde::{Deserialize, Serialize};

use super::energy::Energy;
use super::free_fall::FreeFall;
use crate::contact::ContactHistory;
use crate::state::Motion;
use crate::system::System;

/// Everything of a run that changes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time, positions, velocities, accelerations, co-rotations, bolts.
    pub motion: Motion,
    /// Contact points and their history (`None` without contact or with one block).
    pub contact: Option<ContactHistory>,
    /// The stepper's counters and accounts.
    pub stepper: StepperState,
}

/// What the stepper carries from step to step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepperState {
    /// Force scale of the unbalanced force ratio [N] (set when the run starts).
    pub force_scale: f64,
    /// Contacts locked (initial equilibrium): closed points stick whatever the force.
    pub locked: bool,
    /// The frictional initial equilibrium's static steps: contacts free, velocities reset,
    /// Δt from `analysis.settle_dt`.
    #[serde(default)]
    pub relaxing: bool,
    /// Steps carry the inertia term; without it a step is a Newton iteration of the static
    /// equilibrium (the initial equilibrium's first try).
    pub inertia: bool,
    /// Step cuts because a contact overlapped beyond the allowed depth.
    pub penetration_cuts: u64,
    /// Times the contact penalties were raised because a contact overlapped too deep.
    pub penalty_raises: u32,
    /// Equilibrium iterations of dynamic steps (see `equilibrate`).
    #[serde(default)]
    pub equilibrium_iterations: u64,
    /// Energy accounts of the run so far (dynamic runs, from the first step on).
    pub energy: Option<Energy>,
    /// Largest displacement summed over the steps since the last contact detection [m]; a
    /// checkpoint without it detects at its first step.
    #[serde(default = "never_detected")]
    pub undetected: f64,
    /// Contact forces on the covers at the end of the last accepted step (what its
    /// acceleration carries; empty before the first) [N]; a checkpoint without them takes the
    /// next step's start forces.
    #[serde(default)]
    pub contact_end: Vec<Vec3>,
    /// The Newton iterations of a static equilibrium so far (see `newton`).
    #[serde(default)]
    pub newton: NewtonState,
    /// The free-fall bound of a dynamic run so far (`free_fall`; `None` before its first
    /// step, without gravity, and in checkpoints written before it existed).
    #[serde(default)]
    pub free_fall: Option<FreeFall>,
}

/// What the next Newton iteration of a static equilibrium goes by (see `newton`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct NewtonState {
    /// Unbalanced force ratio at the start of the last iteration (`None` before one).
    pub last: Option<f64>,
    /// Iterations so far.
    pub iterations: u64,
    /// An iteration after the first reduced the unbalanced force by less than
    /// `KEEP_CONTRACTION`, or the first increased it: a geometrically nonlinear structure,
    /// whose iterations all assemble their tangent.
    pub full: bool,
}

impl StepperState {
    /// Inside an initial equilibrium (locked or frictional): static steps, no energy accounts.
    pub fn settling(&self) -> bool {
        self.locked || self.relaxing
    }
}

fn never_detected() -> f64 {
    f64::MAX
}

impl Default for StepperState {
    fn default() -> Self {
        Self {
            force_scale: 0.0,
            locked: false,
            relaxing: false,
            inertia: true,
            penetration_cuts: 0,
            penalty_raises: 0,
            equilibrium_iterations: 0,
            energy: None,
            undetected: 0.0,
            contact_end: Vec::new(),
            newton: NewtonState::default(),
            free_fall: None,
        }
    }
}

impl State {
    /// The state at t = 0, before the first contact detection (`Stepper::new` makes it).
    pub fn initial(sys: &System) -> Self {
        Self { motion: Motion::initial(sys), contact: None, stepper: StepperState::default() }
    }
}
