//! Contact dashpots: a viscous damper beside each closed point's normal spring (Cundall & Strack
//! 1979; the normal "contact damping" of PFC and 3DEC), C = c k_n n nᵀ, nothing while open. It
//! damps what soft joints let blocks do — bounce and rock on them.
//!
//! No shear dashpot: one beside the stuck shear spring (and none while sliding) made the
//! open–close iteration cycle at stick–slip flips — the thesis slope at φ = 33.3° took 10 218
//! steps for 1 s with Δt down to 10⁻⁷ s, against 1 000 steps at 1 ms without it
//! (`docs/theory/contact.md`, *Contact damping*).
//!
//! c is set per block pair from a fraction ξ of critical damping of the pair's normal mode:
//! c = 2ξ √(m / K) with m the pair's reduced mass and K the normal stiffness of its closed points,
//! so each point's share of the dashpot follows its share of the springs and the pair's
//! damping does not depend on how finely the points fall. The damper acts on the relative
//! velocity at the step's end, which Newmark's rule makes linear in the increment:
//! v₁ = γ/(βΔt) rel + (1 − γ/β) v₀ + Δt (1 − γ/(2β)) a₀ (v₀, a₀ of A relative to B at the point).
//! It is left out of the opening test and of the Coulomb limit (both follow the springs).
//!
//! Where the step does not resolve the bounce (ω Δt > 2, ω = √(K/m): stiff penalties) c is
//! capped at c K = 2ξ m (2/Δt): the scheme itself removes a mode it does not resolve (DDA's
//! is L-stable), and an uncapped dashpot there pushes far harder than it takes to stop the pair
//! in one step (on the "auto" dominos over 1.5 s its accounted work was 22.8 kJ uncapped, 5.7 kJ
//! capped, for 0.23 kJ of gravity's work; `docs/theory/energy.md` on that split).

use std::collections::HashMap;

use nmm3d_geom::{Mat3, Vec3};

use super::history::ContactHistory;
use super::record::{ContactRecord, ContactState, Damper};
use crate::state::Motion;
use crate::system::System;

impl ContactRecord {
    /// The damping matrix of the point's state [N s/m].
    fn damping_matrix(&self) -> Mat3 {
        let n = self.normal;
        match self.state {
            ContactState::Open => Mat3::zeros(),
            _ if self.damper.c == 0.0 => Mat3::zeros(),
            ContactState::Stick | ContactState::Slide => self.damper.c * self.kn * n * n.transpose(),
        }
    }

    /// The dashpot linearised in the relative increment: stiffness (3 × 3) and constant force
    /// on A; the force on A is `constant − block · rel`.
    pub fn dashpot(&self) -> (Mat3, Vec3) {
        let c = self.damping_matrix();
        (self.damper.rate * c, -(c * self.damper.lag))
    }

    /// Damper force on A at relative increment `rel` in the current state [N].
    pub fn damper_force(&self, rel: &Vec3) -> Vec3 {
        let (block, constant) = self.dashpot();
        constant - block * rel
    }
}

impl ContactHistory {
    /// Set every point's dashpot for a trial of `dt` by Newmark's (β, γ) from the motion at the
    /// step's start (`state`); ξ = `params.damping_ratio`. Called after the trial's records are
    /// restored.
    pub fn prepare_damping(&mut self, sys: &System, state: &Motion, (beta, gamma): (f64, f64), dt: f64) {
        let xi = self.params.damping_ratio;
        if xi <= 0.0 {
            return;
        }
        let factors = pair_factors(sys, &self.records, xi, dt);
        let (g_b, rate) = (gamma / beta, gamma / (beta * dt));
        let a_factor = dt * (1.0 - 0.5 * g_b);
        for r in &mut self.records {
            let v0 = relative(sys, r, &state.v);
            let a0 = if a_factor != 0.0 { relative(sys, r, &state.a) } else { Vec3::zeros() };
            let c = factors.get(&r.blocks).copied().unwrap_or(0.0);
            r.damper = Damper { c, rate, lag: (1.0 - g_b) * v0 + a_factor * a0, end: Vec3::zeros() };
        }
    }

    /// No dashpots (a static or locked step).
    pub fn clear_damping(&mut self) {
        self.records.iter_mut().for_each(|r| r.damper = Damper::default());
    }

    /// Close the accepted step's dashpots at its final increment `d` (per cover): the step's
    /// end equilibrium may have moved it after the last open–close solve, and the dashpots,
    /// linear in it, acted at the final one. Each point's end force (and its share of
    /// `applied`) is set there.
    pub fn finish_damping(&mut self, sys: &System, d: &[Vec3]) {
        for r in self.records.iter_mut().filter(|r| r.damper.c > 0.0) {
            let end = r.damper_force(&relative(sys, r, d));
            r.applied += end - r.damper.end;
            r.damper.end = end;
        }
    }

    /// Energy the dashpots took from the blocks over the accepted step of increment `d`, by the
    /// scheme's rule, −Σ ½ d · (f₀ + f₁) per cover, with `start` their forces at the step's start
    /// (`damper_forces` then) and f₁ at its end [J]: the dashpot part of the contacts' work.
    pub fn damping_work(&self, sys: &System, d: &[Vec3], start: &[Vec3]) -> f64 {
        let end = self.damper_forces(sys).unwrap_or_default();
        let at = |f: &[Vec3], c: usize| f.get(c).copied().unwrap_or_default();
        d.iter().enumerate().map(|(c, d)| -0.5 * d.dot(&(at(start, c) + at(&end, c)))).sum()
    }

    /// The dashpots' forces as the last solve (or `finish_damping`) left them, per cover [N];
    /// `None` without dashpots. Taken at a step's start, before a detection replaces the
    /// points, they are the dashpot part of the forces the start's acceleration carries.
    pub fn damper_forces(&self, sys: &System) -> Option<Vec<Vec3>> {
        if self.params.damping_ratio <= 0.0 {
            return None;
        }
        let mut f = vec![Vec3::zeros(); sys.covers.covers.len()];
        self.records.iter().for_each(|r| r.scatter(sys, &r.damper.end, &mut f));
        Some(f)
    }
}

/// A per-cover field `x` at the point on A minus at the point on B.
fn relative(sys: &System, r: &ContactRecord, x: &[Vec3]) -> Vec3 {
    r.a.of(sys, x) - r.b.of(sys, x)
}

/// c = 2ξ m min(ω, 2/Δt) / K per block pair (2ξ √(m/K) where the step resolves the bounce): m
/// the reduced mass (a fixed block's is infinite), K the normal penalties of the pair's closed
/// points (all of its points when none is closed yet), ω = √(K/m).
fn pair_factors(sys: &System, records: &[ContactRecord], xi: f64, dt: f64) -> HashMap<(usize, usize), f64> {
    let mass = block_masses(sys);
    let mut stiffness: HashMap<(usize, usize), (f64, f64)> = HashMap::new();
    for r in records {
        let e = stiffness.entry(r.blocks).or_default();
        if r.state != ContactState::Open {
            e.0 += r.kn;
        }
        e.1 += r.kn;
    }
    stiffness
        .into_iter()
        .map(|(pair, (closed, all))| {
            let k = if closed > 0.0 { closed } else { all };
            let m = reduced(mass[pair.0], mass[pair.1]);
            // c K = 2ξ m ω, with ω = √(K/m) capped at 2/Δt (see the module documentation).
            let omega = (k / m).sqrt().min(2.0 / dt);
            (pair, if k > 0.0 && m.is_finite() { 2.0 * xi * m * omega / k } else { 0.0 })
        })
        .collect()
}

/// Each block's mass [kg], infinite for a fixed block.
fn block_masses(sys: &System) -> Vec<f64> {
    let mut m = vec![0.0; sys.geometry.blocks.len()];
    for (c, pc) in sys.covers.covers.iter().enumerate() {
        m[pc.block] += sys.cover_mass[c];
    }
    for (b, block) in sys.geometry.blocks.iter().enumerate() {
        if block.fixed {
            m[b] = f64::INFINITY;
        }
    }
    m
}

/// m₁m₂/(m₁ + m₂), the other mass where one is infinite.
fn reduced(m1: f64, m2: f64) -> f64 {
    match (m1.is_finite(), m2.is_finite()) {
        (true, true) if m1 + m2 > 0.0 => m1 * m2 / (m1 + m2),
        (true, false) => m1,
        (false, true) => m2,
        _ => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::test_point;

    #[test]
    fn a_closed_point_damps_its_normal_velocity_at_the_steps_end() {
        let mut r = test_point(ContactState::Stick, -1e-6);
        r.damper = Damper { c: 1e-3, rate: 2000.0, lag: Vec3::new(0.1, 0.0, -0.2), ..Damper::default() };
        // End velocity (0.1, 0, −0.2) + 2000 rel = (0.12, 0, −0.16); force −c k_n (n·v) n.
        let rel = Vec3::new(1e-5, 0.0, 2e-5);
        for state in [ContactState::Stick, ContactState::Slide] {
            r.state = state;
            assert!((r.damper_force(&rel) - Vec3::new(0.0, 0.0, 1e6 * 0.16)).norm() < 1e-6);
        }
        r.state = ContactState::Open;
        assert_eq!(r.damper_force(&rel), Vec3::zeros());
    }

    #[test]
    fn the_reduced_mass_of_a_pair_with_a_fixed_block_is_the_other() {
        assert_eq!(reduced(2.0, f64::INFINITY), 2.0);
        assert_eq!(reduced(f64::INFINITY, 3.0), 3.0);
        assert!((reduced(2.0, 2.0) - 1.0).abs() < 1e-15);
        assert!(reduced(f64::INFINITY, f64::INFINITY).is_infinite());
    }
}
