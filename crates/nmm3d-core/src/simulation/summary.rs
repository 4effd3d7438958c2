//! The run summary (`summary.json`): counts, timings per phase, energy accounts and the final
//! monitored values with their checks.

use std::collections::BTreeMap;

use super::recorder::Recorder;
use crate::output::summary::{EnergySummary, FreeFallSummary, InitialEquilibrium, ResumedFrom, RunSummary, Status};
use crate::output::{checks, cuts};
use crate::system::System;
use crate::time::free_fall::{gravity_only, FreeFall};
use crate::time::settle::{block_name, Settled};
use crate::time::{State, Stepper};

/// What the run adds to the summary beyond its own state: how it ended, how long it took, how
/// it started.
pub(super) struct Ending<'a> {
    pub status: Status,
    pub message: &'a str,
    pub wall: f64,
    /// How the initial equilibrium ended, when one was solved.
    pub initial_equilibrium: Option<Settled>,
    /// Step and time of the checkpoint a resumed run continued from.
    pub resumed_at: Option<(u64, f64)>,
}

pub(super) fn summary(sys: &System, whole: &State, stepper: &Stepper, rec: &Recorder, end: &Ending) -> RunSummary {
    let (state, run) = (&whole.motion, &whole.stepper);
    let last = rec.final_values();
    let counts = stepper.solve_counts();
    let not_held = not_held(sys, whole, rec, end.status);
    let cause = deep_overlap(sys, rec.max_penetration);
    let single = stepper.solver().single_precision();
    RunSummary {
        status: end.status,
        message: end.message.to_string(),
        steps: state.step,
        time: state.time,
        wall_seconds: end.wall,
        blocks: sys.geometry.blocks.len(),
        manifold_elements: sys.covers.elements.len(),
        physical_covers: sys.covers.covers.len(),
        dofs: sys.n_eq(),
        max_penetration: rec.max_penetration,
        max_contact_points: rec.max_contacts,
        open_close_iterations: rec.open_close,
        step_cuts: rec.cuts,
        penetration_cuts: run.penetration_cuts,
        penalty_raises: run.penalty_raises,
        equilibrium_iterations: run.equilibrium_iterations,
        missed_overlaps: whole.contact.as_ref().map_or(0, |c| c.missed_overlaps),
        carried_joint_forces: whole.contact.as_ref().map_or(0, |c| c.carried_forces),
        pattern_rebuilds: stepper.pattern_rebuilds(),
        factor_nonzeros: stepper.factor_nonzeros(),
        factorizations: counts.factorizations,
        krylov_solves: counts.krylov_solves,
        krylov_iterations: counts.krylov_iterations,
        krylov_failures: counts.krylov_failures,
        unbalanced_force_ratio: Some(rec.last_unbalanced).filter(|r| r.is_finite()),
        energy: energy_summary(run.energy.as_ref(), &rec.diagnostics, &cause),
        step_diagnostics: cuts::summary(sys, &rec.cut_log, &rec.diagnostics),
        stress_sign: "compression negative".into(),
        timings: timings(sys, stepper, rec),
        checks: checks::checks(&sys.scenario.expect, &last),
        final_values: last,
        initial_equilibrium: end.initial_equilibrium.as_ref().map(|s| initial_equilibrium(sys, s)),
        resumed_from: end.resumed_at.map(|(step, time)| ResumedFrom { step, time }),
        stages: Vec::new(),
        linear_solver: stepper.solver().name().into(),
        multigrid_iterations: stepper.solver().inner_iterations(),
        single_precision_factorizations: single.0,
        refinement_iterations: single.1,
        not_held_monitors: (rec.monitors.iter())
            .filter(|m| not_held.contains(&m.block))
            .map(|m| m.name.clone())
            .collect(),
        not_held,
        free_fall: run.free_fall.as_ref().map(|f| free_fall(sys, f, &cause)),
        patterns_adopted: counts.patterns_adopted,
    }
}

/// The run's free-fall bound, with a warning when a block went past it and gravity alone
/// drives the run ([`gravity_only`]); `cause`: [`deep_overlap`]'s clause.
fn free_fall(sys: &System, f: &FreeFall, cause: &str) -> FreeFallSummary {
    let body = sys.scenario.body[sys.geometry.blocks[f.block].body].name.clone();
    let past = f.ratio > 1.0 && gravity_only(&sys.scenario);
    let warning = past.then(|| {
        format!("block {} of body '{body}' moved at {:.3} m/s at t = {:.6} s, {:.2} times as fast as a free fall from the top of the moving blocks to it ({:.3} m/s): unless a heavier block struck it, look for energy from nowhere at its contacts (diagnostics.csv, cuts.csv){cause}", f.block, f.speed, f.time, f.ratio, f.bound)
    });
    FreeFallSummary { max_ratio: f.ratio, block: f.block, body, time: f.time, speed: f.speed, bound: f.bound, warning }
}

/// A clause for the warnings of energy from nowhere when joints of their own stiffness let the
/// blocks overlap by more than [`DEEP_OVERLAP`] of the cover size: on 10 MPa/m joints blocks
/// that meet at metres per second pass 10–50 cm into each other, and a detection that finds such
/// an overlap again sets spring energy that was not there (`docs/theory/contact.md`, *Turned
/// faces in a run*). Empty otherwise.
fn deep_overlap(sys: &System, max_penetration: f64) -> String {
    let size = sys.covers.mesh().size;
    let joints = sys.scenario.joint.iter().any(|j| j.stiffness().is_some());
    if !joints || max_penetration <= DEEP_OVERLAP * size {
        return String::new();
    }
    format!("; the blocks overlapped by up to {max_penetration:.3} m ({:.0} % of the cover size) on joints of their own stiffness: springs that soft let blocks that strike each other pass far into each other, and contacts that deep are no joint's — the joint stiffness is a closed joint's, too soft for impacts (docs/theory/contact.md, a joint's force carried across a detection)", 100.0 * max_penetration / size)
}

/// Overlap, as a fraction of the cover size, beyond which the warnings of energy from nowhere
/// name the joints' own stiffness as the likely cause.
const DEEP_OVERLAP: f64 = 0.1;

/// The blocks beyond `analysis.static_travel_limit` of a static run that stopped with the
/// others in equilibrium (`System::beyond_travel_limit`); none otherwise.
fn not_held(sys: &System, whole: &State, rec: &Recorder, status: Status) -> Vec<usize> {
    let settled = rec.last_unbalanced <= sys.scenario.analysis.equilibrium_tolerance;
    if status != Status::NotConverged || !settled {
        return Vec::new();
    }
    sys.beyond_travel_limit(&whole.motion.travel()).into_iter().map(|(b, _)| b).collect()
}

/// Seconds per phase: those of building the system, then of the run.
fn timings(sys: &System, stepper: &Stepper, rec: &Recorder) -> BTreeMap<String, f64> {
    let mut t: BTreeMap<String, f64> = sys.timings.iter().cloned().collect();
    let (symbolic, numeric) = stepper.solver_timings();
    let mut put = |k: &str, v: f64| {
        let _ = t.insert(k.into(), v);
    };
    put("assembly", stepper.times.assembly);
    put("ordering_symbolic", symbolic);
    put("factorization", numeric);
    put("krylov", stepper.times.krylov);
    put("solve", stepper.times.solve);
    put("step_equilibrium", stepper.times.equilibrium);
    put("output", rec.output_seconds);
    if let Some(c) = stepper.contacts() {
        put("contact_warning", c.times.warning);
        put("contact_detection", c.times.detection);
        put("contact_open_close", stepper.times.open_close);
        put("contact_pattern", stepper.times.pattern);
    }
    t
}

/// The initial equilibrium in the summary; unconverged, it names the blocks nothing holds.
fn initial_equilibrium(sys: &System, s: &Settled) -> InitialEquilibrium {
    let converged = s.converged(sys);
    let warning = (!converged).then(|| {
        // Named on the model that settled; after a resume, on this one (its own blocks only).
        let named = |&b: &usize| (b < sys.geometry.blocks.len()).then(|| block_name(sys, b));
        let names: Vec<String> = match s.names.is_empty() {
            false => s.names.iter().take(10).cloned().collect(),
            true => s.moving.iter().take(10).filter_map(named).collect(),
        };
        let more = s.moving.len().saturating_sub(10);
        format!(
            "initial equilibrium not reached after {} steps (unbalanced force ratio {:.2e} > \
             analysis.equilibrium_tolerance {:.1e}); still moving at its last step, held by nothing or \
             hardly: {}{}; the run starts from there{}",
            s.steps,
            s.unbalanced,
            sys.scenario.analysis.equilibrium_tolerance,
            if names.is_empty() { "none".into() } else { names.join(", ") },
            if more > 0 { format!(" and {more} more") } else { String::new() },
            if s.exhausted { hint(sys.scenario.analysis.initial_equilibrium) } else { "" },
        )
    });
    InitialEquilibrium { steps: s.steps, unbalanced_force_ratio: s.unbalanced, converged, warning }
}

/// What to try when an initial equilibrium ran out of steps (`docs/theory/contact.md`,
/// *Initial equilibrium*).
fn hint(method: crate::scenario::InitialEquilibrium) -> &'static str {
    match method {
        crate::scenario::InitialEquilibrium::Frictional => {
            " (try more analysis.max_settle_steps — the thesis tunnel on 1 MPa/m joints takes 37–65 — or a smaller analysis.settle_dt)"
        }
        _ => {
            " (on joints of a given stiffness, analysis.initial_equilibrium = \"frictional\" lets them close as \
             the rock settles)"
        }
    }
}

/// The energy accounts at the end [J], the largest balance error and the largest gain
/// ([`crate::time::Energy::gain`]) over the run relative to the largest account of the run,
/// and a warning when either exceeds [`ENERGY_ERROR_BOUND`]; `None` for runs without accounts
/// (static).
fn energy_summary(
    end: Option<&crate::time::Energy>,
    rows: &[(f64, u64, crate::time::StepReport)],
    cause: &str,
) -> Option<EnergySummary> {
    let e = end?;
    // Relative to the largest account of the whole run: early steps, with little energy yet,
    // would otherwise make round-off look large.
    let scale = rows.iter().map(|(_, _, r)| r.energy.largest()).fold(0.0, f64::max);
    let largest_over_run = |of: fn(&crate::time::Energy) -> f64| {
        rows.iter().map(|(t, _, r)| (of(&r.energy) / scale.max(f64::MIN_POSITIVE), *t)).fold((0.0, 0.0), |m, x| {
            if x.0 > m.0 {
                x
            } else {
                m
            }
        })
    };
    let worst = largest_over_run(|e| e.error().abs());
    let gain = largest_over_run(crate::time::Energy::gain);
    let bound = 100.0 * ENERGY_ERROR_BOUND;
    let warnings: Vec<String> = [
        (worst.0 > ENERGY_ERROR_BOUND).then(|| {
            format!("the energy balance error reached {:.1} % of the largest energy account at t = {:.6} s (bound {bound:.0} %): look for impacts in diagnostics.csv", 100.0 * worst.0, worst.1)
        }),
        (gain.0 > ENERGY_ERROR_BOUND).then(|| {
            format!("the blocks held {:.1} % of the largest energy account more kinetic and strain energy than the loads and the start gave them, at t = {:.6} s (bound {bound:.0} %): energy from nowhere, booked as negative dissipation ({}; diagnostics.csv) — an undamped integrator on blocks that bounce on their joints: damp the contacts (contact.damping_ratio) or keep the default integrator{cause}", 100.0 * gain.0, gain.1, negative_accounts(e))
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    let warning = (!warnings.is_empty()).then(|| warnings.join("; "));
    Some(EnergySummary {
        kinetic: e.kinetic,
        elastic: e.elastic,
        external_work: e.external_work,
        contact: e.contact,
        friction_dissipation: e.friction,
        numerical_dissipation: e.numerical,
        contact_event_dissipation: e.contact_events,
        error: e.error(),
        max_error_ratio: worst.0,
        max_error_time: worst.1,
        warning,
        damping_dissipation: e.damping,
        max_gain_ratio: gain.0,
        max_gain_time: gain.1,
    })
}

/// The dissipation accounts that ended negative, named with their values.
fn negative_accounts(e: &crate::time::Energy) -> String {
    let named = [("numerical_dissipation", e.numerical), ("contact_event_dissipation", e.contact_events)];
    let negative: Vec<String> =
        named.iter().filter(|(_, v)| *v < 0.0).map(|(name, v)| format!("{name} = {v:.4} J at the end")).collect();
    if negative.is_empty() {
        "none negative at the end".into()
    } else {
        negative.join(", ")
    }
}

/// Balance error, relative to the largest energy account, beyond which a run is warned about.
const ENERGY_ERROR_BOUND: f64 = 0.05;
