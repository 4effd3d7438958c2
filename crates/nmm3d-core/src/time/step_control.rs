//! Adaptive time step from the maximum displacement ratio (DDA's g₂ rule, Shi 1988;
//! ntdda `timestep.c`), with every constant a named scenario parameter:
//!
//! * ratio r = max_i |d_i| / (g₂ w₀), w₀ = half the largest model extent;
//! * r > 1: the step is rejected and repeated with Δt ← Δt · max(`max_step_cut`, target / r), not below
//!   `min_dt_ratio · dt`; at the smallest step, r ≤ `divergence_ratio` is accepted, more is
//!   divergence;
//! * accepted: the next Δt = min(dt, remaining time, Δt · min(max_dt_growth, target / r)), at
//!   least `min_dt_ratio · dt`.

use std::borrow::Cow;

use crate::scenario::{Analysis, AnalysisKind};

/// What to do with a trial step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Accept it.
    Accept,
    /// Repeat with this step.
    Retry(f64),
    /// No acceptable step exists.
    Diverged,
}

/// The controls a step goes by: the scenario's, or in the frictional initial equilibrium's
/// static steps (`relaxing`) those of a static analysis whose Δt is `settle_dt`.
pub fn controls(a: &Analysis, relaxing: bool) -> Cow<'_, Analysis> {
    if !relaxing {
        return Cow::Borrowed(a);
    }
    Cow::Owned(Analysis { kind: AnalysisKind::Static, dt: a.settle_dt, ..a.clone() })
}

/// Judge a trial step of size `dt` that gave displacement ratio `r`.
pub fn judge(a: &Analysis, dt: f64, r: f64) -> Verdict {
    let dt_min = a.min_dt_ratio * a.dt;
    if !r.is_finite() {
        return if dt > dt_min { Verdict::Retry((dt * a.max_step_cut).max(dt_min)) } else { Verdict::Diverged };
    }
    if r <= 1.0 {
        return Verdict::Accept;
    }
    if dt > dt_min * (1.0 + 1e-12) {
        return Verdict::Retry((dt * (a.target_displacement_ratio / r).max(a.max_step_cut)).max(dt_min));
    }
    if r <= a.divergence_ratio {
        Verdict::Accept
    } else {
        Verdict::Diverged
    }
}

/// Judge a trial whose open–close iteration did not settle (or whose contacts overlap too
/// deep): cut by `open_close_cut` (DDA cuts to 0.3 Δt), down to the smallest step, where the
/// run cannot go on.
pub fn judge_unsettled(a: &Analysis, dt: f64) -> Verdict {
    let dt_min = a.min_dt_ratio * a.dt;
    if dt > dt_min * (1.0 + 1e-12) {
        Verdict::Retry((dt * a.open_close_cut).max(dt_min))
    } else {
        Verdict::Diverged
    }
}

/// Step size after an accepted step of size `dt` with ratio `r`, never below the smallest
/// step: a step accepted there with r > 1 (its displacement does not shrink with Δt) would
/// otherwise shrink the next one geometrically, and the run would stall without a word.
pub fn next_dt(a: &Analysis, dt: f64, r: f64) -> f64 {
    let grow = if r > 0.0 { (a.target_displacement_ratio / r).min(a.max_dt_growth) } else { a.max_dt_growth };
    (dt * grow).min(a.dt).max(a.min_dt_ratio * a.dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_and_growth_follow_the_rules() {
        let a = Analysis::default();
        assert_eq!(judge(&a, 1e-3, 0.5), Verdict::Accept);
        assert_eq!(judge(&a, 1e-3, 4.0), Verdict::Retry(1e-3 * 0.2));
        assert_eq!(judge(&a, 1e-3, 1e6), Verdict::Retry(1e-4));
        assert_eq!(judge(&a, 1e-7, 2.0), Verdict::Accept);
        assert_eq!(judge(&a, 1e-7, 1e9), Verdict::Diverged);
        assert!((next_dt(&a, 1e-4, 0.1) - 1.2e-4).abs() < 1e-18);
        assert_eq!(next_dt(&a, 1e-3, 0.0), 1e-3);
        // Accepted at the smallest step with r > 1: the next step is not smaller still.
        assert_eq!(next_dt(&a, a.min_dt_ratio * a.dt, 10.0), a.min_dt_ratio * a.dt);
    }

    #[test]
    fn an_unsettled_step_is_cut_then_fails_at_the_smallest_step() {
        let a = Analysis::default();
        assert_eq!(judge_unsettled(&a, 1e-3), Verdict::Retry(1e-3 * 0.3));
        assert_eq!(judge_unsettled(&a, 2e-7), Verdict::Retry(a.min_dt_ratio * a.dt));
        assert_eq!(judge_unsettled(&a, 1e-7), Verdict::Diverged);
    }

    #[test]
    fn the_frictional_settling_steps_by_settle_dt_as_a_static_analysis() {
        let a = Analysis { dt: 1e-3, settle_dt: 0.5, ..Analysis::default() };
        assert!(matches!(controls(&a, false), Cow::Borrowed(_)));
        let c = controls(&a, true);
        assert_eq!((c.kind, c.dt), (AnalysisKind::Static, 0.5));
        assert_eq!(c.settle_tolerance(), a.static_open_close_tolerance);
        assert_eq!(next_dt(&c, 0.45, 0.0), 0.5, "grows up to settle_dt, not the run's dt");
    }
}
