//! The end of a step whose trial is accepted: the step's end equilibrium, the new state, the
//! energy accounts — and, if the step gave the blocks energy at its contacts, the way back to
//! its start with a smaller Δt (`gain`).

use std::time::Instant;

use nmm3d_geom::Vec3;

use super::account::Increment;
use super::base_motion::advance_base;
use super::cut::CutReason;
use super::gain::{self, GainVerdict};
use super::report::StepReport;
use super::state::StepperState;
use super::step_control;
use super::stepper::{dynamic, shaking, Accepted, Finish, GainGuard, StepStart, Stepper};
use super::vectors::kinetic_energy;
use crate::contact::ContactHistory;
use crate::error::Result;
use crate::state::Motion;
use crate::system::System;

impl Stepper {
    /// Take the accepted trial `a` from `start`.
    pub(super) fn finish(
        &mut self,
        sys: &System,
        (state, contact, run): (&mut Motion, &mut Option<ContactHistory>, &mut StepperState),
        start: &StepStart,
        mut a: Accepted,
        guard: &mut GainGuard,
    ) -> Result<Finish> {
        let analysis = &sys.scenario.analysis;
        let (dt, dynamic) = (a.dt, dynamic(sys, run));
        let end_residual = match dynamic && analysis.step_equilibrium_iterations > 0 {
            true => {
                let clock = Instant::now();
                let r1 = self.equilibrate(sys, (state, run), &start.residual, &mut a.d)?;
                self.times.equilibrium += clock.elapsed().as_secs_f64();
                r1
            }
            false => None,
        };
        let d = &a.d;
        // The free-fall bound starts from the first dynamic step's start.
        if dynamic && run.free_fall.is_none() {
            run.free_fall = self.free_fall.start(state);
        }
        // What to go back to if the step gives energy at its contacts (`gain`; only a step
        // where some point opened or closed can).
        let events = contact.as_ref().is_some_and(ContactHistory::any_event);
        let undo = gain::guarded(analysis, guard.armed && dynamic && events).then(|| (state.clone(), run.clone()));
        run.undetected += d.iter().map(|x| x.norm()).fold(0.0, f64::max);
        let kinetic0 = kinetic_energy(sys, &state.v, &start.mv);
        if shaking(sys, run) {
            advance_base(sys, state, dt);
        }
        self.accept(sys, (state, run), d, dt);
        self.update_bolts(sys, state);
        let (contacts, max_penetration, friction, springs, damping) = match contact.as_mut() {
            Some(h) => {
                let friction = h.accept();
                h.finish_damping(sys, d);
                let damping = start.damper.as_ref().map_or(0.0, |f0| h.damping_work(sys, d, f0));
                (h.records.len(), h.max_penetration(), friction, h.spring_energy(), damping)
            }
            None => (0, 0.0, 0.0, 0.0, 0.0),
        };
        let mut contact_end = vec![Vec3::zeros(); d.len()];
        if let Some(h) = contact.as_ref() {
            h.add_end_forces(sys, &mut contact_end);
        }
        // The contacts' work on the blocks by the scheme's rule (the mean of the forces its
        // start and end accelerations carry).
        let contact_work: f64 =
            d.iter().zip(&start.contact).zip(&contact_end).map(|((d, f0), f1)| 0.5 * d.dot(&(f0 + f1))).sum();
        run.contact_end = contact_end;
        state.dt = step_control::next_dt(&step_control::controls(analysis, run.relaxing), dt, a.ratio);
        // M a₀: the scheme's acceleration at the start (the last step's end), except at the
        // first step, where the unbalanced force stands for it.
        let m_a0 = if run.energy.is_some() { &start.ma } else { &start.force };
        let increment = Increment {
            d,
            residual: &start.residual,
            end_residual: end_residual.as_deref(),
            base: (start.base.as_deref(), a.base_end.as_deref()),
            m_a0,
            kinetic0,
            friction,
            damping,
            springs: (start.springs, springs),
            contact_work,
        };
        let energy = self.account(sys, (state, run), &increment);
        if let Some(undo) = undo {
            if let Some(next) =
                self.gain_cut(sys, (state, contact.as_ref(), run), (start, d, dt), energy.largest(), undo, guard)
            {
                return Ok(Finish::Cut(next));
            }
        }
        if let Some(f) = run.free_fall.as_mut().filter(|_| dynamic) {
            self.free_fall.observe(state, f);
        }
        if let Some(h) = contact.as_mut() {
            h.travel.add(sys, d);
        }
        let (ratio, unbalanced, open_close, cuts) = (a.ratio, start.unbalanced, a.iterations, a.cuts);
        Ok(Finish::Taken(StepReport {
            dt,
            cuts,
            ratio,
            unbalanced,
            contacts,
            open_close,
            max_penetration,
            energy,
            factorizations: 0,
        }))
    }

    /// The energy-gain check of a taken step (`gain`): if its contact events gave the blocks
    /// more than the analysis allows, the state goes back to `undo` (the step's start) and the
    /// smaller Δt to try is returned.
    fn gain_cut(
        &mut self,
        sys: &System,
        (state, contact, run): (&mut Motion, Option<&ContactHistory>, &mut StepperState),
        (start, d, dt): (&StepStart, &[Vec3], f64),
        largest: f64,
        (motion, before): (Motion, StepperState),
        guard: &mut GainGuard,
    ) -> Option<f64> {
        let gained = match (contact, start.records.as_ref()) {
            (Some(h), Some(records)) => h.event_gain(records, self.newmark.gamma),
            _ => 0.0,
        };
        let verdict = gain::judge(&sys.scenario.analysis, dt, gained, largest, guard.tried);
        let (GainVerdict::Cut(next) | GainVerdict::Back(next)) = verdict else { return None };
        let why = self.why(sys, (&motion, contact), dt, CutReason::EnergyGain, (d, gained));
        self.cuts.push(why);
        (*state, *run) = (motion, before);
        (guard.tried, guard.armed) = (Some((gained, dt)), matches!(verdict, GainVerdict::Cut(_)));
        Some(next)
    }
}
