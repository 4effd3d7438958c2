//! Helpers shared by the integration tests: build scenarios from TOML text and run them.
#![allow(dead_code)]

use std::path::PathBuf;

use nmm3d_core::scenario::Scenario;
use nmm3d_core::simulation::{run, RunOptions, RunOutcome};

/// The model of `text` with its initial state and a stepper ready to step (what a run does
/// before its first step), for tests that step by hand.
pub fn started(text: &str, label: &str) -> (System, State, Stepper) {
    let sys = System::build(scenario(text), label).unwrap_or_else(|e| panic!("{e}"));
    let mut state = State::initial(&sys);
    let mut stepper = Stepper::new(&sys, &mut state, label).unwrap_or_else(|e| panic!("{e}"));
    stepper.initialize(&sys, &mut state).unwrap_or_else(|e| panic!("{e}"));
    (sys, state, stepper)
}

/// Parse and validate a scenario written inline.
pub fn scenario(text: &str) -> Scenario {
    nmm3d_core::input::from_toml_str(text, "<test>", &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// A fresh output directory under the target dir.
pub fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Run and require completion.
pub fn run_ok(text: &str, name: &str) -> RunOutcome {
    let out = run(scenario(text), "<test>", &RunOptions { out: out_dir(name), progress: false, ..Default::default() })
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(out.completed, "{}", out.summary.message);
    out
}

/// One column of `history.csv` of the run named `name` (time, values).
#[allow(dead_code)] // not every test binary reads histories
pub fn history(name: &str, column: &str) -> Vec<(f64, f64)> {
    let text = std::fs::read_to_string(PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name).join("history.csv"))
        .expect("history.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let k = header.iter().position(|h| *h == column).unwrap_or_else(|| panic!("no column {column}"));
    lines.map(|l| l.split(',').collect::<Vec<_>>()).map(|c| (c[0].parse().unwrap(), c[k].parse().unwrap())).collect()
}

/// A final monitor value from the summary.
pub fn final_value(out: &RunOutcome, key: &str) -> f64 {
    out.summary.final_values.get(key).copied().flatten().unwrap_or_else(|| panic!("no final value {key}"))
}

use nmm3d_core::state::Motion;
use nmm3d_core::system::System;
use nmm3d_core::time::{State, Stepper};

/// Step a static scenario to equilibrium and return the system and final motion.
pub fn solve_static(text: &str) -> (System, Motion) {
    let sys = System::build(scenario(text), "<test>").unwrap_or_else(|e| panic!("{e}"));
    let mut state = State::initial(&sys);
    let mut stepper = Stepper::new(&sys, &mut state, "<test>").unwrap_or_else(|e| panic!("{e}"));
    stepper.initialize(&sys, &mut state).unwrap();
    let tol = sys.scenario.analysis.equilibrium_tolerance;
    for _ in 0..sys.scenario.analysis.max_steps {
        let r = stepper.step(&sys, &mut state, 1e30).unwrap_or_else(|e| panic!("{e}"));
        if state.motion.step > 1 && r.unbalanced <= tol {
            return (sys, state.motion);
        }
    }
    panic!("no equilibrium within max_steps");
}

/// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG, seeded).
pub struct Lcg(pub u64);

impl Lcg {
    /// Next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Text of an example scenario in `examples/`.
pub fn example(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `text` with `old` replaced by `new`, which must occur.
pub fn with(text: &str, old: &str, new: &str) -> String {
    assert!(text.contains(old), "'{old}' is not in the scenario");
    text.replacen(old, new, 1)
}

/// `text` with each `(old, new)` replaced in turn ([`with`]).
pub fn with_each<S: AsRef<str>>(text: &str, replacements: &[(&str, S)]) -> String {
    replacements.iter().fold(text.to_string(), |t, (old, new)| with(&t, old, new.as_ref()))
}

/// Half-space planes (`convex` shape rows) of a fixed incline dipping `alpha_deg` towards
/// `dip_direction_deg` (surface through the origin, 3 m thick, 8 × 5 m) and of a block of
/// `height` × 1 × 1 m resting on it at the origin.
#[allow(dead_code)] // not every test binary builds inclines
pub fn incline_planes(alpha_deg: f64, dip_direction_deg: f64, height: f64) -> (String, String) {
    let (a, dd) = (alpha_deg.to_radians(), dip_direction_deg.to_radians());
    // Upward normal of the slope, dip vector, strike.
    let n = [a.sin() * dd.sin(), a.sin() * dd.cos(), a.cos()];
    let s = [a.cos() * dd.sin(), a.cos() * dd.cos(), -a.sin()];
    let h = [dd.cos(), -dd.sin(), 0.0];
    let plane = |v: [f64; 3], d: f64| format!("[{}, {}, {}, {}]", v[0], v[1], v[2], d);
    let neg = |v: [f64; 3]| [-v[0], -v[1], -v[2]];
    let base =
        [plane(n, 0.0), plane(neg(n), 3.0), plane(s, 4.0), plane(neg(s), 4.0), plane(h, 2.5), plane(neg(h), 2.5)]
            .join(", ");
    let block =
        [plane(neg(n), 0.0), plane(n, height), plane(s, 0.5), plane(neg(s), 0.5), plane(h, 0.5), plane(neg(h), 0.5)]
            .join(", ");
    (base, block)
}
