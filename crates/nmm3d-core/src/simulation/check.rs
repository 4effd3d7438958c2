//! What `nmm3d check` verifies beyond the scenario's own values: the model a run would build
//! before its first step — the blocks and covers, the monitors, bolts and loads located on them,
//! the first contact detection with its overlap check — for every stage of a staged analysis.
//! `check` and `run` then refuse the same inputs, with the same messages.

use serde_json::{json, Value};

use crate::error::Result;
use crate::model::Geometry;
use crate::monitor::MonitorPlan;
use crate::scenario::Scenario;
use crate::system::System;
use crate::time::{State, Stepper};

use super::stages::stage_scenarios;

/// Build what a run of the validated `scenario` builds before its first step; the model's size
/// (blocks and MEs of each stage) as JSON, or the error the run would end with.
pub fn check(scenario: Scenario, label: &str) -> Result<Value> {
    if !scenario.staged() {
        let sys = System::build(scenario, label)?;
        located(&sys, label, true)?;
        return Ok(json!({ "stages": [size(&sys)] }));
    }
    let full = Geometry::staged(&scenario);
    full.require_blocks(label)?;
    let extent = full.aabb().extent();
    let mut stages = Vec::new();
    for (k, at) in stage_scenarios(&scenario, label)?.into_iter().enumerate() {
        let (geometry, _) = full.without(&scenario.open_excavations(k));
        let sys = System::on_geometry(at, geometry, extent, label)?;
        // Later stages carry the state of the one before: no fresh detection.
        located(&sys, label, k == 0)?;
        stages.push(size(&sys));
    }
    Ok(json!({ "stages": stages }))
}

/// The monitors located on `sys` and, for a model a run starts on, the first contact detection.
fn located(sys: &System, label: &str, first: bool) -> Result<()> {
    MonitorPlan::all(sys, label)?;
    if first {
        Stepper::new(sys, &mut State::initial(sys), label)?;
    }
    Ok(())
}

fn size(sys: &System) -> Value {
    json!({ "blocks": sys.geometry.blocks.len(), "manifold_elements": sys.covers.elements.len() })
}
