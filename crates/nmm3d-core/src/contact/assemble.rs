//! The contact terms of the system: every closed point's spring scattered through the coupling
//! of its pair of MEs, the start-of-step forces, and the energy in the springs.

use nmm3d_geom::Vec3;

use super::history::ContactHistory;
use super::record::{ContactRecord, ContactState};
use crate::assembly::{Coupling, SparsityPattern};
use crate::system::System;

impl ContactHistory {
    /// The springs of every closed point, summed per pair of MEs and scattered into `values`
    /// (on `pattern`) through the pair's coupling (its covers, lower ME first); the constant
    /// forces go straight to `force` per cover. A point's matrix is w wᵀ ⊗ B, so tied covers
    /// are folded into the weights (Tᵀ w) before the product, not after; only the lower node
    /// blocks, which the coupling scatters, are summed.
    pub fn assemble<'a>(
        &self,
        sys: &System,
        force: &mut [Vec3],
        pattern: &SparsityPattern,
        coupling: impl Fn((usize, usize)) -> &'a Coupling,
        values: &mut [f64],
    ) {
        let mut order: Vec<usize> =
            (0..self.records.len()).filter(|&k| self.records[k].state != ContactState::Open).collect();
        order.sort_by_key(|&k| self.records[k].element_pair());
        let (mut mat, mut w, mut wm) = (Vec::new(), Vec::new(), Vec::new());
        for points in order.chunk_by(|&a, &b| self.records[a].element_pair() == self.records[b].element_pair()) {
            let cp = coupling(self.records[points[0]].element_pair());
            let m = cp.nodes();
            mat.clear();
            mat.resize(9 * m * m, 0.0);
            for &k in points {
                let r = &self.records[k];
                let (block, f) = r.spring();
                // Weights in the clique order of the pair (lower ME first); B's negative.
                let (first, second, sign) =
                    if r.a.element < r.b.element { (&r.a, &r.b, 1.0) } else { (&r.b, &r.a, -1.0) };
                w.clear();
                w.extend(first.weights.iter().map(|x| sign * x).chain(second.weights.iter().map(|x| -sign * x)));
                let covers =
                    sys.covers.elements[first.element].covers.iter().chain(&sys.covers.elements[second.element].covers);
                for (&c, wc) in covers.zip(&w) {
                    force[c] += *wc * f;
                }
                cp.node_weights(&w, &mut wm);
                let b: [f64; 9] = std::array::from_fn(|t| block[(t / 3, t % 3)]);
                // The lower node blocks (q ≤ p: the coupling's nodes are in equation order).
                for (p, &wp) in wm.iter().enumerate().filter(|(_, x)| **x != 0.0) {
                    for (q, &wq) in wm[..=p].iter().enumerate().filter(|(_, x)| **x != 0.0) {
                        let s = wp * wq;
                        let dst = &mut mat[9 * (p * m + q)..][..9];
                        dst.iter_mut().zip(&b).for_each(|(d, b)| *d += s * b);
                    }
                }
            }
            cp.add(pattern, values, &mat);
        }
    }

    /// Add each point's force at the start of the step (springs at the start gaps and
    /// extensions) to the per-cover forces `f`.
    pub fn add_start_forces(&self, sys: &System, f: &mut [Vec3]) {
        for r in &self.records {
            let (n, kn) = (r.normal, r.kn);
            let spring = -kn * r.gap0 * n;
            let force = match r.state {
                ContactState::Open => continue,
                ContactState::Stick => r.preload + spring - r.ks * r.shear0,
                ContactState::Slide => {
                    let normal = (n.dot(&r.preload) - kn * r.gap0).max(0.0);
                    n * n.dot(&r.preload) + spring - (r.strength.tan_phi * normal + r.strength.cohesion) * r.slip
                }
            };
            // The dashpot's force as the last step ended (the point's, if it is the same one).
            r.scatter(sys, &(force + r.damper.end), f);
        }
    }

    /// Add each point's force as the last solve applied it (the step's end) to the per-cover
    /// forces `f`.
    pub fn add_end_forces(&self, sys: &System, f: &mut [Vec3]) {
        for r in &self.records {
            r.scatter(sys, &r.applied, f);
        }
    }

    /// Energy in the springs of the closed points: ½ k_n g² for an overlap, ½ k_s |s|² [J]
    /// (after `accept`; an in-situ preload's share is not counted).
    pub fn spring_energy(&self) -> f64 {
        self.records.iter().map(ContactRecord::spring_energy).sum()
    }

    /// Some point opened or closed during this step's open–close iterations (only such a step
    /// can give the blocks energy at an impact, `crate::time::gain`).
    pub fn any_event(&self) -> bool {
        self.records.iter().any(ContactRecord::event)
    }

    /// The energy the points that closed or opened in the step just accepted gave the blocks
    /// [J], their contact events' share of −(D_c + D_n) (`crate::time::energy`): the work the
    /// scheme did with their forces at the step's start (as detected or carried) and as the last
    /// solve applied them, ((1 − γ) f₀ + γ f₁) · rel — a Newmark step with β = γ/2 moves the
    /// blocks by Δt times their mean velocity and changes their momentum by Δt ((1 − γ) f₀ + γ f₁)
    /// — less that of their in-situ preloads, plus the change of their springs' energy. `start`:
    /// the points at the step's start, in the same order (after `accept`). Their friction and
    /// dashpot dissipation, never negative, are not added: the estimate errs low.
    pub fn event_gain(&self, start: &[ContactRecord], gamma: f64) -> f64 {
        let events = self.records.iter().zip(start).filter(|(r, _)| r.event());
        events.map(|(r, s)| r.scheme_work(s, gamma) + r.spring_energy() - s.spring_energy()).sum()
    }
}

impl ContactRecord {
    /// The work [J] the step did on the blocks with this point's force, from its record `s` at
    /// the step's start: ((1 − γ) f₀ + γ f₁) · rel less its in-situ preload's (see
    /// [`ContactHistory::event_gain`]).
    pub(super) fn scheme_work(&self, s: &ContactRecord, gamma: f64) -> f64 {
        ((1.0 - gamma) * (s.force - s.preload) + gamma * (self.applied - self.preload)).dot(&self.rel)
    }

    /// Energy in the point's springs if closed [J] (see [`ContactHistory::spring_energy`]).
    fn spring_energy(&self) -> f64 {
        match self.state {
            ContactState::Open => 0.0,
            _ => 0.5 * self.kn * self.gap.min(0.0).powi(2) + 0.5 * self.ks * self.shear0.norm_squared(),
        }
    }

    /// Add `force` on A (and its opposite on B) to the per-cover forces `f` through the
    /// material points' weights.
    pub(super) fn scatter(&self, sys: &System, force: &Vec3, f: &mut [Vec3]) {
        for (mp, sign) in [(&self.a, 1.0), (&self.b, -1.0)] {
            for (&c, w) in sys.covers.elements[mp.element].covers.iter().zip(&mp.weights) {
                f[c] += sign * w * force;
            }
        }
    }
}

/// The covers of two MEs, first then second (the clique a contact between them couples).
pub fn pair_clique(sys: &System, a: usize, b: usize) -> Vec<usize> {
    [sys.covers.elements[a].covers.as_slice(), sys.covers.elements[b].covers.as_slice()].concat()
}
