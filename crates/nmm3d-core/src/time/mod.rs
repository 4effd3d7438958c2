//! Time stepping: Newmark/DDA integration, co-rotation, adaptive step, the stepper.

mod account;
mod base_motion;
mod bolts;
pub mod carry;
pub mod contact_pattern;
pub mod corotation;
mod counters;
pub mod cut;
pub mod energy;
mod equilibrate;
mod finish;
pub mod free_fall;
mod gain;
mod held;
pub mod integrator;
pub mod kept_tangent;
mod newton;
mod reach;
pub mod report;
mod residual;
pub mod settle;
mod setup;
pub mod snapshot;
pub mod state;
pub mod step_control;
pub mod stepper;
mod trial;
mod vectors;
mod water;

pub use bolts::{bolt_values, spring_forces};
pub use cut::{Cut, CutReason};
pub use energy::Energy;
pub use integrator::Newmark;
pub use report::{PhaseTimes, StepReport};
pub use state::{State, StepperState};
pub use stepper::Stepper;
