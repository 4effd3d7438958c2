//! A staged analysis (`[[stage]]`): one rock mass cut once, its excavations' plugs kept as
//! blocks until their stage; each stage builds the model of the blocks that are left (one
//! cover mesh for all), carries the state onto it (`time::carry`), and runs for its duration or
//! to equilibrium. One history, one series of frames and one summary for the whole run; each
//! stage is a row of `stages.csv` and of the summary's `stages`.

use std::fmt::Write as _;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::model::Geometry;
use crate::monitor::MonitorPlan;
use crate::output::progress::Progress;
use crate::output::summary::{StageSummary, Status};
use crate::output::{atomic, run_dir, tables};
use crate::scenario::{AnalysisKind, Scenario};
use crate::system::System;
use crate::time::carry::carry;
use crate::time::{State, Stepper};

use super::advance::{advance, failed, progress_mode, start, write_summary, End, Saver};
use super::options::{RunOptions, RunOutcome};
use super::recorder::Recorder;
use super::summary::{summary, Ending};

/// Each stage's scenario, its end time [s] in `analysis.duration`.
pub(super) fn stage_scenarios(s: &Scenario, label: &str) -> Result<Vec<Scenario>> {
    let mut end = 0.0;
    (0..s.stage.len())
        .map(|k| {
            let mut at = s.at_stage(k).map_err(|(path, reason)| Error::input(label, path, reason))?;
            end += s.stage[k].duration;
            at.analysis.duration = end;
            Ok(at)
        })
        .collect()
}

/// Old → new block index from the stage before (`before`: whole rock mass → its blocks) to this
/// one (`now`).
fn link(before: &[Option<usize>], now: &[Option<usize>]) -> Vec<Option<usize>> {
    let n = before.iter().flatten().count();
    let mut out = vec![None; n];
    for (b, n) in before.iter().zip(now) {
        if let Some(b) = b {
            out[*b] = *n;
        }
    }
    out
}

/// Run a validated staged scenario into `opts.out`.
pub(super) fn run(scenario: Scenario, label: &str, opts: &RunOptions) -> Result<RunOutcome> {
    if opts.resume {
        return Err(Error::input(label, "stage", "a staged analysis cannot be resumed; run it again"));
    }
    let t_start = Instant::now();
    let out = &opts.out;
    let _dir = run_dir::open(out, label, true)?;
    let scenarios = stage_scenarios(&scenario, label)?;
    let full = Geometry::staged(&scenario);
    full.require_blocks(label)?;
    let extent = full.aabb().extent();
    let mut saver = Saver::new(out, serde_json::Value::Null, 0.0);
    let _ = std::fs::remove_file(out.join("summary.json"));
    tables::write_block_rows(&scenario, &full, out)?;

    let mut rows: Vec<StageSummary> = Vec::new();
    let mut before: Vec<Option<usize>> = Vec::new();
    let mut current: Option<(System, State, Stepper, Recorder)> = None;
    let mut progress = None;
    let mut last = (Status::Completed, String::new());
    for (k, at) in scenarios.iter().enumerate() {
        let t_stage = Instant::now();
        let (geometry, map) = full.without(&scenario.open_excavations(k));
        let built = System::on_geometry(at.clone(), geometry, extent, label)
            .and_then(|sys| MonitorPlan::all(&sys, label).map(|m| (sys, m)));
        let (sys, monitors) = match (built, current.as_ref()) {
            (Ok(b), _) => b,
            // A later stage's model that cannot be built (a bolt in no rock): the run so far stands.
            (Err(e), Some((old, state, stepper, rec))) => return Err(failed(old, state, stepper, rec, e, t_start)),
            (Err(e), None) => return Err(e),
        };
        let (mut state, mut stepper, mut rec, started) = match current.take() {
            Some((old, state, _, mut rec)) => {
                let state = carry(&old, &sys, &link(&before, &map), &state);
                drop(old);
                rec.restage(&sys, monitors);
                let stepper = Stepper::carried(&sys, &state);
                (state, stepper, rec, Ok(()))
            }
            None => {
                let mut state = State::initial(&sys);
                let mut stepper = Stepper::new(&sys, &mut state, label)?;
                let mut rec = Recorder::new(&sys, monitors.clone(), out).for_stages(&scenarios);
                rec.restage(&sys, monitors);
                let started = start(&sys, &mut state, &mut stepper, &mut rec, &mut saver);
                (state, stepper, rec, started)
            }
        };
        let progress = progress.get_or_insert_with(|| Progress::new(progress_mode(opts.progress), &state.motion));
        let (t0, s0) = (state.motion.time, state.motion.step);
        let until = at.analysis.kind == AnalysisKind::Static || scenario.stage[k].equilibrium;
        let stop = opts.stop.as_ref();
        let result = started
            .and_then(|_| advance(&sys, (&mut state, &mut stepper), &mut rec, progress, stop, &mut saver, until));
        rec.cut_log.append(&mut stepper.cuts);
        last = match result {
            Ok(End::Completed(m)) => (Status::Completed, m),
            Ok(End::Interrupted(m)) => (Status::Interrupted, m),
            Ok(End::NotConverged(m)) => (Status::NotConverged, m),
            Err(e @ (Error::Diverged { .. } | Error::Solver { .. })) => (Status::Failed, e.to_string()),
            Err(e) => return Err(failed(&sys, &state, &stepper, &rec, e, t_start)),
        };
        // The stage's last state is a frame, before the next stage changes the model.
        if let Err(e) = rec.finish(&sys, &state) {
            return Err(failed(&sys, &state, &stepper, &rec, e, t_start));
        }
        rows.push(StageSummary {
            name: scenario.stage[k].name.clone(),
            status: last.0,
            message: last.1.clone(),
            start_time: t0,
            end_time: state.motion.time,
            start_step: s0,
            end_step: state.motion.step,
            blocks: sys.geometry.blocks.len(),
            unbalanced_force_ratio: Some(rec.last_unbalanced).filter(|r| r.is_finite()),
            wall_seconds: t_stage.elapsed().as_secs_f64(),
        });
        current = Some((sys, state, stepper, rec));
        before = map;
        if last.0 != Status::Completed {
            last.1 = format!("stage '{}': {}", scenario.stage[k].name, last.1);
            break;
        }
    }
    if let Some(p) = progress.as_mut() {
        p.finish();
    }
    let (sys, state, stepper, rec) = current.expect("a staged scenario has a stage");
    if let Err(e) = write_stages(out, &rows) {
        return Err(failed(&sys, &state, &stepper, &rec, e, t_start));
    }
    let end = Ending {
        status: last.0,
        message: &last.1,
        wall: t_start.elapsed().as_secs_f64(),
        initial_equilibrium: saver.initial_equilibrium.clone(),
        resumed_at: None,
    };
    let mut summary = summary(&sys, &state, &stepper, &rec, &end);
    summary.stages = rows;
    write_summary(out, &summary)?;
    Ok(RunOutcome { completed: summary.status == Status::Completed, summary })
}

/// `stages.csv`: one row per stage that ran.
fn write_stages(out: &std::path::Path, rows: &[StageSummary]) -> Result<()> {
    let mut s = String::from(
        "stage,status,start_time,end_time,start_step,end_step,blocks,unbalanced_force_ratio,wall_seconds,message\n",
    );
    for r in rows {
        let status = serde_json::to_value(r.status).expect("a status serialises");
        let ratio = r.unbalanced_force_ratio.map_or(String::new(), |x| x.to_string());
        let _ = writeln!(
            s,
            "\"{}\",{},{},{},{},{},{},{ratio},{},\"{}\"",
            r.name.replace('"', "\"\""),
            status.as_str().unwrap_or(""),
            r.start_time,
            r.end_time,
            r.start_step,
            r.end_step,
            r.blocks,
            r.wall_seconds,
            r.message.replace('"', "\"\""),
        );
    }
    atomic::write(&out.join("stages.csv"), s.as_bytes())
}
