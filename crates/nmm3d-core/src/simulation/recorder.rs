//! The run's record as it goes: history rows, diagnostics, step cuts and frames, and the
//! values they end with.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::checkpoint::RecordSnapshot;
use crate::error::Result;
use crate::monitor::MonitorPlan;
use crate::output::layout::FrameLayout;
use crate::output::{cuts, frame, tables, vtu};
use crate::scenario::Scenario;
use crate::system::System;
use crate::time::State;

/// Records history rows and frames as the run goes.
pub(super) struct Recorder {
    pub(super) monitors: Vec<MonitorPlan>,
    pub(super) history: tables::History,
    pub(super) diagnostics: Vec<(f64, u64, crate::time::StepReport)>,
    pub(super) cut_log: Vec<crate::time::Cut>,
    pub(super) frames: Vec<(f64, String, Option<String>)>,
    pub(super) out: PathBuf,
    pub(super) next_history: f64,
    pub(super) next_frame: f64,
    pub(super) last_frame_step: Option<u64>,
    pub(super) last_unbalanced: f64,
    pub(super) cuts: u64,
    pub(super) max_penetration: f64,
    pub(super) max_contacts: usize,
    pub(super) open_close: u64,
    pub(super) output_seconds: f64,
    pub(super) last_history_write: Instant,
    /// Where each monitored value of the current model goes among the history's columns (a
    /// staged run's columns are every stage's); `None`: in order.
    layout: Option<Vec<usize>>,
    /// The frames' cells of the current model, made by its first frame.
    frame_layout: Option<FrameLayout>,
}

/// Wall-clock seconds between rewrites of `history.csv` during a run, so long runs can be
/// followed and a crash loses little.
const HISTORY_FLUSH_SECONDS: f64 = 10.0;

impl Recorder {
    pub(super) fn new(sys: &System, monitors: Vec<MonitorPlan>, out: &Path) -> Self {
        let columns = columns(&sys.scenario, &monitors);
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
            layout: None,
            frame_layout: None,
        }
    }

    /// The history's columns made those of all `stages` (first appearance first).
    pub(super) fn for_stages(mut self, stages: &[Scenario]) -> Self {
        for s in stages {
            for c in columns(s, &self.monitors) {
                if !self.history.columns.contains(&c) {
                    self.history.columns.push(c);
                }
            }
        }
        self
    }

    /// Record the model `sys` of the next stage from now on, with its monitors.
    pub(super) fn restage(&mut self, sys: &System, monitors: Vec<MonitorPlan>) {
        let all = &self.history.columns;
        let at = |c: &String| all.iter().position(|x| x == c).expect("the run's columns hold every stage's");
        self.layout = Some(columns(&sys.scenario, &monitors).iter().map(at).collect());
        self.monitors = monitors;
        self.frame_layout = None;
    }

    pub(super) fn record(&mut self, sys: &System, whole: &State, first: bool) -> Result<()> {
        let state = &whole.motion;
        let t = Instant::now();
        let a = &sys.scenario.analysis;
        let eps = 1e-9 * a.dt;
        if first || a.history_interval.is_none() || state.time + eps >= self.next_history {
            let mut vals: Vec<f64> = self.monitors.iter().flat_map(|m| m.values(sys, state)).collect();
            vals.extend(crate::time::bolt_values(sys, state));
            if sys.scenario.seismic.moves() {
                vals.extend(state.base.iter().flat_map(|v| [v.x, v.y, v.z]));
            }
            if let Some(layout) = &self.layout {
                let mut row = vec![f64::NAN; self.history.columns.len()];
                layout.iter().zip(&vals).for_each(|(&i, &v)| row[i] = v);
                vals = row;
            }
            self.history.rows.push((state.time, state.step, vals));
            if let Some(h) = a.history_interval {
                self.next_history = (state.time / h + 1e-9).floor() * h + h;
            }
        }
        if first || (a.output_interval > 0.0 && state.time + eps >= self.next_frame) {
            self.frame(sys, whole)?;
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

    pub(super) fn frame(&mut self, sys: &System, whole: &State) -> Result<()> {
        let (state, contacts) = (&whole.motion, whole.contact.as_ref());
        let k = self.frames.len();
        let name = format!("frames/blocks_{k:05}.vtu");
        frame::write_frame(sys, state, &self.out.join(&name), &mut self.frame_layout)?;
        let contact_name = match contacts {
            Some(c) => {
                let name = format!("frames/contacts_{k:05}.vtu");
                vtu::write_contacts(sys, state, &c.records, &self.out.join(&name))?;
                Some(name)
            }
            None => None,
        };
        let bolts = !sys.bolt_paths.is_empty();
        if bolts {
            vtu::write_bolts(sys, state, &self.out.join(vtu::bolts_file(&name)))?;
        }
        self.frames.push((state.time, name, contact_name));
        self.last_frame_step = Some(state.step);
        vtu::write_pvd(&self.out.join("result.pvd"), &self.frames, bolts)?;
        self.history.write(&self.out)
    }

    pub(super) fn finish(&mut self, sys: &System, state: &State) -> Result<()> {
        if self.last_frame_step != Some(state.motion.step) {
            self.frame(sys, state)?;
        }
        tables::write_diagnostics(&self.out, &self.diagnostics)?;
        cuts::write(&self.out, &self.cut_log)?;
        self.history.write(&self.out)
    }

    pub(super) fn snapshot(&self) -> RecordSnapshot {
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

    pub(super) fn restore(&mut self, s: RecordSnapshot) {
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

    /// The monitored values of the last history row; `None` where a value is not defined.
    pub(super) fn final_values(&self) -> BTreeMap<String, Option<f64>> {
        let Some((_, _, vals)) = self.history.rows.last() else { return BTreeMap::new() };
        self.history.columns.iter().zip(vals).map(|(c, &v)| (c.clone(), Some(v).filter(|v| v.is_finite()))).collect()
    }
}

/// History columns of a scenario's model: monitors, bolts, the shaking base.
fn columns(s: &Scenario, monitors: &[MonitorPlan]) -> Vec<String> {
    let bolts = s.bolt.iter().flat_map(|b| b.columns());
    monitors.iter().flat_map(|m| m.columns()).chain(bolts).chain(s.seismic.columns()).collect()
}
