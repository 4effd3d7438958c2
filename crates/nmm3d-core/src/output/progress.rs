//! What a running simulation tells the person waiting for it: a live line on a terminal, a plain
//! periodic line in a log, one estimate of the run's cost after the first steps and a hint when
//! the time step collapses. Written to standard error; standard output stays for results.

use std::collections::VecDeque;
use std::io::Write;
use std::time::Instant;

use crate::scenario::{Analysis, AnalysisKind};
use crate::state::Motion;
use crate::time::StepReport;

/// Where progress goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgressMode {
    /// Nothing.
    Off,
    /// One line rewritten in place (standard error is a terminal).
    Terminal,
    /// A plain line every [`LOG_SECONDS`] (standard error is a file or a pipe).
    Log,
}

/// Wall seconds between rewrites of the terminal line.
const TERMINAL_SECONDS: f64 = 0.5;
/// Wall seconds between lines in a log.
const LOG_SECONDS: f64 = 30.0;
/// Wall seconds of running, and accepted steps, before the cost of the run is estimated.
const ESTIMATE_AFTER_SECONDS: f64 = 5.0;
const ESTIMATE_AFTER_STEPS: u64 = 3;
/// A step below this fraction of the requested `dt` has collapsed [-].
const COLLAPSED_DT_RATIO: f64 = 0.01;
/// Window over which cuts are counted and the rate of simulated time is measured [s wall].
const WINDOW_SECONDS: f64 = 10.0;

/// The progress of one run.
#[derive(Debug)]
pub struct Progress {
    mode: ProgressMode,
    start: Instant,
    last_line: Option<Instant>,
    /// (wall, simulated time, cuts of the step) of recent steps.
    recent: VecDeque<(f64, f64, u32)>,
    estimated: bool,
    warned_collapse: bool,
    t0: f64,
}

impl Progress {
    /// Progress from the state the stepping starts at.
    pub fn new(mode: ProgressMode, state: &Motion) -> Self {
        Self {
            mode,
            start: Instant::now(),
            last_line: None,
            recent: VecDeque::new(),
            estimated: false,
            warned_collapse: false,
            t0: state.time,
        }
    }

    /// After each accepted step.
    pub fn step(&mut self, a: &Analysis, state: &Motion, report: &StepReport) {
        if self.mode == ProgressMode::Off {
            return;
        }
        let wall = self.start.elapsed().as_secs_f64();
        self.recent.push_back((wall, state.time, report.cuts));
        while self.recent.front().is_some_and(|r| wall - r.0 > WINDOW_SECONDS) && self.recent.len() > 2 {
            let _ = self.recent.pop_front();
        }
        self.notes(a, state, report, wall);
        let every = if self.mode == ProgressMode::Terminal { TERMINAL_SECONDS } else { LOG_SECONDS };
        if self.last_line.is_none_or(|t| t.elapsed().as_secs_f64() >= every) {
            let line = self.line(a, state, report, wall);
            self.emit(&line);
            self.last_line = Some(Instant::now());
        }
    }

    /// Ends the terminal line before anything else is printed.
    pub fn finish(&self) {
        if self.mode == ProgressMode::Terminal && self.last_line.is_some() {
            eprintln!();
        }
    }

    fn emit(&self, line: &str) {
        let mut err = std::io::stderr().lock();
        let _ = match self.mode {
            ProgressMode::Terminal => write!(err, "\r{line}\x1b[K"),
            _ => writeln!(err, "{line}"),
        };
        let _ = err.flush();
    }

    /// Messages printed once on their own line.
    fn note(&self, text: &str) {
        let mut err = std::io::stderr().lock();
        let _ =
            if self.mode == ProgressMode::Terminal { writeln!(err, "\r{text}\x1b[K") } else { writeln!(err, "{text}") };
    }

    fn notes(&mut self, a: &Analysis, state: &Motion, report: &StepReport, wall: f64) {
        if !self.estimated
            && a.kind == AnalysisKind::Dynamic
            && wall >= ESTIMATE_AFTER_SECONDS
            && state.step >= ESTIMATE_AFTER_STEPS
        {
            self.estimated = true;
            if let Some(left) = self.remaining(a, state, wall) {
                self.note(&format!(
                    "  estimate: {} more at the current rate (Δt = {:.3e} s, {:.0} steps/s)",
                    duration(left),
                    report.dt,
                    self.steps_per_second()
                ));
            }
        }
        if !self.warned_collapse && report.dt < COLLAPSED_DT_RATIO * a.dt {
            self.warned_collapse = true;
            self.note(&format!(
                "  note: the time step has collapsed to {:.3e} s ({:.2} % of dt = {} s) at t = {:.6} s: diagnostics.csv gives the cuts per step; \
                 for jointed rock try analysis.open_close_tolerance = 1e-4, or 1e-3 for blocks sliding as a layer (docs/open-close-tolerance.md)",
                report.dt, 100.0 * report.dt / a.dt, a.dt, state.time
            ));
        }
    }

    fn line(&self, a: &Analysis, state: &Motion, report: &StepReport, wall: f64) -> String {
        let cuts: u32 = self.recent.iter().map(|r| r.2).sum();
        let head = match a.kind {
            AnalysisKind::Dynamic => {
                let pct = 100.0 * state.time / a.duration;
                let eta = self.remaining(a, state, wall).map_or_else(|| "–".to_string(), duration);
                format!("{pct:5.1} %  t = {:.6} s  ETA {eta}", state.time)
            }
            AnalysisKind::Static => {
                format!("static  unbalanced {:.3e} (target {:.1e})", report.unbalanced, a.equilibrium_tolerance)
            }
        };
        format!(
            "  {head}  step {}  Δt = {:.3e} s  unbalanced {:.2e}  contacts {}  cuts {cuts} in {:.0} s  wall {}",
            state.step,
            report.dt,
            report.unbalanced,
            report.contacts,
            self.window(),
            duration(wall)
        )
    }

    /// Wall seconds left at the rate of the recent window; `None` before anything moved.
    fn remaining(&self, a: &Analysis, state: &Motion, wall: f64) -> Option<f64> {
        let (w0, t0) = self.recent.front().map_or((0.0, self.t0), |r| (r.0, r.1));
        let (dw, dt) = if self.recent.len() > 2 { (wall - w0, state.time - t0) } else { (wall, state.time - self.t0) };
        (dt > 0.0 && dw > 0.0).then(|| (a.duration - state.time).max(0.0) * dw / dt)
    }

    fn steps_per_second(&self) -> f64 {
        let span = self.window();
        if span > 0.0 {
            (self.recent.len() - 1) as f64 / span
        } else {
            0.0
        }
    }

    fn window(&self) -> f64 {
        match (self.recent.front(), self.recent.back()) {
            (Some(f), Some(b)) => b.0 - f.0,
            _ => 0.0,
        }
    }
}

/// "2 h 05 min", "3 min 20 s", "12 s".
pub fn duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::duration;

    #[test]
    fn durations_read_as_people_say_them() {
        assert_eq!(duration(12.4), "12 s");
        assert_eq!(duration(200.0), "3 min 20 s");
        assert_eq!(duration(7500.0), "2 h 05 min");
        assert_eq!(duration(-1.0), "0 s");
    }
}
