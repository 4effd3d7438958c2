//! Checks of `[analysis]`: the run's length and step, the step control, the open–close
//! iteration, the solvers' tolerances and the integrator.

use super::Checker;
use crate::scenario::schema::{Analysis, Integrator, Stiffness};

/// Every `[analysis]` key within its range.
pub(super) fn analysis(c: &mut Checker, a: &Analysis) {
    if !(a.max_step_cut > 0.0 && a.max_step_cut < 1.0) {
        c.fail("analysis.max_step_cut", format!("must lie in (0, 1), got {}", a.max_step_cut));
    }
    if !(a.checkpoint_interval >= 0.0 && a.checkpoint_interval.is_finite()) {
        c.fail("analysis.checkpoint_interval", format!("must be a finite number >= 0, got {}", a.checkpoint_interval));
    }
    for (key, tolerance) in [
        ("analysis.krylov_tolerance", a.krylov_tolerance),
        ("analysis.amg_tolerance", a.amg_tolerance),
        ("analysis.amg_newton_tolerance", a.amg_newton_tolerance),
    ] {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            c.fail(key, format!("must lie in (0, 1), got {tolerance}"));
        }
    }
    if !(a.max_memory >= 0.0 && a.max_memory.is_finite()) {
        c.fail(
            "analysis.max_memory",
            format!("must be a finite number of bytes >= 0 (0: automatic), got {}", a.max_memory),
        );
    }
    if a.krylov_max_iterations == 0 {
        c.fail("analysis.krylov_max_iterations", "must be at least 1");
    }
    c.positive("analysis.duration", a.duration);
    c.positive("analysis.dt", a.dt);
    c.positive("analysis.max_displacement_ratio", a.max_displacement_ratio);
    c.positive("analysis.equilibrium_tolerance", a.equilibrium_tolerance);
    c.positive("analysis.penalty_factor", a.penalty_factor);
    c.positive("analysis.divergence_ratio", a.divergence_ratio);
    if a.max_steps == 0 {
        c.fail("analysis.max_steps", "must be at least 1");
    }
    if !(a.output_interval >= 0.0) {
        c.fail("analysis.output_interval", format!("must be ≥ 0, got {}", a.output_interval));
    }
    if let Some(h) = a.history_interval {
        c.positive("analysis.history_interval", h);
    }
    if let Stiffness::Value(v) = a.penalty_stiffness {
        c.positive("analysis.penalty_stiffness", v);
    }
    if !(a.min_dt_ratio > 0.0 && a.min_dt_ratio <= 1.0) {
        c.fail("analysis.min_dt_ratio", "must be in (0, 1]");
    }
    if !(a.max_dt_growth >= 1.0) {
        c.fail("analysis.max_dt_growth", "must be ≥ 1");
    }
    if !(a.target_displacement_ratio > 0.0 && a.target_displacement_ratio <= 1.0) {
        c.fail("analysis.target_displacement_ratio", "must be in (0, 1]");
    }
    if !(a.static_travel_limit >= 0.0 && a.static_travel_limit.is_finite()) {
        c.fail("analysis.static_travel_limit", "must be a finite length ≥ 0 (0: off)");
    }
    if !(a.settle_dt > 0.0 && a.settle_dt.is_finite()) {
        c.fail("analysis.settle_dt", "must be a finite time > 0");
    }
    if a.max_open_close == 0 {
        c.fail("analysis.max_open_close", "must be at least 1");
    }
    for (key, t) in [
        ("open_close_tolerance", a.open_close_tolerance),
        ("static_open_close_tolerance", a.static_open_close_tolerance),
    ] {
        if !(0.0..1.0).contains(&t) {
            c.fail(format!("analysis.{key}"), "must lie in [0, 1)");
        }
    }
    if !(a.step_equilibrium_tolerance > 0.0 && a.step_equilibrium_tolerance < 1.0) {
        c.fail("analysis.step_equilibrium_tolerance", "must lie in (0, 1)");
    }
    if !(a.step_equilibrium_stall >= a.step_equilibrium_tolerance && a.step_equilibrium_stall < 1.0) {
        c.fail("analysis.step_equilibrium_stall", "must lie in [step_equilibrium_tolerance, 1)");
    }
    if !(a.tangent_keep_angle >= 0.0 && a.tangent_keep_angle < 1.0) {
        c.fail("analysis.tangent_keep_angle", "must lie in [0, 1) rad (0: every tangent afresh)");
    }
    if !(a.max_energy_gain >= 0.0 && a.max_energy_gain.is_finite()) {
        c.fail("analysis.max_energy_gain", "must be finite and ≥ 0");
    }
    if !(a.open_close_cut > 0.0 && a.open_close_cut < 1.0) {
        c.fail("analysis.open_close_cut", "must lie in (0, 1)");
    }
    if a.integrator == Integrator::Newmark {
        c.positive("analysis.newmark_beta", a.newmark_beta);
        if !(a.newmark_gamma >= 0.5) {
            c.fail("analysis.newmark_gamma", "must be ≥ 0.5 for a stable scheme");
        }
    }
    if a.gravity.iter().any(|g| !g.is_finite()) {
        c.fail("analysis.gravity", "must be finite");
    }
}
