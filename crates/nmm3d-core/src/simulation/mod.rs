//! The façade: build the system, step to the end, record monitors and frames, write outputs.

mod advance;
mod check;
mod options;
mod recorder;
mod run;
mod stages;
mod summary;

pub use crate::output::summary::{RunSummary, Status};
pub use check::check;
pub use options::{RunOptions, RunOutcome, StopRequest};
pub use run::run;
