//! The run summary (`summary.json`): counts, timings per phase, energy accounts and the final
//! monitored values with their checks.

use serde_json::{json, Map, Value};

use super::recorder::Recorder;
use crate::output::{checks, cuts};
use crate::state::State;
use crate::system::System;
use crate::time::Stepper;

pub(super) fn summary(
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
    let _ = timings.insert("step_equilibrium".into(), json!(stepper.times.equilibrium));
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
        "equilibrium_iterations": stepper.equilibrium_iterations,
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
