//! The Newton iterations of a static equilibrium (a static analysis's steps, without contacts):
//! a step that finds the run balanced at its start solves nothing, and a step after an
//! iteration that reduced the unbalanced force well solves with the matrix of the solver's
//! last factor instead of a new tangent (modified Newton: Bathe, *Finite Element Procedures*,
//! 2nd ed., 2014, §8.4.1; Crisfield, *Non-linear Finite Element Analysis of Solids and
//! Structures* 1, 1991, §9.1) — no tangent assembled, and the solve needs no new matrix.

use nmm3d_geom::Vec3;

use super::state::StepperState;
use super::stepper::Stepper;
use super::vectors::unbalanced_ratio;
use crate::scenario::AnalysisKind;
use crate::state::Motion;
use crate::system::System;

/// The unbalanced force must have fallen at least this much (×) over the last iteration for
/// the next to keep its matrix, and over every iteration of the run after the first: the
/// tangent still describes the structure (the 10⁵-ME block gains 30× and 10³× per iteration;
/// a cantilever turning by large rotations ends its first with 2.8× the force it started
/// with, and assembles every tangent from then on).
pub const KEEP_CONTRACTION: f64 = 0.1;

/// Whether the run's steps are Newton iterations of a static equilibrium without contacts.
fn static_newton(sys: &System, run: &StepperState, contacts: bool) -> bool {
    sys.scenario.analysis.kind == AnalysisKind::Static && !run.settling() && !contacts
}

impl Stepper {
    /// Whether a static run without contacts is in equilibrium at the start of a step after its
    /// first (`step` taken so far): the run stops after this step, which then needs no solve —
    /// one Newton iteration of four saved on a continuum (a run with contacts still settles its
    /// contacts' states in the step).
    pub(super) fn balanced_static(
        sys: &System,
        run: &StepperState,
        contacts: bool,
        step: u64,
        unbalanced: f64,
    ) -> bool {
        let a = &sys.scenario.analysis;
        static_newton(sys, run, contacts) && step >= 1 && unbalanced <= a.equilibrium_tolerance
    }

    /// The unbalanced force at the start of a step, and whether its solve keeps the matrix of
    /// the solver's factor (modified Newton): a Newton iteration of a static equilibrium
    /// (factor reuse on) after one that cut the unbalanced force by [`KEEP_CONTRACTION`], in a
    /// run where no iteration did worse — the first one, which starts from the unloaded state
    /// with a loose solve, only if it increased the force. Otherwise the tangent is assembled
    /// as usual.
    pub(super) fn start_residual(
        &mut self,
        sys: &System,
        state: &mut Motion,
        run: &mut StepperState,
        contacts: bool,
    ) -> (Vec<Vec3>, bool) {
        if !static_newton(sys, run, contacts) {
            return (self.assembled(sys, state, super::stepper::dynamic(sys, run)), false);
        }
        let prev = run.newton;
        let reusable = sys.scenario.analysis.factor_reuse && self.solver.source_values().is_some();
        let may_keep = !prev.full && reusable && prev.last.is_some();
        let mut residual =
            if may_keep { self.start_forces(sys, state, None) } else { self.assembled(sys, state, false) };
        let mut ratio = unbalanced_ratio(sys, run, &residual);
        let mut keep = false;
        if let Some(last) = prev.last {
            let bound = if prev.iterations == 1 { 1.0 } else { KEEP_CONTRACTION };
            run.newton.full |= ratio > bound * last;
            keep = may_keep && !run.newton.full && ratio <= KEEP_CONTRACTION * last;
        }
        if may_keep && !keep {
            residual = self.assembled(sys, state, false);
            ratio = unbalanced_ratio(sys, run, &residual);
        }
        // This iteration as the next judges it (a static step is accepted or ends the run; its
        // cuts retry from here, not from its start).
        (run.newton.last, run.newton.iterations) = (Some(ratio), run.newton.iterations + 1);
        (residual, keep)
    }
}
