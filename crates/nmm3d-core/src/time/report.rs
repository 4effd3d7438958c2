//! What a step reports: its diagnostics (one row of `diagnostics.csv`) and the stepper's time
//! per phase (`summary.json` `timings`).

use super::energy::Energy;

/// Diagnostics of one accepted step.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepReport {
    /// Contact points detected at the start of the step.
    pub contacts: usize,
    /// Open–close iterations of the accepted trial.
    pub open_close: u32,
    /// Largest penetration after the step [m].
    pub max_penetration: f64,
    /// Accepted step [s].
    pub dt: f64,
    /// Rejected trials before acceptance.
    pub cuts: u32,
    /// Displacement ratio of the accepted step.
    pub ratio: f64,
    /// Unbalanced force / force scale at the start of the step.
    pub unbalanced: f64,
    /// Energy accounts after the step (dynamic runs; zero otherwise).
    pub energy: Energy,
    /// Numeric factorisations the step made: its rejected trials, every open–close iteration
    /// and the equilibrium iterations included (set by the run's loop).
    #[serde(default)]
    pub factorizations: u64,
}

/// Seconds spent per phase.
#[derive(Debug, Clone, Copy, Default)]
pub struct PhaseTimes {
    /// Element loop and scatter.
    pub assembly: f64,
    /// Matrices combined and factorised (symbolic analysis included), with their solve.
    pub factorization: f64,
    /// Systems solved by PCG on an earlier factor (matrices combined included).
    pub krylov: f64,
    /// Right-hand sides gathered, solutions scattered.
    pub solve: f64,
    /// Open–close iterations beyond the first (their factorisations and solves included).
    pub open_close: f64,
    /// Equilibrium iterations of dynamic steps (their element loops and solves).
    pub equilibrium: f64,
    /// Sparsity pattern growth for newly closed ME pairs (the symbolic analysis that follows
    /// is counted with the factorisation).
    pub pattern: f64,
}
