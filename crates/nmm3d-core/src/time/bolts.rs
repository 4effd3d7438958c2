//! Bolts in the step: their springs in the tangent and their forces in the unbalanced force
//! (at the step's start state, like the elements'), yield and rupture after each accepted step.
//! A spring at its axial (or shear) capacity flows plastically: it pulls with that capacity and
//! adds no axial (shear) stiffness over the step (an elastic tangent would resist the flow like
//! a dashpot of k Δt); the update after the step returns an overshoot to the capacity or finds
//! it unloading elastically.

use nmm3d_geom::Vec3;

use super::stepper::Stepper;
use crate::element::bolt::{BoltSpring, BoltState};
use crate::state::Motion;
use crate::system::System;

/// A spring within this fraction of its capacity is yielding.
const YIELD_TOLERANCE: f64 = 1e-9;

/// The forces of a spring at relative displacement `d`, capped at its capacities: (tension
/// [N], shear force [N], axial elastic, shear elastic).
fn forces(b: &BoltSpring, s: &BoltState, d: &Vec3) -> (f64, Vec3, bool, bool) {
    let tension = b.tension(b.axis.dot(d), s.plastic);
    let axial = tension.abs() < b.law.yield_force * (1.0 - YIELD_TOLERANCE);
    let tension = if axial { tension } else { tension.signum() * b.law.yield_force };
    let shear = s.trial_shear(b, d);
    let m = shear.norm();
    let elastic = m < b.law.shear_capacity * (1.0 - YIELD_TOLERANCE);
    let shear = if elastic { shear } else { shear * (b.law.shear_capacity / m) };
    (tension, shear, axial, elastic)
}

/// Add the unbroken bolt springs' forces to `residual` and their stiffness to `tangent` if
/// given.
pub(super) fn add_bolts(sys: &System, state: &Motion, residual: &mut [Vec3], mut tangent: Option<&mut Vec<f64>>) {
    let first = sys.covers.elements.len();
    for (k, (b, s)) in sys.bolts.iter().zip(&state.bolts).enumerate().filter(|(_, (_, s))| !s.broken) {
        let (tension, shear, axial, elastic) = forces(b, s, &s.relative(b, &state.u));
        let f = b.axis * tension + shear;
        for (&c, w) in b.covers.iter().zip(&b.weights) {
            residual[c] -= *w * f;
        }
        if let (true, Some(t)) = (axial || (elastic && b.law.shear_stiffness > 0.0), tangent.as_deref_mut()) {
            sys.assembler.add(t, first + k, &b.local_matrix(axial, elastic));
        }
    }
}

impl Stepper {
    /// After an accepted step: each bolt spring yields or breaks.
    pub(super) fn update_bolts(&self, sys: &System, state: &mut Motion) {
        for (b, s) in sys.bolts.iter().zip(state.bolts.iter_mut()) {
            let d = s.relative(b, &state.u);
            s.update(b, &d);
        }
    }
}

/// Tension [N] (0 once broken), elongation [m] and shear force [N] of each spring.
pub fn spring_forces(sys: &System, state: &Motion) -> Vec<(f64, f64, f64)> {
    sys.bolts
        .iter()
        .zip(&state.bolts)
        .map(|(b, s)| {
            let d = s.relative(b, &state.u);
            let (tension, shear, _, _) = forces(b, s, &d);
            if s.broken {
                (0.0, b.axis.dot(&d), 0.0)
            } else {
                (tension, b.axis.dot(&d), shear.norm())
            }
        })
        .collect()
}

/// The history values of each scenario bolt, in the order of its columns: its largest tension
/// [N] and elongation [m] over its springs (a grouted bolt's joints), and a grouted bolt's
/// largest shear force [N].
pub fn bolt_values(sys: &System, state: &Motion) -> Vec<f64> {
    let springs = spring_forces(sys, state);
    let mut out = Vec::new();
    for (i, b) in sys.scenario.bolt.iter().enumerate() {
        let mine = || sys.bolts.iter().zip(&springs).filter(move |(s, _)| s.bolt == i).map(|(_, f)| *f);
        let largest = |f: fn(&(f64, f64, f64)) -> f64| {
            mine().map(|v| f(&v)).fold(0.0, |a: f64, v| if v.abs() > a.abs() { v } else { a })
        };
        out.push(largest(|v| v.0));
        out.push(largest(|v| v.1));
        if b.grout.grouted {
            out.push(largest(|v| v.2));
        }
    }
    out
}
