//! The façade: build the system, step to the end, record monitors and frames, write outputs.
//! Failures after the model is built end the run with status "failed", a stop request (Ctrl-C)
//! with status "interrupted" after the current step; either way every output stays valid up to
//! the last accepted step, and `summary.json` is always written last.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use serde_json::{json, Map, Value};

use crate::checkpoint::{self, Checkpoint, RecordSnapshot};
use crate::contact::ContactSet;
use crate::error::{Error, Result};
use crate::monitor::MonitorPlan;
use crate::output::progress::{Progress, ProgressMode};
use crate::output::{atomic, checks, cuts, run_dir, tables, vtu};
use crate::scenario::{AnalysisKind, Scenario};
use crate::state::State;
use crate::system::System;
use crate::time::Stepper;

/// How a run ended.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The summary written to `summary.json`.
    pub summary: Value,
    /// Whether the run completed (false: failed or interrupted, see `summary.status`).
    pub completed: bool,
}

/// Asked after every accepted step: `true` stops the run there (status "interrupted").
#[derive(Clone)]
pub struct StopRequest(pub Arc<dyn Fn() -> bool + Send + Sync>);

impl std::fmt::Debug for StopRequest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("StopRequest")
    }
}

/// Options of a run.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Output directory (created if missing).
    pub out: PathBuf,
    /// Report progress on standard error: a live line on a terminal, a periodic line otherwise.
    pub progress: bool,
    /// Checked after every accepted step (the Python binding checks for Ctrl-C).
    pub stop: Option<StopRequest>,
    /// Continue the run whose `checkpoint.json` is in `out` instead of starting afresh.
    pub resume: bool,
}

/// How the stepping ended (errors aside).
enum End {
    /// Reached the duration, equilibrium, or (dynamic) `max_steps`.
    Completed(String),
    /// A static run that reached its duration or `max_steps` before equilibrium.
    NotConverged(String),
    /// Stopped on request.
    Interrupted(String),
}

/// Run a validated scenario (or, with `opts.resume`, continue the run whose checkpoint is in
/// `opts.out`). `Err` only for invalid input or unwritable outputs; a run that fails
/// numerically returns `Ok` with `completed = false`.
pub fn run(scenario: Scenario, label: &str, opts: &RunOptions) -> Result<RunOutcome> {
    let t_start = Instant::now();
    let out = &opts.out;
    // Held to the end of the run: no other run writes here meanwhile.
    let _dir = run_dir::open(out, label, !opts.resume)?;
    let resumed = if opts.resume { Some(checkpoint::read(out, &scenario, label)?) } else { None };
    let resumed_at = resumed.as_ref().map(|c| (c.state.step, c.state.time));
    let mut saver = Saver::new(out, checkpoint::comparable(&scenario), scenario.analysis.checkpoint_interval);
    let sys = System::build(scenario, label)?;
    let monitors = MonitorPlan::all(&sys, label)?;
    let _ = std::fs::remove_file(out.join("summary.json"));
    tables::write_blocks(&sys, out)?;
    let mut rec = Recorder::new(&sys, monitors, out);
    let (mut state, mut stepper) = match resumed {
        Some(c) => {
            rec.restore(c.record);
            saver.initial_equilibrium = c.initial_equilibrium;
            (c.state, Stepper::resume(&sys, c.stepper)?)
        }
        None => {
            let state = State::initial(&sys);
            let stepper = Stepper::new(&sys, &state, label)?;
            (state, stepper)
        }
    };
    let mut progress = Progress::new(progress_mode(opts.progress), &state);
    let started =
        if resumed_at.is_some() { Ok(()) } else { start(&sys, &mut state, &mut stepper, &mut rec, &mut saver) };
    let result = started
        .and_then(|_| advance(&sys, &mut state, &mut stepper, &mut rec, &mut progress, opts.stop.as_ref(), &mut saver));
    rec.cut_log.append(&mut stepper.cuts);
    progress.finish();
    let (status, message) = match result {
        Ok(End::Completed(m)) => ("completed", m),
        Ok(End::Interrupted(m)) => ("interrupted", m),
        Ok(End::NotConverged(m)) => ("not_converged", m),
        Err(e @ (Error::Diverged { .. } | Error::Solver { .. })) => ("failed", e.to_string()),
        Err(e) => return Err(failed(&sys, &state, &stepper, &rec, e, t_start)),
    };
    let written = rec.finish(&sys, &state, stepper.contacts());
    if let Err(e) = written.and_then(|_| if status == "failed" { Ok(()) } else { saver.save(&state, &stepper, &rec) }) {
        return Err(failed(&sys, &state, &stepper, &rec, e, t_start));
    }
    let mut summary = summary(&sys, &state, &stepper, &rec, status, &message, t_start.elapsed().as_secs_f64());
    if let Some(map) = summary.as_object_mut() {
        if let Some((steps, unbalanced)) = saver.initial_equilibrium {
            let _ =
                map.insert("initial_equilibrium".into(), json!({"steps": steps, "unbalanced_force_ratio": unbalanced}));
        }
        if let Some((step, time)) = resumed_at {
            let _ = map.insert("resumed_from".into(), json!({"step": step, "time": time}));
        }
    }
    let text = serde_json::to_string_pretty(&summary).expect("a JSON value serialises");
    atomic::write(&out.join("summary.json"), text.as_bytes())?;
    Ok(RunOutcome { summary, completed: status == "completed" })
}

/// An error that stopped the run's outputs (a disk full, a directory gone): a `summary.json`
/// saying `failed` with the reason is still written where the disk allows; the error is
/// returned.
fn failed(sys: &System, state: &State, stepper: &Stepper, rec: &Recorder, e: Error, t_start: Instant) -> Error {
    let summary = summary(sys, state, stepper, rec, "failed", &e.to_string(), t_start.elapsed().as_secs_f64());
    let text = serde_json::to_string_pretty(&summary).expect("a JSON value serialises");
    let _ = atomic::write(&rec.out.join("summary.json"), text.as_bytes());
    e
}

/// Where progress goes: nowhere, a terminal line, or periodic lines in a log.
fn progress_mode(wanted: bool) -> ProgressMode {
    match (wanted, std::io::stderr().is_terminal()) {
        (false, _) => ProgressMode::Off,
        (true, true) => ProgressMode::Terminal,
        (true, false) => ProgressMode::Log,
    }
}

/// A fresh run's start: initial accelerations, the initial equilibrium if asked for, the first
/// history row and frame.
fn start(sys: &System, state: &mut State, stepper: &mut Stepper, rec: &mut Recorder, saver: &mut Saver) -> Result<()> {
    stepper.initialize(sys, state)?;
    if sys.scenario.analysis.initial_equilibrium {
        saver.initial_equilibrium = Some(stepper.settle(sys, state)?);
    }
    rec.record(sys, state, stepper.contacts(), true)
}

/// Writes `checkpoint.json`: every `interval` wall seconds during the run and at its end.
struct Saver {
    out: PathBuf,
    scenario: Value,
    interval: f64,
    last: Instant,
    initial_equilibrium: Option<(u64, f64)>,
}

impl Saver {
    fn new(out: &Path, scenario: Value, interval: f64) -> Self {
        Self { out: out.to_path_buf(), scenario, interval, last: Instant::now(), initial_equilibrium: None }
    }

    fn save(&mut self, state: &State, stepper: &Stepper, rec: &Recorder) -> Result<()> {
        let c = Checkpoint {
            version: checkpoint::VERSION,
            scenario: self.scenario.clone(),
            state: state.clone(),
            stepper: stepper.snapshot(),
            record: rec.snapshot(),
            initial_equilibrium: self.initial_equilibrium,
        };
        self.last = Instant::now();
        checkpoint::write(&self.out, &c)
    }

    fn due(&self) -> bool {
        self.interval > 0.0 && self.last.elapsed().as_secs_f64() >= self.interval
    }
}

/// Step until the end or a stop request.
fn advance(
    sys: &System,
    state: &mut State,
    stepper: &mut Stepper,
    rec: &mut Recorder,
    progress: &mut Progress,
    stop: Option<&StopRequest>,
    saver: &mut Saver,
) -> Result<End> {
    let a = &sys.scenario.analysis;
    let end = a.duration;
    loop {
        let unbalanced = rec.last_unbalanced;
        let static_run = a.kind == AnalysisKind::Static;
        if state.time >= end * (1.0 - 1e-12) {
            return Ok(if static_run {
                End::NotConverged(format!(
                    "reached the duration t = {end} s before equilibrium (unbalanced force ratio {unbalanced:.3e} > \
                     equilibrium_tolerance {:.3e})",
                    a.equilibrium_tolerance
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
        let cap = (end - state.time).max(0.0);
        let report = stepper.step(sys, state, cap)?;
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
        rec.record(sys, state, stepper.contacts(), false)?;
        progress.step(a, state, &report);
        if a.kind == AnalysisKind::Static && state.step > 1 && report.unbalanced <= a.equilibrium_tolerance {
            return Ok(End::Completed(format!(
                "equilibrium reached (unbalanced force ratio {:.3e})",
                report.unbalanced
            )));
        }
        if saver.due() {
            saver.save(state, stepper, rec)?;
        }
        if stop.is_some_and(|s| (s.0)()) {
            return Ok(End::Interrupted(format!(
                "interrupted at step {} (t = {} s); the outputs are valid up to this step",
                state.step, state.time
            )));
        }
    }
}

/// Records history rows and frames as the run goes.
struct Recorder {
    monitors: Vec<MonitorPlan>,
    history: tables::History,
    diagnostics: Vec<(f64, u64, crate::time::StepReport)>,
    cut_log: Vec<crate::time::Cut>,
    frames: Vec<(f64, String, Option<String>)>,
    out: PathBuf,
    next_history: f64,
    next_frame: f64,
    last_frame_step: Option<u64>,
    last_unbalanced: f64,
    cuts: u64,
    max_penetration: f64,
    max_contacts: usize,
    open_close: u64,
    output_seconds: f64,
    last_history_write: Instant,
}

/// Wall-clock seconds between rewrites of `history.csv` during a run, so long runs can be
/// followed and a crash loses little.
const HISTORY_FLUSH_SECONDS: f64 = 10.0;

impl Recorder {
    fn new(sys: &System, monitors: Vec<MonitorPlan>, out: &Path) -> Self {
        let bolts = sys.scenario.bolt.iter().flat_map(|b| b.columns());
        let base = sys.scenario.seismic.columns();
        let columns = monitors.iter().flat_map(|m| m.columns()).chain(bolts).chain(base).collect();
        Self {
            monitors,
            history: tables::History::new(columns),
            diagnostics: Vec::new(),
            cut_log: Vec::new(),
            frames: Vec::new(),
            out: out.to_path_buf(),
            next_history: 0.0,
            next_frame: 0.0,
            last_frame_step: None,
            last_unbalanced: f64::NAN,
            cuts: 0,
            max_penetration: 0.0,
            max_contacts: 0,
            open_close: 0,
            output_seconds: 0.0,
            last_history_write: Instant::now(),
        }
    }

    fn record(&mut self, sys: &System, state: &State, contacts: Option<&ContactSet>, first: bool) -> Result<()> {
        let t = Instant::now();
        let a = &sys.scenario.analysis;
        let eps = 1e-9 * a.dt;
        if first || a.history_interval.is_none() || state.time + eps >= self.next_history {
            let mut vals: Vec<f64> = self.monitors.iter().flat_map(|m| m.values(sys, state)).collect();
            vals.extend(crate::time::bolt_values(sys, state));
            if sys.scenario.seismic.moves() {
                vals.extend(state.base.iter().flat_map(|v| [v.x, v.y, v.z]));
            }
            self.history.rows.push((state.time, state.step, vals));
            if let Some(h) = a.history_interval {
                self.next_history = (state.time / h + 1e-9).floor() * h + h;
            }
        }
        if first || (a.output_interval > 0.0 && state.time + eps >= self.next_frame) {
            self.frame(sys, state, contacts)?;
            if a.output_interval > 0.0 {
                self.next_frame =
                    (state.time / a.output_interval + 1e-9).floor() * a.output_interval + a.output_interval;
            }
        } else if self.last_history_write.elapsed().as_secs_f64() > HISTORY_FLUSH_SECONDS {
            self.history.write(&self.out)?;
            self.last_history_write = Instant::now();
        }
        self.output_seconds += t.elapsed().as_secs_f64();
        Ok(())
    }

    fn frame(&mut self, sys: &System, state: &State, contacts: Option<&ContactSet>) -> Result<()> {
        let k = self.frames.len();
        let name = format!("frames/blocks_{k:05}.vtu");
        vtu::write_frame(sys, state, &self.out.join(&name))?;
        let contact_name = match contacts {
            Some(c) => {
                let name = format!("frames/contacts_{k:05}.vtu");
                vtu::write_contacts(sys, state, &c.records, &self.out.join(&name))?;
                Some(name)
            }
            None => None,
        };
        self.frames.push((state.time, name, contact_name));
        self.last_frame_step = Some(state.step);
        vtu::write_pvd(&self.out.join("result.pvd"), &self.frames)?;
        self.history.write(&self.out)
    }

    fn finish(&mut self, sys: &System, state: &State, contacts: Option<&ContactSet>) -> Result<()> {
        if self.last_frame_step != Some(state.step) {
            self.frame(sys, state, contacts)?;
        }
        tables::write_diagnostics(&self.out, &self.diagnostics)?;
        cuts::write(&self.out, &self.cut_log)?;
        self.history.write(&self.out)
    }

    fn snapshot(&self) -> RecordSnapshot {
        RecordSnapshot {
            history: self.history.rows.clone(),
            diagnostics: self.diagnostics.clone(),
            cut_log: self.cut_log.clone(),
            frames: self.frames.clone(),
            next_history: self.next_history,
            next_frame: self.next_frame,
            last_frame_step: self.last_frame_step,
            last_unbalanced: Some(self.last_unbalanced).filter(|x| !x.is_nan()),
            cuts: self.cuts,
            max_penetration: self.max_penetration,
            max_contacts: self.max_contacts,
            open_close: self.open_close,
        }
    }

    fn restore(&mut self, s: RecordSnapshot) {
        self.history.rows = s.history;
        self.diagnostics = s.diagnostics;
        self.cut_log = s.cut_log;
        self.frames = s.frames;
        self.next_history = s.next_history;
        self.next_frame = s.next_frame;
        self.last_frame_step = s.last_frame_step;
        self.last_unbalanced = s.last_unbalanced.unwrap_or(f64::NAN);
        self.cuts = s.cuts;
        self.max_penetration = s.max_penetration;
        self.max_contacts = s.max_contacts;
        self.open_close = s.open_close;
    }

    fn final_values(&self) -> Map<String, Value> {
        let mut m = Map::new();
        if let Some((_, _, vals)) = self.history.rows.last() {
            for (c, v) in self.history.columns.iter().zip(vals) {
                let _ = m.insert(c.clone(), json!(v));
            }
        }
        m
    }
}

fn summary(
    sys: &System,
    state: &State,
    stepper: &Stepper,
    rec: &Recorder,
    status: &str,
    message: &str,
    wall: f64,
) -> Value {
    let mut timings = Map::new();
    for (k, v) in &sys.timings {
        let _ = timings.insert(k.clone(), json!(v));
    }
    let (symbolic, numeric) = stepper.solver_timings();
    let _ = timings.insert("assembly".into(), json!(stepper.times.assembly));
    let _ = timings.insert("ordering_symbolic".into(), json!(symbolic));
    let _ = timings.insert("factorization".into(), json!(numeric));
    let _ = timings.insert("krylov".into(), json!(stepper.times.krylov));
    let _ = timings.insert("solve".into(), json!(stepper.times.solve));
    let _ = timings.insert("output".into(), json!(rec.output_seconds));
    let last = rec.final_values();
    if let Some(c) = stepper.contacts() {
        let _ = timings.insert("contact_warning".into(), json!(c.times.warning));
        let _ = timings.insert("contact_detection".into(), json!(c.times.detection));
        let _ = timings.insert("contact_open_close".into(), json!(stepper.times.open_close));
        let _ = timings.insert("contact_pattern".into(), json!(stepper.times.pattern));
    }
    json!({
        "status": status,
        "message": message,
        "steps": state.step,
        "time": state.time,
        "wall_seconds": wall,
        "blocks": sys.geometry.blocks.len(),
        "manifold_elements": sys.covers.elements.len(),
        "physical_covers": sys.covers.covers.len(),
        "dofs": sys.n_eq(),
        "max_penetration": rec.max_penetration,
        "max_contact_points": rec.max_contacts,
        "open_close_iterations": rec.open_close,
        "step_cuts": rec.cuts,
        "penetration_cuts": stepper.penetration_cuts,
        "penalty_raises": stepper.penalty_raises,
        "missed_overlaps": stepper.contacts().map_or(0, |c| c.missed_overlaps),
        "pattern_rebuilds": stepper.pattern_rebuilds(),
        "factor_nonzeros": stepper.factor_nonzeros(),
        "factorizations": stepper.solve_counts().factorizations,
        "krylov_solves": stepper.solve_counts().krylov_solves,
        "krylov_iterations": stepper.solve_counts().krylov_iterations,
        "krylov_failures": stepper.solve_counts().krylov_failures,
        "unbalanced_force_ratio": rec.last_unbalanced,
        "energy": energy_summary(stepper.energy.as_ref(), &rec.diagnostics),
        "step_diagnostics": cuts::summary(sys, &rec.cut_log, &rec.diagnostics),
        "stress_sign": "compression negative",
        "timings": Value::Object(timings),
        "final": Value::Object(last.clone()),
        "checks": checks::checks(&sys.scenario.expect, &last),
    })
}

/// The energy accounts at the end [J], the largest balance error over the run relative to the
/// largest account of the run, and a warning when it exceeds [`ENERGY_ERROR_BOUND`]; `null`
/// for runs without accounts (static).
fn energy_summary(end: Option<&crate::time::Energy>, rows: &[(f64, u64, crate::time::StepReport)]) -> Value {
    let Some(e) = end else { return Value::Null };
    // Relative to the largest account of the whole run: early steps, with little energy yet,
    // would otherwise make round-off look large.
    let scale = rows.iter().map(|(_, _, r)| r.energy.largest()).fold(0.0, f64::max);
    let worst = rows
        .iter()
        .map(|(t, _, r)| (r.energy.error().abs() / scale.max(f64::MIN_POSITIVE), *t))
        .fold((0.0, 0.0), |m, x| if x.0 > m.0 { x } else { m });
    let warning = (worst.0 > ENERGY_ERROR_BOUND).then(|| {
        format!("the energy balance error reached {:.1} % of the largest energy account at t = {:.6} s (bound {:.0} %): look for impacts in diagnostics.csv", 100.0 * worst.0, worst.1, 100.0 * ENERGY_ERROR_BOUND)
    });
    json!({
        "kinetic": e.kinetic, "elastic": e.elastic, "external_work": e.external_work, "contact": e.contact,
        "friction_dissipation": e.friction, "numerical_dissipation": e.numerical,
        "contact_event_dissipation": e.contact_events, "error": e.error(),
        "max_error_ratio": worst.0, "max_error_time": worst.1, "warning": warning,
    })
}

/// Balance error, relative to the largest energy account, beyond which a run is warned about.
const ENERGY_ERROR_BOUND: f64 = 0.05;
