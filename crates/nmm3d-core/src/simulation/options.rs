//! What a run is asked to do and what it gives back.

use std::path::PathBuf;
use std::sync::Arc;

use crate::output::summary::RunSummary;

/// How a run ended.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The summary written to `summary.json`.
    pub summary: RunSummary,
    /// Whether the run completed (false: failed or interrupted, see `summary.status`).
    pub completed: bool,
}

/// Asked after every accepted step: `true` stops the run there (status "interrupted").
#[derive(Clone)]
pub struct StopRequest(pub Arc<dyn Fn() -> bool + Send + Sync>);

impl std::fmt::Debug for StopRequest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StopRequest")
    }
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output directory (created if missing).
    pub out: PathBuf,
    /// Report progress on standard error: a live line on a terminal, a periodic line otherwise.
    pub progress: bool,
    /// Checked after every accepted step (the Python binding checks for Ctrl-C).
    pub stop: Option<StopRequest>,
    /// Continue the run whose `checkpoint.json` is in `out` instead of starting afresh.
    pub resume: bool,
}
