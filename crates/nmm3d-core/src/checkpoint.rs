//! `checkpoint.json`: everything a run needs to continue exactly where it stopped — the whole
//! [`State`] (motion, contact points, counters, energy accounts), the stepper's caches (matrix
//! pattern, factor) and what the recorder has gathered — with the scenario it belongs to.
//! `nmm3d run --resume` reads it; a resumed run continues bit for bit as if it had never
//! stopped (`tests/contract_checkpoint.rs`).
//!
//! JSON, so a checkpoint can be read and compared by people and tools; floats round-trip exactly
//! (shortest representation out, `serde_json`'s `float_roundtrip` in).

use std::path::Path;

use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::error::{Error, Problem, Result};
use crate::output::atomic;
use crate::scenario::Scenario;
use crate::time::snapshot::StepperSnapshot;
use crate::time::State;
use crate::time::{Cut, StepReport};

/// Version of the file format (2: the contact points and counters moved from `stepper` into
/// `state`; a version-1 file is read and moved over, see [`upgrade_v1`]).
pub const VERSION: u32 = 2;
/// File name in the output directory.
pub const FILE: &str = "checkpoint.json";

/// Scenario keys a resumed run may change: how far it goes, not how it gets there.
const MAY_CHANGE: [&str; 3] = ["duration", "max_steps", "checkpoint_interval"];

/// A run stopped at the end of an accepted step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// File format version.
    pub version: u32,
    /// The scenario as run, without the keys a resumed run may change.
    pub scenario: Value,
    /// The whole state of the run.
    pub state: State,
    /// The stepper's caches.
    pub stepper: StepperSnapshot,
    /// The outputs gathered so far.
    pub record: RecordSnapshot,
    /// Steps and unbalanced force ratio of the initial equilibrium, when there was one.
    pub initial_equilibrium: Option<(u64, f64)>,
    /// Blocks still moving when the initial equilibrium stopped unconverged.
    #[serde(default)]
    pub initial_moving: Vec<usize>,
    /// The initial equilibrium stopped unconverged at its step limit (not because a block
    /// moved by a cover cell).
    #[serde(default)]
    pub initial_exhausted: bool,
}

/// What the recorder has gathered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordSnapshot {
    /// History rows: time, step, monitor values.
    pub history: Vec<(f64, u64, Vec<f64>)>,
    /// Diagnostics rows: time, step, the step's report.
    pub diagnostics: Vec<(f64, u64, StepReport)>,
    /// Rejected trials so far.
    #[serde(default)]
    pub cut_log: Vec<Cut>,
    /// Frames written: time, blocks file, contact file.
    pub frames: Vec<(f64, String, Option<String>)>,
    /// Time of the next history row [s].
    pub next_history: f64,
    /// Time of the next frame [s].
    pub next_frame: f64,
    /// Step of the last frame.
    pub last_frame_step: Option<u64>,
    /// Unbalanced force ratio of the last step.
    pub last_unbalanced: Option<f64>,
    /// Step cuts so far.
    pub cuts: u64,
    /// Largest penetration so far [m].
    pub max_penetration: f64,
    /// Most contact points so far.
    pub max_contacts: usize,
    /// Open–close iterations so far.
    pub open_close: u64,
}

/// The scenario as a checkpoint records it.
pub fn comparable(s: &Scenario) -> Value {
    let mut v = serde_json::to_value(s).expect("a validated scenario serialises");
    if let Some(a) = v.get_mut("analysis").and_then(Value::as_object_mut) {
        for k in MAY_CHANGE {
            let _ = a.remove(k);
        }
    }
    if let Some(m) = v.as_object_mut() {
        let _ = m.remove("expect");
        let _ = m.remove("study");
    }
    v
}

/// A checkpoint's scenario as this version reads it: keys it does not name — added to nmm3d
/// after it was written, and the ones a resumed run may change, which `comparable` drops again —
/// at their defaults, as a scenario file that leaves them out gets them. As recorded if this
/// version cannot read it (the comparison then names what differs).
fn with_defaults(recorded: &Value) -> Value {
    serde_json::from_value::<Scenario>(recorded.clone()).map_or_else(|_| recorded.clone(), |s| comparable(&s))
}

/// Write `checkpoint.json` in `out` (atomically).
pub fn write(out: &Path, c: &Checkpoint) -> Result<()> {
    atomic::write_with(&out.join(FILE), |w| serde_json::to_writer(w, c).map_err(std::io::Error::from))
}

/// Read `out/checkpoint.json` and check it belongs to `scenario` (`label` names it).
pub fn read(out: &Path, scenario: &Scenario, label: &str) -> Result<Checkpoint> {
    let path = out.join(FILE);
    let problem = |reason: String| Error::Scenario {
        file: label.to_string(),
        problems: vec![Problem { path: "--resume".into(), reason }],
    };
    let text = match std::fs::read(&path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(problem(format!("there is no {FILE} in {} (a run writes it when it completes or is interrupted, and every analysis.checkpoint_interval seconds)", out.display())));
        }
        r => r.map_err(|e| Error::io(&path, e))?,
    };
    let unreadable =
        |e: serde_json::Error| problem(format!("{} is not a checkpoint of this version: {e}", path.display()));
    let mut value: Value = serde_json::from_slice(&text).map_err(unreadable)?;
    match value.get("version").and_then(Value::as_u64) {
        Some(1) => upgrade_v1(&mut value),
        Some(v) if v == u64::from(VERSION) => {}
        v => {
            let v = v.map_or("none".to_string(), |v| v.to_string());
            return Err(problem(format!(
                "{} has format version {v}, this nmm3d reads 1 and {VERSION}",
                path.display()
            )));
        }
    }
    let c: Checkpoint = serde_json::from_value(value).map_err(unreadable)?;
    if let Some(key) = first_difference(&with_defaults(&c.scenario), &comparable(scenario), String::new()) {
        return Err(problem(format!("the scenario differs from the checkpoint's at '{key}' (only analysis.duration, max_steps and checkpoint_interval may change)")));
    }
    Ok(c)
}

/// Move a version-1 checkpoint's run state into place: version 1 kept the motion alone in
/// `state` and the contact points and counters in `stepper`.
pub fn upgrade_v1(v: &mut Value) {
    const COUNTERS: [&str; 12] = [
        "force_scale",
        "locked",
        "relaxing",
        "inertia",
        "penetration_cuts",
        "penalty_raises",
        "equilibrium_iterations",
        "energy",
        "undetected",
        "contact_end",
        "newton",
        "free_fall",
    ];
    let Some(m) = v.as_object_mut() else { return };
    let motion = m.remove("state").unwrap_or(Value::Null);
    let mut stepper = match m.remove("stepper") {
        Some(Value::Object(s)) => s,
        _ => serde_json::Map::new(),
    };
    let contact = stepper.remove("contacts").unwrap_or(Value::Null);
    let counters: serde_json::Map<String, Value> =
        COUNTERS.iter().filter_map(|&k| stepper.remove(k).map(|x| (k.to_string(), x))).collect();
    let state = serde_json::json!({ "motion": motion, "contact": contact, "stepper": counters });
    let _ = m.insert("state".into(), state);
    let _ = m.insert("stepper".into(), Value::Object(stepper));
    let _ = m.insert("version".into(), Value::from(VERSION));
}

/// The key path of the first difference between two JSON values.
fn first_difference(a: &Value, b: &Value, path: String) -> Option<String> {
    let join = |k: &str| if path.is_empty() { k.to_string() } else { format!("{path}.{k}") };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => x.keys().chain(y.keys()).find_map(|k| match (x.get(k), y.get(k)) {
            (Some(p), Some(q)) => first_difference(p, q, join(k)),
            _ => Some(join(k)),
        }),
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            x.iter().zip(y).enumerate().find_map(|(i, (p, q))| first_difference(p, q, format!("{path}[{i}]")))
        }
        _ => (a != b).then_some(if path.is_empty() { "(the whole scenario)".into() } else { path }),
    }
}

#[cfg(test)]
mod tests {
    use super::first_difference;
    use serde_json::json;

    #[test]
    fn the_first_difference_is_named_by_its_key_path() {
        let a = json!({"analysis": {"dt": 0.001}, "body": [{"name": "a"}, {"name": "b"}]});
        assert_eq!(first_difference(&a, &a, String::new()), None);
        let b = json!({"analysis": {"dt": 0.002}, "body": [{"name": "a"}, {"name": "b"}]});
        assert_eq!(first_difference(&a, &b, String::new()).as_deref(), Some("analysis.dt"));
        let c = json!({"analysis": {"dt": 0.001}, "body": [{"name": "a"}, {"name": "c"}]});
        assert_eq!(first_difference(&a, &c, String::new()).as_deref(), Some("body[1].name"));
        let d = json!({"analysis": {"dt": 0.001, "kind": "static"}, "body": [{"name": "a"}, {"name": "b"}]});
        assert_eq!(first_difference(&a, &d, String::new()).as_deref(), Some("analysis.kind"));
    }
}
