//! The run summary, `summary.json`, as types: what a run reports about itself (status, counts,
//! timings, energy, why steps were cut, the checks of its `[[expect]]`). The Python dataclass
//! `nmm3d.RunSummary` mirrors these fields one to one (`tests/test_summary.py` keeps them so);
//! the user guide documents each.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// It reached its end time (or static equilibrium).
    Completed,
    /// A stop request (Ctrl-C) ended it after an accepted step.
    Interrupted,
    /// A static or initial equilibrium did not converge within its iterations.
    NotConverged,
    /// An error ended it; `message` says which.
    Failed,
}

/// Contents of `summary.json`. Values a run could not define (a monitor never sampled, a ratio of
/// nothing) are `null`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// How the run ended.
    pub status: Status,
    /// Why it ended (the error for a failed run).
    pub message: String,
    /// Accepted steps.
    pub steps: u64,
    /// Simulated time at the end [s].
    pub time: f64,
    /// Wall-clock time of the run [s].
    pub wall_seconds: f64,
    /// Blocks after cutting.
    pub blocks: usize,
    /// Manifold elements.
    pub manifold_elements: usize,
    /// Physical covers.
    pub physical_covers: usize,
    /// Equations (degrees of freedom).
    pub dofs: usize,
    /// Deepest overlap of a contact point at the end of an accepted step [m].
    pub max_penetration: f64,
    /// Most contact points closed at once.
    pub max_contact_points: usize,
    /// Open–close iterations, summed over the accepted steps.
    pub open_close_iterations: u64,
    /// Rejected trial steps.
    pub step_cuts: u64,
    /// Steps cut for an overlap beyond `max_penetration_ratio`.
    pub penetration_cuts: u64,
    /// Times the penalties were raised.
    pub penalty_raises: u32,
    /// Corrections that brought dynamic steps to equilibrium at their ends.
    pub equilibrium_iterations: u64,
    /// Contact points found overlapping deeper than a detection lets one arise.
    pub missed_overlaps: u64,
    /// Times the matrix pattern grew for newly closed contacts.
    pub pattern_rebuilds: u64,
    /// Entries of the last Cholesky factor (multigrid: of its operators, prolongators and coarsest factor).
    pub factor_nonzeros: usize,
    /// Numeric factorisations.
    pub factorizations: u64,
    /// Systems solved by preconditioned CG on an earlier factor.
    pub krylov_solves: u64,
    /// CG iterations, those of unconverged attempts included.
    pub krylov_iterations: u64,
    /// CG attempts that fell back to a factorisation.
    pub krylov_failures: u64,
    /// Out-of-balance force over applied force at the last step (`null` before any step).
    pub unbalanced_force_ratio: Option<f64>,
    /// Energy accounts of a dynamic run; `null` for a static one.
    pub energy: Option<EnergySummary>,
    /// Why steps were cut and how large the accepted ones were.
    pub step_diagnostics: StepDiagnostics,
    /// Sign convention of the stresses: always "compression negative".
    pub stress_sign: String,
    /// Seconds per phase of the run.
    pub timings: BTreeMap<String, f64>,
    /// The monitored values of the last history row (`null`: not defined).
    #[serde(rename = "final")]
    pub final_values: BTreeMap<String, Option<f64>>,
    /// The scenario's `[[expect]]` judged on the final values.
    pub checks: Vec<Check>,
    /// The initial static equilibrium, when `initial_equilibrium = true`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_equilibrium: Option<InitialEquilibrium>,
    /// Where a resumed run continued from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resumed_from: Option<ResumedFrom>,
    /// The stages of a staged analysis as they ran (also `stages.csv`); the counters and
    /// timings above are the last stage's model's, steps and time the whole run's.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stages: Vec<StageSummary>,
    /// The linear solver used: "direct" (sparse Cholesky) or "amg" (multigrid PCG).
    #[serde(default = "direct")]
    pub linear_solver: String,
    /// PCG iterations of the multigrid solver (0 with the direct one).
    #[serde(default)]
    pub multigrid_iterations: u64,
    /// A static run with `analysis.static_travel_limit` that ended with every other block in
    /// equilibrium: the blocks that moved beyond the limit (not held), farthest first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_held: Vec<usize>,
    /// The monitors of those blocks (a study judges them failed: they are pinned where they
    /// crossed the limit, which may lie below its criterion's displacement).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_held_monitors: Vec<String>,
    /// The block that came closest to (or went past) the free-fall bound of a dynamic run
    /// under gravity; `null` for a static run or without gravity.
    #[serde(default)]
    pub free_fall: Option<FreeFallSummary>,
    /// Joint pairs found again whose new points pushed harder than their previous ones, lifted to
    /// push as hard, and arrivals lifted to push from the transfer distance
    /// (`contact.carry_joint_force`; 0 in summaries before it).
    #[serde(default)]
    pub carried_joint_forces: u64,
    /// Grown or shrunk patterns factorised on the symbolic analysis of an earlier one, their
    /// entries all inside its factor (0 in summaries before it).
    #[serde(default)]
    pub patterns_adopted: u64,
    /// Factorisations the direct solver made in single precision (`analysis.factor_precision`;
    /// 0 in summaries before it).
    #[serde(default)]
    pub single_precision_factorizations: u64,
    /// Iterations that refined the solves on those factors to double precision.
    #[serde(default)]
    pub refinement_iterations: u64,
}

/// The free-fall bound (`time/free_fall.rs`): no block's centre of mass faster than a body
/// falling freely from the highest point of the moving blocks at the start down to the block's
/// lowest point, starting at the fastest block's initial speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FreeFallSummary {
    /// Largest speed over bound of any block over the run (> 1: past it).
    pub max_ratio: f64,
    /// That block (id of `blocks.csv`).
    pub block: usize,
    /// Name of its body.
    pub body: String,
    /// When [s].
    pub time: f64,
    /// Its centre of mass's speed then [m/s].
    pub speed: f64,
    /// Its bound then [m/s].
    pub bound: f64,
    /// Set when a block went past the bound in a run that gravity alone drives.
    pub warning: Option<String>,
}

fn direct() -> String {
    "direct".into()
}

/// One stage of a staged analysis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StageSummary {
    /// Its name.
    pub name: String,
    /// How it ended.
    pub status: Status,
    /// Why.
    pub message: String,
    /// Simulated time at its start and end [s].
    pub start_time: f64,
    /// Simulated time at its end [s].
    pub end_time: f64,
    /// Accepted steps before it.
    pub start_step: u64,
    /// Accepted steps at its end.
    pub end_step: u64,
    /// Blocks of its model.
    pub blocks: usize,
    /// Unbalanced-force ratio at its end.
    pub unbalanced_force_ratio: Option<f64>,
    /// Wall-clock seconds, building its model included.
    pub wall_seconds: f64,
}

/// The energy accounts at the end [J] and how well they balanced over the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnergySummary {
    /// Kinetic energy now [J].
    pub kinetic: f64,
    /// Elastic strain energy gained since the start [J].
    pub elastic: f64,
    /// Work of gravity and loads since the start [J].
    pub external_work: f64,
    /// Energy in the contact springs now [J].
    pub contact: f64,
    /// Energy dissipated by friction [J].
    pub friction_dissipation: f64,
    /// Energy dissipated by the time integration [J].
    pub numerical_dissipation: f64,
    /// Energy taken by contacts closing or opening within a step [J].
    pub contact_event_dissipation: f64,
    /// Balance error at the end [J].
    pub error: f64,
    /// Largest balance error over the run relative to the largest account of the run.
    pub max_error_ratio: f64,
    /// When that largest error occurred [s].
    pub max_error_time: f64,
    /// Set when `max_error_ratio` or `max_gain_ratio` exceeds 5 %.
    pub warning: Option<String>,
    /// Energy dissipated by the contact dashpots (`contact.damping_ratio`) [J].
    #[serde(default)]
    pub damping_dissipation: f64,
    /// Largest gain over the run — the kinetic and strain energy the blocks held beyond the
    /// energy the loads and the start gave them, energy from nowhere — relative to the
    /// largest account of the run (0 in summaries before it).
    #[serde(default)]
    pub max_gain_ratio: f64,
    /// When that largest gain occurred [s].
    #[serde(default)]
    pub max_gain_time: f64,
}

/// Step cuts by reason and block, and the accepted steps by size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepDiagnostics {
    /// Rejected trials per reason (the names of `cuts.csv`).
    pub cuts_by_reason: BTreeMap<String, u64>,
    /// The blocks most often responsible, most first.
    pub blocks_most_cut: Vec<BlockCuts>,
    /// Accepted steps per bin of Δt.
    pub dt_histogram: Vec<DtBin>,
}

/// A block and how many cuts it was responsible for.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct BlockCuts {
    /// Block id of `blocks.csv`.
    pub block: usize,
    /// Name of its body.
    pub body: String,
    /// Cuts it was responsible for.
    pub cuts: u64,
}

/// Accepted steps with `from ≤ Δt < to`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DtBin {
    /// Lower edge [s].
    pub from: f64,
    /// Upper edge [s].
    pub to: f64,
    /// Accepted steps in the bin.
    pub steps: u64,
}

/// One `[[expect]]` judged on the final value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Check {
    /// The monitored quantity.
    pub quantity: String,
    /// Its final value (`null`: not monitored or not defined).
    pub value: Option<f64>,
    /// The expected value, if one was given.
    pub reference: Option<f64>,
    /// (value − reference) / reference (`null` for a zero or missing reference).
    pub relative_difference: Option<f64>,
    /// Allowed relative difference.
    pub tolerance: f64,
    /// Allowed absolute difference.
    pub absolute_tolerance: f64,
    /// Lower bound on the value, if any.
    pub at_least: Option<f64>,
    /// Upper bound on the value, if any.
    pub at_most: Option<f64>,
    /// Whether the value met the reference and the bounds.
    pub passed: bool,
    /// Where the reference comes from.
    pub source: String,
}

/// The initial static equilibrium's iterations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InitialEquilibrium {
    /// Static iterations it took.
    pub steps: u64,
    /// Out-of-balance force ratio it reached.
    pub unbalanced_force_ratio: f64,
    /// Whether that ratio is within `analysis.equilibrium_tolerance`.
    pub converged: bool,
    /// When it is not: which blocks nothing holds (those still moving at its last step).
    pub warning: Option<String>,
}

/// The checkpoint a resumed run continued from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResumedFrom {
    /// Its step.
    pub step: u64,
    /// Its time [s].
    pub time: f64,
}
