//! A run from scenario to outputs. Failures after the model is built end the run with status "failed", a stop request (Ctrl-C)
//! with status "interrupted" after the current step; either way every output stays valid up to
//! the last accepted step, and `summary.json` is always written last.

use std::time::Instant;

use crate::checkpoint;
use crate::error::{Error, Result};
use crate::monitor::MonitorPlan;
use crate::output::progress::Progress;
use crate::output::summary::Status;
use crate::output::{run_dir, tables};
use crate::scenario::{AnalysisKind, Scenario};
use crate::system::System;
use crate::time::settle::Settled;
use crate::time::{State, Stepper};

use super::advance::{advance, failed, progress_mode, start, write_summary, End, Saver};
use super::options::{RunOptions, RunOutcome};
use super::recorder::Recorder;
use super::summary::{summary, Ending};

/// Run a validated scenario (or, with `opts.resume`, continue the run whose checkpoint is in
/// `opts.out`). `Err` only for invalid input or unwritable outputs; a run that fails
/// numerically returns `Ok` with `completed = false`. It runs on a thread pool of its own
/// ([`on_own_pool`]).
pub fn run(scenario: Scenario, label: &str, opts: &RunOptions) -> Result<RunOutcome> {
    on_own_pool(|| run_here(scenario, label, opts))
}

/// Stack of a run's threads [bytes]: the stepper ran on the caller's (a main thread's 8 MiB),
/// rayon's workers get 2 MiB unless told; only what is touched is committed.
const RUN_STACK: usize = 16 << 20;

/// `f` on a worker of a thread pool of its own (as many threads as rayon's global pool would
/// have: `RAYON_NUM_THREADS`, else the cores), unless already on a pool's worker (a caller that
/// chose the threads). The stepper's parallel loops — detection, the elements' tangents and
/// forces — then start inside the pool they run on; started from outside, each handed its work
/// over to the pool and woke the caller when done, which cost 3–16 % of the wall time of the
/// thesis slope, the Yade-matched dominos and the thesis tunnel (2026-11-30, back to back, the
/// same results bit for bit). A pool per run, so that runs in threads of one process never take up each other's
/// work in their waits.
fn on_own_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        return f();
    }
    match rayon::ThreadPoolBuilder::new().stack_size(RUN_STACK).thread_name(|i| format!("nmm3d-run-{i}")).build() {
        Ok(pool) => pool.install(f),
        // No threads to be had: run here, as before.
        Err(_) => f(),
    }
}

fn run_here(scenario: Scenario, label: &str, opts: &RunOptions) -> Result<RunOutcome> {
    if scenario.staged() {
        return super::stages::run(scenario, label, opts);
    }
    let t_start = Instant::now();
    let out = &opts.out;
    // Held to the end of the run: no other run writes here meanwhile.
    let _dir = run_dir::open(out, label, !opts.resume)?;
    let resumed = if opts.resume { Some(checkpoint::read(out, &scenario, label)?) } else { None };
    let resumed_at = resumed.as_ref().map(|c| (c.state.motion.step, c.state.motion.time));
    let mut saver = Saver::new(out, checkpoint::comparable(&scenario), scenario.analysis.checkpoint_interval);
    let sys = System::build(scenario, label)?;
    let monitors = MonitorPlan::all(&sys, label)?;
    let _ = std::fs::remove_file(out.join("summary.json"));
    tables::write_blocks(&sys, out)?;
    let mut rec = Recorder::new(&sys, monitors, out);
    let (mut state, mut stepper) = match resumed {
        Some(c) => {
            rec.restore(c.record);
            saver.initial_equilibrium = c.initial_equilibrium.map(|(steps, unbalanced)| Settled {
                steps,
                unbalanced,
                moving: c.initial_moving.clone(),
                names: Vec::new(),
                exhausted: c.initial_exhausted,
            });
            (c.state, Stepper::resume(&sys, c.stepper)?)
        }
        None => {
            let mut state = State::initial(&sys);
            let stepper = Stepper::new(&sys, &mut state, label)?;
            (state, stepper)
        }
    };
    let mut progress = Progress::new(progress_mode(opts.progress), &state.motion);
    let static_run = sys.scenario.analysis.kind == AnalysisKind::Static;
    let started =
        if resumed_at.is_some() { Ok(()) } else { start(&sys, &mut state, &mut stepper, &mut rec, &mut saver) };
    let result = started.and_then(|_| {
        advance(&sys, (&mut state, &mut stepper), &mut rec, &mut progress, opts.stop.as_ref(), &mut saver, static_run)
    });
    rec.cut_log.append(&mut stepper.cuts);
    progress.finish();
    let (status, message) = match result {
        Ok(End::Completed(m)) => (Status::Completed, m),
        Ok(End::Interrupted(m)) => (Status::Interrupted, m),
        Ok(End::NotConverged(m)) => (Status::NotConverged, m),
        Err(e @ (Error::Diverged { .. } | Error::Solver { .. })) => (Status::Failed, e.to_string()),
        Err(e) => return Err(failed(&sys, &state, &stepper, &rec, e, t_start)),
    };
    // The last frame, the tables and the checkpoint count as output too.
    let t_out = Instant::now();
    let written = rec.finish(&sys, &state);
    let written =
        written.and_then(|_| if status == Status::Failed { Ok(()) } else { saver.save(&state, &stepper, &rec) });
    rec.output_seconds += t_out.elapsed().as_secs_f64();
    if let Err(e) = written {
        return Err(failed(&sys, &state, &stepper, &rec, e, t_start));
    }
    let end = Ending {
        status,
        message: &message,
        wall: t_start.elapsed().as_secs_f64(),
        initial_equilibrium: saver.initial_equilibrium.clone(),
        resumed_at,
    };
    let summary = summary(&sys, &state, &stepper, &rec, &end);
    write_summary(out, &summary)?;
    Ok(RunOutcome { summary, completed: status == Status::Completed })
}
