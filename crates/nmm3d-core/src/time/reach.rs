//! How far a material point can move in the coming step: the detection margin of a dynamic
//! step. The step control allows a step to move a point by up to `max_displacement_ratio` × half
//! the model size, which grows with the model (0.24 m on a pile of 8 000 half-metre cubes), and
//! a margin that wide makes every block a candidate of its neighbours' neighbours. The motion
//! the step will have is known far better from its start: a point moves by
//! v Δt + (½ − β) a Δt² + β a₁ Δt², bounded here by |v| Δt + (|a| + |g|) Δt² — twice the
//! Newmark acceleration terms, and gravity's in case a support opens — times
//! `contact.reach_safety` (4): an impact in the step moves blocks farther than their start
//! tells. A point that travels farther still is caught by the lagged verification, which
//! detects the step's end on the warning list (it keeps the full margin) and solves the step
//! again; but that adds only points deeper than the tolerance, and on the thesis slope (case A,
//! 10 s) a safety of 1 left three points to be found late, 14.5 mm and more inside, 2 one and
//! 4 none.

use super::state::StepperState;
use super::stepper::Stepper;
use crate::scenario::AnalysisKind;
use crate::state::Motion;
use crate::system::System;

impl Stepper {
    /// How far a cover may move in a step of `dt` [m] from `state` (infinite for a
    /// static or locked step, whose displacement the velocities do not tell, and under a
    /// shaking base).
    pub(super) fn reach(sys: &System, (state, run): (&Motion, &StepperState), dt: f64) -> f64 {
        let a = &sys.scenario.analysis;
        if !run.inertia || run.settling() || a.kind == AnalysisKind::Static || sys.scenario.seismic.moves() {
            return f64::INFINITY;
        }
        let g = nmm3d_geom::Vec3::from(a.gravity).norm();
        (0..state.v.len())
            .filter(|&c| sys.dofs.moves(c))
            .map(|c| state.v[c].norm() * dt + (state.a[c].norm() + g) * dt * dt)
            .fold(0.0, f64::max)
            * sys.scenario.contact.reach_safety
    }
}
