//! The trials of a step: the linear solve of a trial and the open–close iteration around it,
//! with the sparsity pattern grown for contacts that close, contact points arriving during a
//! trial, and why a trial is rejected.

use std::time::Instant;

use nmm3d_geom::Vec3;

use super::cut::{self, Cut, CutReason};
use super::stepper::{Stepper, Trial};
use super::vectors::{gather, scatter_into, solver_error};
use crate::contact::{ContactHistory, ContactRecord};
use crate::error::Result;
use crate::solver::Solved;
use crate::state::Motion;
use crate::system::System;

impl Stepper {
    /// Solve, update contact states, repeat until no contact changes state.
    pub(super) fn open_close(
        &mut self,
        sys: &System,
        (state, mut contact): (&Motion, Option<&mut ContactHistory>),
        t: &Trial,
    ) -> Result<(Vec<Vec3>, u32, bool)> {
        let max = sys.scenario.analysis.max_open_close;
        for it in 1..=max {
            let (clock, pattern) = (Instant::now(), self.times.pattern);
            if it > 1 {
                // A point that closed in the last solve may couple a pair the pattern lacks.
                self.ensure_contact_pattern(sys, contact.as_deref(), state.step);
            }
            let d = self.solve_trial(sys, (state, contact.as_deref()), t)?;
            let changes = &mut self.last_changes;
            let (changed, mismatch) = contact.as_deref_mut().map_or((0, 0.0), |h| h.update_states(sys, &d, changes));
            if it > 1 {
                self.times.open_close += clock.elapsed().as_secs_f64() - (self.times.pattern - pattern);
            }
            // Settled when no point changes state, or when the changes move the contact forces
            // by less than the tolerance (points flipping at zero force or at the Coulomb limit
            // — side faces of neighbouring blocks — would otherwise cycle without end).
            let tolerance = t.tolerance;
            if changed == 0 || (tolerance > 0.0 && mismatch <= tolerance) {
                return Ok((d, it, true));
            }
            if it == max {
                return Ok((d, it, false));
            }
        }
        unreachable!("max_open_close ≥ 1")
    }

    /// Make the sparsity pattern hold the couplings of every closed contact point (grown, with
    /// a new symbolic factorisation, when a pair of MEs closes that it lacks).
    pub(super) fn ensure_contact_pattern(&mut self, sys: &System, contact: Option<&ContactHistory>, step: u64) {
        let Some(h) = contact else { return };
        let t = Instant::now();
        if self.pattern.ensure(sys, &h.closed_pairs(), step) {
            self.solver.new_pattern();
        }
        self.times.pattern += t.elapsed().as_secs_f64();
    }

    pub(super) fn solve_trial(
        &mut self,
        sys: &System,
        (state, contact): (&Motion, Option<&ContactHistory>),
        trial: &Trial,
    ) -> Result<Vec<Vec3>> {
        let Trial { residual, mv, ma, k, keep, .. } = *trial;
        let t = Instant::now();
        match self.solver.source_values().filter(|v| keep && v.len() == self.values.len()) {
            Some(kept) => self.values.copy_from_slice(kept),
            None => self.pattern.combine(sys, (1.0, &self.tangent), (k.c0, &sys.mass_values), &mut self.values),
        }
        let mut contact_force = vec![Vec3::zeros(); residual.len()];
        // Only a matrix without contact springs is reused (see `solver::reuse`).
        let nearby = !contact.is_some_and(ContactHistory::any_closed);
        if let Some(h) = contact {
            let pattern = &self.pattern;
            h.assemble(sys, &mut contact_force, pattern.pattern(sys), |pair| pattern.coupling(pair), &mut self.values);
        }
        let rhs_cover: Vec<Vec3> =
            (0..residual.len()).map(|c| residual[c] + k.c1 * mv[c] + k.c2 * ma[c] + contact_force[c]).collect();
        let mut rhs = gather(sys, &rhs_cover);
        let solved = self
            .solver
            .solve(self.pattern.pattern(sys), &self.values, &mut rhs, nearby)
            .map_err(|f| solver_error(sys, state.step + 1, f))?;
        match solved {
            Solved::Factorized => self.times.factorization += t.elapsed().as_secs_f64(),
            Solved::Krylov(_) => self.times.krylov += t.elapsed().as_secs_f64(),
            Solved::OwnFactor => self.times.solve += t.elapsed().as_secs_f64(),
        }
        let t = Instant::now();
        let mut d = vec![Vec3::zeros(); residual.len()];
        scatter_into(sys, &rhs, &mut d);
        self.times.solve += t.elapsed().as_secs_f64();
        Ok(d)
    }

    /// Whether contact points arrived during the trial that ends at `state` + `d` (see
    /// [`crate::contact::ContactSurfaces::arrivals`]): they join the step's start records and
    /// the pattern, and the step is solved again (`detect`: lagged verification is due). So is
    /// it, first, when points that started the step overlapping with no force gave the blocks
    /// more than `push_budget` [J] pushing that out ([`ContactHistory::bound_pushed_overlaps`]).
    /// `carry`: joints carry their force (`contact.carry_joint_force` in a dynamic step).
    pub(super) fn arrivals(
        &mut self,
        sys: &System,
        (state, contact): (&Motion, Option<&mut ContactHistory>),
        d: &[Vec3],
        saved: Option<&mut Vec<ContactRecord>>,
        (push_budget, detect, carry): (f64, bool, bool),
    ) -> bool {
        let (Some(c), Some(h), Some(saved)) = (self.contacts.as_mut(), contact, saved) else { return false };
        if h.bound_pushed_overlaps(saved, self.newmark.gamma, push_budget) > 0 {
            return true;
        }
        if !detect {
            return false;
        }
        let mut end = state.clone();
        end.u.iter_mut().zip(d).for_each(|(u, d)| *u += d);
        let added = c.arrivals(sys, (state, &end), h, carry);
        if added.is_empty() {
            return false;
        }
        saved.extend(added);
        self.ensure_contact_pattern(sys, Some(h), state.step);
        true
    }

    /// Why the trial of `dt` from `state` is rejected, and the blocks responsible; `measure`:
    /// the trial's displacement ratio, or the energy it gained (`CutReason::EnergyGain`).
    pub(super) fn why(
        &self,
        sys: &System,
        (state, contacts): (&Motion, Option<&ContactHistory>),
        dt: f64,
        reason: CutReason,
        (d, measure): (&[Vec3], f64),
    ) -> Cut {
        let (value, blocks) = match reason {
            CutReason::DisplacementRatio => {
                let limit = sys.scenario.analysis.max_displacement_ratio * sys.half_size;
                (measure, cut::moved_too_far(sys, d, limit))
            }
            CutReason::EnergyGain => (measure, cut::impacts(contacts)),
            CutReason::OpenCloseUnsettled => (self.last_changes.len() as f64, cut::unsettled(&self.last_changes)),
            CutReason::Overlap | CutReason::PenaltyRaised => {
                let depth = sys.scenario.contact.max_penetration_ratio * sys.covers.mesh().size;
                let (blocks, deepest) = cut::overlapping(contacts, depth);
                (deepest, blocks)
            }
        };
        Cut { step: state.step + 1, time: state.time, dt, reason, value, blocks }
    }
}
