//! One accepted step added to the energy accounts of a dynamic run (the terms and their
//! sources are in [`super::energy`]).

use nmm3d_geom::Vec3;

use super::energy::Energy;
use super::vectors::{equation_vector, kinetic_energy, mass_times};
use crate::state::Motion;
use crate::system::System;

/// What an accepted step's energy accounts need besides the state.
pub(super) struct Increment<'a> {
    pub(super) d: &'a [Vec3],
    pub(super) residual: &'a [Vec3],
    /// The unbalanced force at the end, where the step was brought to equilibrium there.
    pub(super) end_residual: Option<&'a [Vec3]>,
    /// The base's force at the start and the end of the step (a moving base only).
    pub(super) base: (Option<&'a [Vec3]>, Option<&'a [Vec3]>),
    pub(super) m_a0: &'a [Vec3],
    pub(super) kinetic0: f64,
    pub(super) friction: f64,
    /// Energy the contact dashpots took over the step [J].
    pub(super) damping: f64,
    /// Contact spring energy at the start and the end of the step [J].
    pub(super) springs: (f64, f64),
    /// Work of the contact forces on the blocks over the step [J].
    pub(super) contact_work: f64,
}

/// Add the step that led to `state` to the accounts `so_far` (started at this step when
/// `None`) and return them; `loads` are the step's dead loads [N] and `tangent` the values of
/// its tangent stiffness on the system's pattern.
pub(super) fn add_step(
    sys: &System,
    state: &Motion,
    s: &Increment,
    (loads, tangent): (&[Vec3], &[f64]),
    so_far: &mut Option<Energy>,
) -> Energy {
    let dot = |f: &[Vec3]| -> f64 { s.d.iter().zip(f).map(|(d, f)| d.dot(f)).sum() };
    // A moving base's force changes over the step: its work by the trapezoidal rule.
    let base_work = match s.base {
        (Some(f0), Some(f1)) => 0.5 * (dot(f0) + dot(f1)),
        _ => 0.0,
    };
    let external_work = dot(loads) + base_work;
    let f_int = |r: &[Vec3]| -> Vec<Vec3> { loads.iter().zip(r).map(|(f, r)| f - r).collect() };
    let elastic = match s.end_residual {
        // The trapezoidal rule on the inner forces at both ends: what the end's equilibrium
        // and the scheme's ½ d·M(a₀ + a₁) make exact.
        Some(r1) => 0.5 * (dot(&f_int(s.residual)) + dot(&f_int(r1))),
        None => {
            dot(&f_int(s.residual)) + 0.5 * sys.assembler.pattern.quadratic_form(tangent, &equation_vector(sys, s.d))
        }
    };
    // The springs' energy at the end of the last step (the bodies never see a change of it
    // between steps — points found or lost by a detection — only the forces applied).
    let springs_before = so_far.map_or(s.springs.0, |e| e.contact);
    let m_a1 = mass_times(sys, &state.a);
    let kinetic = kinetic_energy(sys, &state.v, &mass_times(sys, &state.v));
    let inertial: f64 = s.d.iter().zip(s.m_a0).zip(&m_a1).map(|((d, a0), a1)| 0.5 * d.dot(&(a0 + a1))).sum();
    let step = Energy {
        kinetic,
        elastic,
        external_work,
        contact: s.springs.1,
        friction: s.friction,
        damping: s.damping,
        numerical: inertial - (kinetic - s.kinetic0),
        contact_events: -s.contact_work - (s.springs.1 - springs_before) - s.friction - s.damping,
        initial: 0.0,
    };
    let energy = so_far.get_or_insert_with(|| Energy::start(s.kinetic0, s.springs.0));
    energy.add(&step);
    *energy
}
