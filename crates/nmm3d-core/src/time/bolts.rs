//! Bolts in the step: their springs in the tangent and their tension in the unbalanced force
//! (at the step's start state, like the elements'), yield and rupture after each accepted step.
//! A bolt at its yield force flows plastically: it pulls with ±F_y and adds no stiffness over
//! the step (an elastic tangent would resist the flow like a dashpot of k Δt); the update after
//! the step returns an overshoot to F_y or finds it unloading elastically.

use nmm3d_geom::Vec3;

use super::stepper::Stepper;
use crate::state::Motion;
use crate::system::System;

/// A bolt within this fraction of its yield force is yielding.
const YIELD_TOLERANCE: f64 = 1e-9;

/// Add the unbroken bolts' forces to `residual` and their springs to `tangent` if given.
pub(super) fn add_bolts(sys: &System, state: &Motion, residual: &mut [Vec3], mut tangent: Option<&mut Vec<f64>>) {
    let first = sys.covers.elements.len();
    for (k, (b, s)) in sys.bolts.iter().zip(&state.bolts).enumerate().filter(|(_, (_, s))| !s.broken) {
        let tension = b.tension(b.elongation(&state.u), s.plastic);
        let yielding = tension.abs() >= b.yield_force * (1.0 - YIELD_TOLERANCE);
        let tension = if yielding { tension.signum() * b.yield_force } else { tension };
        for (&c, w) in b.covers.iter().zip(&b.weights) {
            residual[c] -= w * tension * b.axis;
        }
        if let (false, Some(t)) = (yielding, tangent.as_deref_mut()) {
            sys.assembler.add(t, first + k, &b.local_matrix());
        }
    }
}

impl Stepper {
    /// After an accepted step: each bolt yields or breaks at its elongation.
    pub(super) fn update_bolts(&self, sys: &System, state: &mut Motion) {
        for (b, s) in sys.bolts.iter().zip(state.bolts.iter_mut()) {
            let delta = b.elongation(&state.u);
            s.update(b, delta);
        }
    }
}

/// Tension [N] (0 once broken) and elongation [m] of each bolt, in the order of its history
/// columns.
pub fn bolt_values(sys: &System, state: &Motion) -> Vec<f64> {
    sys.bolts
        .iter()
        .zip(&state.bolts)
        .flat_map(|(b, s)| {
            let delta = b.elongation(&state.u);
            [if s.broken { 0.0 } else { b.tension(delta, s.plastic) }, delta]
        })
        .collect()
}
