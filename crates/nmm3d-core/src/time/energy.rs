//! Energy accounts of a dynamic run, step by step, and their balance.
//!
//! Per accepted step with increment d (per cover), start and end velocities v₀, v₁:
//!
//! * kinetic K = ½ vᵀ M v (current);
//! * external work W += d · F (gravity and loads are constant over a step);
//! * elastic strain energy U += d · f_int(u₀) + ½ dᵀ K_t d (the internal and constraint forces at
//!   the start plus the tangent's increment: exact for linear elasticity);
//! * contact spring energy S = Σ ½ k_n g² + ½ k_s |s|² over closed points (current);
//! * friction dissipation D_f += Σ L |Δslip| over sliding points (limit × plastic slip);
//! * damping D_d += −½ d · (f_d0 + f_d1), with f_d0, f_d1 the contact dashpots' forces on the
//!   covers at the step's start (before a detection replaces points) and end — their part of
//!   the contacts' work below (`crate::contact::damping`);
//! * numerical dissipation D_n += ½ d · M (a₀ + a₁) − ΔK, with a₀, a₁ the scheme's accelerations
//!   at the start (the last step's end; at the first step the unbalanced force M a₀) and end:
//!   the work of the mean inertial force beyond the kinetic energy gained — zero for the
//!   trapezoidal rule (β = ¼, γ = ½), ½ d · (f₁ − f₀) ≥ 0 for the DDA scheme, which evaluates
//!   the forces at the end of the step;
//! * contact events D_c += −½ d · (f_c0 + f_c1) − (S₁ − S₀) − ΔD_f − ΔD_d, with f_c0, f_c1 the contact
//!   forces on the covers that the scheme's accelerations a₀, a₁ carry and S₀, S₁ the springs'
//!   energy at the step's start (after detection) and end: the work the contacts take from the
//!   blocks beyond what their springs store and friction dissipates. Zero for a spring closed
//!   over the whole step; where a point closes within a step the scheme applies its end force
//!   over the whole approach and dissipates ½ k_n |g₁| g₀ (g₀ > 0 the gap at the start) — the
//!   discrete impact's loss, like the numerical damping of a stiff mode;
//! * balance error E = (K₀ + S₀ + W) − (K + U + S + D_f + D_d + D_n + D_c), with S₀ the springs' energy
//!   at the start of the first step (loaded by the initial equilibrium or by in-situ preloads).
//!
//! The error collects what the other accounts do not explain: energy that appears between
//! steps (a point found overlapping that no spring resisted — a corner that came in unseen),
//! the open–close and Newton tolerances, and in-situ preloads (whose work is not tracked). Krenk
//! (2006), "Energy conservation in Newmark based time integration algorithms", CMAME 195, for the
//! split of the Newmark step's energy.

use serde::{Deserialize, Serialize};

/// Cumulative energy accounts [J].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// Kinetic energy now.
    pub kinetic: f64,
    /// Elastic strain energy (and that of the point constraints) gained since the start.
    pub elastic: f64,
    /// Work of the external forces (gravity, loads) since the start.
    pub external_work: f64,
    /// Energy in the contact springs now.
    pub contact: f64,
    /// Energy dissipated by friction since the start.
    pub friction: f64,
    /// Energy dissipated by the contact dashpots since the start (`contact.damping_ratio`).
    #[serde(default)]
    pub damping: f64,
    /// Energy dissipated by the time integration scheme since the start.
    pub numerical: f64,
    /// Energy the contacts took from the blocks beyond their springs and friction since the
    /// start (points closing or opening within a step).
    #[serde(default)]
    pub contact_events: f64,
    /// Kinetic and contact energy at the start (the reference of the balance).
    pub initial: f64,
}

impl Energy {
    /// Accounts at the start of a run.
    pub fn start(kinetic: f64, contact: f64) -> Self {
        Self { kinetic, contact, initial: kinetic + contact, ..Self::default() }
    }

    /// Add one accepted step: `s` holds its increments, and the kinetic and contact energy at
    /// its end (its `initial` is not read).
    pub fn add(&mut self, s: &Energy) {
        self.kinetic = s.kinetic;
        self.contact = s.contact;
        self.elastic += s.elastic;
        self.external_work += s.external_work;
        self.friction += s.friction;
        self.damping += s.damping;
        self.numerical += s.numerical;
        self.contact_events += s.contact_events;
    }

    /// Balance error: energy put in minus energy accounted for [J].
    pub fn error(&self) -> f64 {
        self.initial + self.external_work
            - (self.kinetic
                + self.elastic
                + self.contact
                + self.friction
                + self.damping
                + self.numerical
                + self.contact_events)
    }

    /// Kinetic and strain energy held beyond what the loads and the start gave [J]: K + U −
    /// (K₀ + S₀ + W). The dissipating accounts never go negative, so without energy from
    /// nowhere K + U + S ≤ K₀ + S₀ + W. The balance does not show such energy — the contact
    /// events' account takes it as negative dissipation — the gain does. The springs' S is
    /// left out: in-situ preloads do work that no account tracks, and it shows in S.
    pub fn gain(&self) -> f64 {
        self.kinetic + self.elastic - (self.initial + self.external_work)
    }

    /// The largest account in magnitude (the scale of the balance error) [J].
    pub fn largest(&self) -> f64 {
        [
            self.kinetic,
            self.elastic,
            self.external_work,
            self.contact,
            self.friction,
            self.damping,
            self.numerical,
            self.contact_events,
            self.initial,
        ]
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_free_fall_step_by_step_balances() {
        // 1 kg falling under g = 10 from rest, trapezoidal steps of 0.1 s: d = v̄ Δt.
        let mut e = Energy::start(0.0, 0.0);
        let (g, dt) = (10.0, 0.1);
        let mut v = 0.0;
        for _ in 0..10 {
            let v1 = v + g * dt;
            let d = 0.5 * (v + v1) * dt;
            e.add(&Energy { kinetic: 0.5 * v1 * v1, external_work: g * d, ..Energy::default() });
            v = v1;
        }
        assert!(e.error().abs() < 1e-12 * e.largest(), "{e:?}");
        assert!(e.gain().abs() < 1e-12 * e.largest());
        // A step that creates energy shows in the error.
        e.add(&Energy { kinetic: e.kinetic + 1.0, ..Energy::default() });
        assert!((e.error() + 1.0).abs() < 1e-12);
    }

    #[test]
    fn energy_booked_as_negative_dissipation_shows_as_a_gain() {
        // At rest on a spring; a step gives the block 2 J of motion from nowhere, which the
        // contact events' account takes: the balance closes, the gain does not.
        let mut e = Energy::start(0.0, 0.5);
        e.add(&Energy { kinetic: 2.0, contact: 0.5, contact_events: -2.0, ..Energy::default() });
        assert!(e.error().abs() < 1e-12);
        assert!((e.gain() - 1.5).abs() < 1e-12, "{}", e.gain());
        // Friction that dissipates what a fall gave: no gain.
        let mut f = Energy::start(0.0, 0.0);
        f.add(&Energy { external_work: 10.0, friction: 9.0, kinetic: 1.0, ..Energy::default() });
        assert!(f.gain() <= 0.0);
    }
}
