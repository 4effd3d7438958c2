//! The stepper: one implicit step of the whole system, with step rejection and retry.
//!
//! Per step: assemble the co-rotated tangent and the unbalanced force at the current
//! configuration (once), then for each trial Δt combine with the mass term, factorise (the
//! symbolic analysis is reused), solve, judge the displacement ratio, and either accept
//! (update positions, velocities, accelerations: `finish`) or retry with a smaller Δt.

use std::time::Instant;

use nmm3d_geom::Vec3;

use super::account::{self, Increment};
use super::base_motion::jump_acceleration;
use super::contact_pattern::ContactPattern;
use super::cut::{self, Cut, CutReason};
use super::energy::Energy;
use super::free_fall::FreeFallPlan;
use super::gain;
use super::integrator::{Newmark, StepCoefficients};
use super::kept_tangent::KeptTangent;
use super::report::{PhaseTimes, StepReport};
use super::setup::{contact_params, solver};
use super::state::{State, StepperState};
use super::step_control::{self, Verdict};
use super::vectors::unbalanced_ratio;
use super::vectors::{add_to, gather, lumped_mass, mass_times, scale, scatter_into, solver_error};
use crate::contact::joint_force::Redetection;
use crate::contact::{overlap_problems, ContactHistory, ContactRecord, ContactSurfaces};
use crate::error::{Error, Result};
use crate::scenario::AnalysisKind;
use crate::solver::ReusingSolver;
use crate::state::Motion;
use crate::system::System;

/// Orchestrates steps: the model's contact surfaces, the linear solver with its factor and the
/// matrix pattern (caches), and work buffers. What a run changes is its [`State`].
pub struct Stepper {
    pub(super) solver: ReusingSolver,
    /// The system matrix's pattern (grown by contacts).
    pub(super) pattern: ContactPattern,
    /// The blocks' contact surfaces (`None` without contact or with one block).
    pub(super) contacts: Option<ContactSurfaces>,
    pub(super) newmark: Newmark,
    pub(super) tangent: Vec<f64>,
    /// The elements' tangent kept per block while it does not turn (dynamic analyses).
    pub(super) kept: Option<KeptTangent>,
    pub(super) values: Vec<f64>,
    /// Time per phase so far.
    pub times: PhaseTimes,
    /// Rejected trials not yet taken by the recorder.
    pub cuts: Vec<Cut>,
    /// The loads of the step being taken: dead loads and water pressure at its start [N].
    pub(super) loads: Vec<Vec3>,
    /// Block pairs of the points that changed state in the last open–close iteration.
    pub(super) last_changes: Vec<(usize, usize)>,
    /// Each cover's lumped (row-summed) mass [kg]: the weights of the blocks' rigid fits.
    pub(super) lumped_mass: Vec<f64>,
    /// The model's part of the free-fall bound (`free_fall`).
    pub(super) free_fall: FreeFallPlan,
    /// The displacements `initialize` assembled at and the unbalanced force it found (taken
    /// by the first step, see `assembled`).
    pub(super) fresh: Option<(Vec<Vec3>, Vec<Vec3>)>,
    /// The elements' rotations and forces where the last step's equilibrium left it (taken by
    /// the next step's start).
    pub(super) end_forces: Option<super::end_forces::EndForces>,
}

impl Stepper {
    /// A stepper with faer's sparse Cholesky. The first contact detection runs here, into
    /// `state`'s contact history: blocks overlapping deeper than the overlap tolerance are
    /// invalid input (`label` names it).
    pub fn new(sys: &System, state: &mut State, label: &str) -> Result<Self> {
        let mut stepper = Self::on_model(sys);
        state.contact = stepper.contacts.as_ref().map(|_| ContactHistory::new(contact_params(sys)));
        if let (Some(c), Some(h)) = (stepper.contacts.as_mut(), state.contact.as_mut()) {
            c.detect(sys, &state.motion, h, (true, f64::INFINITY, Redetection::TOTAL));
            let problems = overlap_problems(sys, h, sys.scenario.contact.overlap_tolerance * sys.covers.mesh().size);
            if !problems.is_empty() {
                return Err(Error::Scenario { file: label.to_string(), problems });
            }
        }
        stepper.ensure_contact_pattern(sys, state.contact.as_ref(), 0);
        Ok(stepper)
    }

    /// A stepper on the model `sys`: its contact surfaces, solver and buffers (no pattern
    /// grown, no factor yet).
    pub(super) fn on_model(sys: &System) -> Self {
        let nnz = sys.assembler.pattern.nnz();
        Self {
            solver: solver(sys),
            pattern: ContactPattern::default(),
            contacts: if sys.scenario.contact.enabled { ContactSurfaces::new(sys) } else { None },
            newmark: Newmark::from_analysis(&sys.scenario.analysis),
            tangent: vec![0.0; nnz],
            kept: KeptTangent::new(sys),
            values: vec![0.0; nnz],
            times: PhaseTimes::default(),
            cuts: Vec::new(),
            loads: Vec::new(),
            last_changes: Vec::new(),
            free_fall: FreeFallPlan::new(sys),
            lumped_mass: lumped_mass(sys),
            fresh: None,
            end_forces: None,
        }
    }

    /// The force scale of the unbalanced force ratio, and the initial acceleration
    /// ([`Self::start_acceleration`]).
    pub fn initialize(&mut self, sys: &System, whole: &mut State) -> Result<()> {
        let residual = self.initial_residual(sys, whole);
        whole.stepper.force_scale = scale(sys, &residual).max(scale(sys, &self.loads));
        self.start_acceleration(sys, whole, residual)
    }

    /// The unbalanced force where the run starts, without the contacts, with a shaking base's
    /// force (the first step takes the assembly, `assembled`).
    pub(super) fn initial_residual(&mut self, sys: &System, whole: &mut State) -> Vec<Vec3> {
        let (state, run) = (&mut whole.motion, &whole.stepper);
        let t = Instant::now();
        let mut residual = self.assemble(sys, state, false);
        // The first step takes this assembly (`assembled`): its time is the step's.
        self.times.assembly += t.elapsed().as_secs_f64();
        self.fresh = Some((state.u.clone(), residual.clone()));
        let base = shaking(sys, run).then(|| sys.base_force(sys.scenario.seismic.acceleration_after(state.time)));
        add_to(&mut residual, base.as_deref());
        residual
    }

    /// The acceleration a run starts from, M a₀ = F − F_int(x₀) + f_c(x₀) (`residual`: the
    /// unbalanced force without the contacts), needed when β ≠ ½: the contacts' forces are part
    /// of it — after an initial equilibrium they hold the blocks, and a₀ = g in their place
    /// gave a trapezoidal step's blocks ½ g Δt of velocity from nowhere.
    pub(super) fn start_acceleration(
        &mut self,
        sys: &System,
        whole: &mut State,
        mut residual: Vec<Vec3>,
    ) -> Result<()> {
        if sys.scenario.analysis.kind != AnalysisKind::Dynamic || !self.newmark.uses_acceleration() || sys.n_eq() == 0 {
            return Ok(());
        }
        if let Some(h) = whole.contact.as_ref() {
            // The points as the first step will find them (their gaps at these positions).
            let mut now = h.clone();
            now.refresh(sys, &whole.motion);
            now.add_start_forces(sys, &mut residual);
        }
        self.pattern.combine(sys, (0.0, &self.tangent), (1.0, &sys.mass_values), &mut self.values);
        let mut rhs = gather(sys, &residual);
        self.solver
            .solve_once(self.pattern.pattern(sys), &self.values, &mut rhs)
            .map_err(|f| solver_error(sys, 0, f))?;
        scatter_into(sys, &rhs, &mut whole.motion.a);
        Ok(())
    }

    /// One accepted step (possibly after cuts). `dt_cap` bounds the step (output times, end).
    pub fn step(&mut self, sys: &System, whole: &mut State, dt_cap: f64) -> Result<StepReport> {
        let State { motion: state, contact, stepper: run } = whole;
        // The dashpots' part of the forces the start carries, before a detection replaces points.
        let damper_start = contact.as_ref().and_then(|h| h.damper_forces(sys));
        // Contacts first: a new contact may change the pattern the tangent is assembled into.
        if let (Some(c), Some(h)) = (self.contacts.as_mut(), contact.as_mut()) {
            // Since the last detection no point has moved by the contact tolerance, so no pair
            // apart by more than the detection margin (twice the tolerance) can touch: the same
            // points are kept (`refresh`). Detecting again would only make points at the edge of
            // a face come and go with round-off, each arrival inheriting its neighbour's springs
            // — energy from nowhere, and a static iteration that never settles.
            if run.undetected < h.params.tolerance {
                h.refresh(sys, state);
            } else {
                let reach = Self::reach(sys, (state, run), state.dt.min(dt_cap));
                // A joint keeps its force, and while settling its area; a static analysis's only
                // beyond a slack (its answer is the total force's); the lock's nothing.
                let no_slack = run.relaxing || dynamic(sys, run);
                let slack = if no_slack { Some(0.0) } else { (!run.settling()).then_some(h.params.static_slack) };
                let carry_force = slack.filter(|_| h.params.carry_joint_force);
                c.detect(sys, state, h, (false, reach, Redetection { keep_area: run.relaxing, carry_force }));
                run.undetected = 0.0;
            }
        }
        self.ensure_contact_pattern(sys, contact.as_ref(), state.step);
        self.solver.moved(&|| super::vectors::node_positions(sys, state));
        let t = Instant::now();
        let (residual, keep) = self.start_residual(sys, state, run, contact.is_some());
        // The unbalanced force at the start, contacts included: M a₀ of a dynamic step.
        let mut start_force = residual.clone();
        let seismic = &sys.scenario.seismic;
        let base_start = shaking(sys, run).then(|| sys.base_force(seismic.acceleration_after(state.time)));
        add_to(&mut start_force, base_start.as_deref());
        let mut start_contact = vec![Vec3::zeros(); residual.len()];
        if let Some(h) = contact.as_ref() {
            h.add_start_forces(sys, &mut start_contact);
        }
        add_to(&mut start_force, Some(&start_contact));
        // The contact forces the start acceleration carries: the last step's end forces, except
        // at the first step (see `m_a0` in `finish`).
        let contact_start = if run.energy.is_some() && run.contact_end.len() == residual.len() {
            std::mem::take(&mut run.contact_end)
        } else {
            start_contact
        };
        let unbalanced = unbalanced_ratio(sys, run, &super::held::of_held(sys, &state.travel(), &start_force));
        let records = contact.as_ref().map(|h| h.records.clone());
        // The springs' energy at the start: the first step's is part of the initial energy
        // (springs loaded by the initial equilibrium or by overlapping input).
        let springs = contact.as_ref().map_or(0.0, ContactHistory::spring_energy);
        self.times.assembly += t.elapsed().as_secs_f64();
        let analysis = step_control::controls(&sys.scenario.analysis, run.relaxing);
        let mut dt = state.dt.min(dt_cap);
        if shaking(sys, run) {
            // No step straddles a jump of the base acceleration; the one that starts at a jump
            // starts from the acceleration after it.
            dt = seismic.next_jump(state.time).map_or(dt, |b| dt.min(b - state.time));
            jump_acceleration(sys, state);
        }
        if Self::balanced_static(sys, run, contact.is_some(), state.step, unbalanced) {
            // Converged before this step's solve: the step is taken with no increment.
            self.accept(sys, (state, run), &vec![Vec3::zeros(); residual.len()], dt);
            return Ok(StepReport { dt, unbalanced, ..StepReport::default() });
        }
        // M v and M a of the start (after a jump of the base: what `accept` goes on from).
        let (mv, ma) = (mass_times(sys, &state.v), mass_times(sys, &state.a));
        let mut start = StepStart {
            residual,
            force: start_force,
            contact: contact_start,
            base: base_start,
            damper: damper_start,
            mv,
            ma,
            springs,
            unbalanced,
            records,
        };
        let (mut cuts, mut trials, mut arrivals) = (0, 0, 0);
        let mut guard = GainGuard { tried: None, armed: true };
        let dynamic = dynamic(sys, run);
        let push_budget = gain::push_budget(&analysis, dynamic, run.energy.as_ref());
        loop {
            let k = if run.inertia {
                self.newmark.coefficients(dt)
            } else {
                StepCoefficients { c0: 0.0, c1: 0.0, c2: 0.0 }
            };
            // Every trial starts from the step's start states (the first one has them already).
            trials += 1;
            if let (Some(h), Some(saved), true) = (contact.as_mut(), start.records.as_ref(), trials > 1) {
                h.records = saved.clone();
            }
            // The dashpots act on velocities: only in a dynamic step, with this trial's Δt.
            if let Some(h) = contact.as_mut() {
                match dynamic {
                    true => h.prepare_damping(sys, state, (self.newmark.beta, self.newmark.gamma), dt),
                    false => h.clear_damping(),
                }
            }
            // The loads at the end of the step (implicit): a moving base's force just before
            // t + Δt (a pulse ending there still acts over the step).
            let base_end = shaking(sys, run).then(|| sys.base_force(seismic.acceleration_before(state.time + dt)));
            let moved;
            let trial_residual = match &base_end {
                Some(f) => {
                    moved = start.residual.iter().zip(f).map(|(r, f)| r + f).collect::<Vec<_>>();
                    &moved
                }
                None => &start.residual,
            };
            let tolerance = analysis.settle_tolerance();
            let trial = Trial { residual: trial_residual, mv: &start.mv, ma: &start.ma, k, keep, tolerance };
            let (mut d, iterations, settled) = self.open_close(sys, (state, contact.as_mut()), &trial)?;
            super::held::pin(sys, &state.travel(), &mut d);
            let dmax = d.iter().map(|x| x.norm()).fold(0.0, f64::max);
            // Lagged verification, where the blocks may have moved into a contact unseen (not
            // while nothing has moved by the contact tolerance since the last detection); before
            // it, overlaps the step started with and pushed out with energy are bounded.
            let moved = contact.as_ref().is_some_and(|h| run.undetected + dmax >= h.params.tolerance);
            let detect = moved && arrivals < sys.scenario.contact.arrival_rounds;
            let carry = contact.as_ref().is_some_and(|h| h.params.carry_joint_force) && dynamic;
            if settled
                && self.arrivals(
                    sys,
                    (state, contact.as_mut()),
                    &d,
                    start.records.as_mut(),
                    (push_budget, detect, carry),
                )
            {
                arrivals += 1;
                continue;
            }
            let ratio = dmax / (analysis.max_displacement_ratio * sys.half_size);
            // Contacts overlapping beyond the allowed depth: the penalty is too soft for the
            // loads — raise it (×10, at most three times in a run) and repeat the step; after
            // that, cut the step like an unsettled one (an impact in smaller steps overlaps less).
            let too_deep = contact.as_ref().is_some_and(|h| {
                h.overlap_growing_beyond(sys.scenario.contact.max_penetration_ratio * sys.covers.mesh().size)
            });
            let raise = sys.scenario.contact.penalty_raise;
            if too_deep && settled && run.penalty_raises < sys.scenario.contact.max_penalty_raises {
                run.penalty_raises += 1;
                let why = self.why(sys, (state, contact.as_ref()), dt, CutReason::PenaltyRaised, (&d, ratio));
                self.cuts.push(why);
                if let (Some(h), Some(saved)) = (contact.as_mut(), start.records.as_mut()) {
                    h.stiffen(raise);
                    saved.iter_mut().for_each(|r| r.stiffen(raise));
                }
                continue;
            }
            let verdict = if settled && !too_deep {
                step_control::judge(&analysis, dt, ratio)
            } else {
                step_control::judge_unsettled(&analysis, dt)
            };
            if too_deep && settled && matches!(verdict, Verdict::Retry(_)) {
                run.penetration_cuts += 1;
            }
            if !matches!(verdict, Verdict::Accept) {
                let why = self.why(sys, (state, contact.as_ref()), dt, CutReason::of(settled, too_deep), (&d, ratio));
                self.cuts.push(why);
            }
            match verdict {
                Verdict::Accept => {
                    let a = Accepted { d, dt, ratio, iterations, base_end, cuts };
                    match self.finish(sys, (state, contact, run), &start, a, &mut guard)? {
                        Finish::Taken(report) => return Ok(report),
                        Finish::Cut(next) => (dt, cuts) = (next, cuts + 1),
                    }
                }
                Verdict::Retry(smaller) => {
                    dt = smaller;
                    cuts += 1;
                }
                Verdict::Diverged => {
                    let why = (CutReason::of(settled, too_deep), ratio);
                    return Err(cut::diverged(sys, state, dt, why, self.cuts.last()));
                }
            }
        }
    }

    /// Add an accepted step to the energy accounts (dynamic runs outside the initial
    /// equilibrium) and return them.
    pub(super) fn account(&self, sys: &System, (state, run): (&Motion, &mut StepperState), s: &Increment) -> Energy {
        if run.settling() || sys.scenario.analysis.kind == AnalysisKind::Static {
            return Energy::default();
        }
        account::add_step(sys, state, s, (&self.loads, &self.tangent), &mut run.energy)
    }

    pub(super) fn accept(&self, sys: &System, (state, run): (&mut Motion, &StepperState), d: &[Vec3], dt: f64) {
        let k = self.newmark.coefficients(dt);
        let g = self.newmark.gamma;
        let is_static = run.settling() || sys.scenario.analysis.kind == AnalysisKind::Static;
        for c in 0..d.len() {
            if !sys.dofs.moves(c) {
                continue;
            }
            let a_new = k.c0 * d[c] - k.c1 * state.v[c] - k.c2 * state.a[c];
            let v_new = state.v[c] + dt * ((1.0 - g) * state.a[c] + g * a_new);
            state.u[c] += d[c];
            (state.v[c], state.a[c]) = if is_static { (Vec3::zeros(), Vec3::zeros()) } else { (v_new, a_new) };
        }
        state.time += dt;
        state.step += 1;
    }
}

/// What every trial of a step starts from.
pub(super) struct StepStart {
    /// The unbalanced force at the start, without contacts or a moving base.
    pub(super) residual: Vec<Vec3>,
    /// The unbalanced force at the start with the contacts and the base: M a₀ of a first step.
    pub(super) force: Vec<Vec3>,
    /// The contact forces the start acceleration carries.
    pub(super) contact: Vec<Vec3>,
    /// A moving base's force at the start.
    pub(super) base: Option<Vec<Vec3>>,
    /// The dashpots' part of the start forces.
    pub(super) damper: Option<Vec<Vec3>>,
    /// M v of the start.
    pub(super) mv: Vec<Vec3>,
    /// M a of the start.
    pub(super) ma: Vec<Vec3>,
    /// The springs' energy at the start [J].
    pub(super) springs: f64,
    /// Unbalanced force ratio at the start.
    pub(super) unbalanced: f64,
    /// The contact records at the start (every trial starts from them).
    pub(super) records: Option<Vec<ContactRecord>>,
}

/// The accepted trial of a step (taken by `finish`).
pub(super) struct Accepted {
    /// The increment (the end equilibrium corrects it).
    pub(super) d: Vec<Vec3>,
    pub(super) dt: f64,
    /// Its displacement ratio.
    pub(super) ratio: f64,
    /// Its open–close iterations.
    pub(super) iterations: u32,
    /// A moving base's force at the end.
    pub(super) base_end: Option<Vec<Vec3>>,
    /// Rejected trials before it.
    pub(super) cuts: u32,
}

/// The energy-gain check across a step's trials: the energy the last trial gave at its contacts
/// and its Δt, if it was cut for it, and whether the step may still be cut for it (`gain`).
pub(super) struct GainGuard {
    pub(super) tried: Option<(f64, f64)>,
    pub(super) armed: bool,
}

/// How an accepted trial ended.
pub(super) enum Finish {
    /// The step is taken.
    Taken(StepReport),
    /// It gave energy at its contacts: back to the start, again with this Δt.
    Cut(f64),
}

/// What every trial of a step solves with: the unbalanced force at the start, M v and M a of
/// the start, and the Newmark coefficients of the trial's Δt.
#[derive(Clone, Copy)]
pub(super) struct Trial<'a> {
    pub(super) residual: &'a [Vec3],
    pub(super) mv: &'a [Vec3],
    pub(super) ma: &'a [Vec3],
    pub(super) k: StepCoefficients,
    /// Solve with the matrix of the solver's factor, not the step's tangent (see `newton`).
    pub(super) keep: bool,
    /// The open–close iteration's tolerance ([`crate::scenario::Analysis::settle_tolerance`]).
    pub(super) tolerance: f64,
}

/// Whether a step follows motion in time: inertia on, outside the initial equilibrium, in a
/// dynamic analysis (the dashpots, the energy-gain check and the end equilibrium act only then).
pub(super) fn dynamic(sys: &System, run: &StepperState) -> bool {
    run.inertia && !run.settling() && sys.scenario.analysis.kind != AnalysisKind::Static
}

/// Whether the base shakes now (not while the initial equilibrium settles: the shaking starts
/// after it).
pub(super) fn shaking(sys: &System, run: &StepperState) -> bool {
    !run.settling() && sys.scenario.seismic.moves()
}
