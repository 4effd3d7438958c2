//! The parts of a run that a single run and a staged one share: its start, stepping to the
//! end, checkpoints, and the summary of a run that could not write its outputs.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::Value;

use crate::checkpoint::{self, Checkpoint};
use crate::error::{Error, Result};
use crate::output::atomic;
use crate::output::progress::{Progress, ProgressMode};
use crate::output::summary::{RunSummary, Status};
use crate::scenario::{AnalysisKind, InitialEquilibrium};
use crate::system::System;
use crate::time::cut;
use crate::time::settle::Settled;
use crate::time::{State, Stepper};

use super::options::StopRequest;
use super::recorder::Recorder;
use super::summary::{summary, Ending};

/// How the stepping ended (errors aside).
pub(super) enum End {
    /// Reached the duration, equilibrium, or (dynamic) `max_steps`.
    Completed(String),
    /// A static run that reached its duration or `max_steps` before equilibrium, or whose
    /// blocks moved beyond `analysis.static_travel_limit`.
    NotConverged(String),
    /// Stopped on request.
    Interrupted(String),
}

/// An error that stopped the run's outputs (a disk full, a directory gone): a `summary.json`
/// saying `failed` with the reason is still written where the disk allows; the error is
/// returned.
pub(super) fn failed(
    sys: &System,
    state: &State,
    stepper: &Stepper,
    rec: &Recorder,
    e: Error,
    t_start: Instant,
) -> Error {
    let message = e.to_string();
    let end = Ending {
        status: Status::Failed,
        message: &message,
        wall: t_start.elapsed().as_secs_f64(),
        initial_equilibrium: None,
        resumed_at: None,
    };
    let _ = write_summary(&rec.out, &summary(sys, state, stepper, rec, &end));
    e
}

/// `summary.json`, written whole or not at all.
pub(super) fn write_summary(out: &Path, summary: &RunSummary) -> Result<()> {
    let text = serde_json::to_string_pretty(summary).expect("the summary serialises");
    atomic::write(&out.join("summary.json"), text.as_bytes())
}

/// Where progress goes: nowhere, a terminal line, or periodic lines in a log.
pub(super) fn progress_mode(wanted: bool) -> ProgressMode {
    match (wanted, std::io::stderr().is_terminal()) {
        (false, _) => ProgressMode::Off,
        (true, true) => ProgressMode::Terminal,
        (true, false) => ProgressMode::Log,
    }
}

/// A fresh run's start: initial accelerations, the initial equilibrium if asked for, the first
/// history row and frame.
pub(super) fn start(
    sys: &System,
    state: &mut State,
    stepper: &mut Stepper,
    rec: &mut Recorder,
    saver: &mut Saver,
) -> Result<()> {
    stepper.initialize(sys, state)?;
    if sys.scenario.analysis.initial_equilibrium != InitialEquilibrium::Off {
        saver.initial_equilibrium = Some(stepper.settle(sys, state)?);
    }
    rec.record(sys, state, true)
}

/// Writes `checkpoint.json`: every `interval` wall seconds during the run and at its end.
pub(super) struct Saver {
    out: PathBuf,
    scenario: Value,
    interval: f64,
    last: Instant,
    pub(super) initial_equilibrium: Option<Settled>,
}

impl Saver {
    pub(super) fn new(out: &Path, scenario: Value, interval: f64) -> Self {
        Self { out: out.to_path_buf(), scenario, interval, last: Instant::now(), initial_equilibrium: None }
    }

    pub(super) fn save(&mut self, state: &State, stepper: &Stepper, rec: &Recorder) -> Result<()> {
        let c = Checkpoint {
            version: checkpoint::VERSION,
            scenario: self.scenario.clone(),
            state: state.clone(),
            stepper: stepper.snapshot(),
            record: rec.snapshot(),
            initial_equilibrium: self.initial_equilibrium.as_ref().map(|s| (s.steps, s.unbalanced)),
            initial_moving: self.initial_equilibrium.as_ref().map(|s| s.moving.clone()).unwrap_or_default(),
            initial_exhausted: self.initial_equilibrium.as_ref().is_some_and(|s| s.exhausted),
        };
        self.last = Instant::now();
        checkpoint::write(&self.out, &c)
    }

    fn due(&self) -> bool {
        self.interval > 0.0 && self.last.elapsed().as_secs_f64() >= self.interval
    }
}

/// Step until the end (`analysis.duration`, or equilibrium if `until_equilibrium`: a static
/// run's, or a dynamic stage's) or a stop request.
pub(super) fn advance(
    sys: &System,
    (whole, stepper): (&mut State, &mut Stepper),
    rec: &mut Recorder,
    progress: &mut Progress,
    stop: Option<&StopRequest>,
    saver: &mut Saver,
    until_equilibrium: bool,
) -> Result<End> {
    let a = &sys.scenario.analysis;
    let end = a.duration;
    loop {
        let state = &whole.motion;
        let unbalanced = rec.last_unbalanced;
        let static_run = a.kind == AnalysisKind::Static;
        if state.time >= end * (1.0 - 1e-12) {
            return Ok(if static_run {
                End::NotConverged(format!(
                    "reached the duration t = {end} s before equilibrium (unbalanced force ratio {unbalanced:.3e} > \
                     equilibrium_tolerance {:.3e})",
                    a.equilibrium_tolerance
                ))
            } else if until_equilibrium {
                End::Completed(format!(
                    "reached t = {end} s before equilibrium (unbalanced force ratio {unbalanced:.3e})"
                ))
            } else {
                End::Completed(format!("reached t = {end} s"))
            });
        }
        if state.step >= a.max_steps {
            let at = format!("stopped at max_steps = {} (t = {} s)", a.max_steps, state.time);
            return Ok(if static_run {
                End::NotConverged(format!("{at} before equilibrium (unbalanced force ratio {unbalanced:.3e})"))
            } else {
                End::Completed(at)
            });
        }
        let cap = (end - whole.motion.time).max(0.0);
        let factorized = stepper.solve_counts().factorizations;
        let mut report = stepper.step(sys, whole, cap)?;
        report.factorizations = stepper.solve_counts().factorizations - factorized;
        let state = &whole.motion;
        rec.cut_log.append(&mut stepper.cuts);
        rec.last_unbalanced = report.unbalanced;
        rec.cuts += report.cuts as u64;
        rec.max_penetration = rec.max_penetration.max(report.max_penetration);
        rec.max_contacts = rec.max_contacts.max(report.contacts);
        rec.open_close += report.open_close as u64;
        rec.diagnostics.push((state.time, state.step, report));
        if state.u.iter().any(|x| !x.iter().all(|c| c.is_finite())) {
            return Err(Error::Diverged {
                step: state.step,
                time: state.time,
                reason: "a displacement is not finite".into(),
            });
        }
        rec.record(sys, whole, false)?;
        progress.step(a, state, &report);
        if until_equilibrium && state.step > 1 && report.unbalanced <= a.equilibrium_tolerance {
            if let Some(m) = not_held(sys, &state.travel()) {
                return Ok(End::NotConverged(format!("{m} (t = {} s, step {})", state.time, state.step)));
            }
            return Ok(End::Completed(format!(
                "equilibrium reached (unbalanced force ratio {:.3e})",
                report.unbalanced
            )));
        }
        if saver.due() {
            saver.save(whole, stepper, rec)?;
        }
        if stop.is_some_and(|s| (s.0)()) {
            return Ok(End::Interrupted(format!(
                "interrupted at step {} (t = {} s); the outputs are valid up to this step",
                state.step, state.time
            )));
        }
    }
}

/// What a static run that stopped with blocks beyond `analysis.static_travel_limit` says (the
/// farthest ten named), or `None` when every block is within it.
fn not_held(sys: &System, u: &[nmm3d_geom::Vec3]) -> Option<String> {
    let gone: Vec<usize> = sys.beyond_travel_limit(u).into_iter().map(|(b, _)| b).collect();
    let limit = sys.scenario.analysis.static_travel_limit;
    (!gone.is_empty()).then(|| {
        format!(
            "not held: {} block(s) moved beyond static_travel_limit = {limit} m from where the \
             analysis started, the others are in equilibrium{}",
            gone.len(),
            cut::named(sys, &gone[..gone.len().min(10)])
        )
    })
}
