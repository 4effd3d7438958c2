//! Helpers shared by the integration tests: build scenarios from TOML text and run them.
#![allow(dead_code)]

use std::path::PathBuf;

use nmm3d_core::scenario::{self, Scenario};
use nmm3d_core::simulation::{run, RunOptions, RunOutcome};

/// Parse and validate a scenario written inline.
pub fn scenario(text: &str) -> Scenario {
    scenario::from_toml_str(text, "<test>", &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// A fresh output directory under the target dir.
pub fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Run and require completion.
pub fn run_ok(text: &str, name: &str) -> RunOutcome {
    let out = run(scenario(text), "<test>", &RunOptions { out: out_dir(name), progress: false }).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.completed, "{}", out.summary["message"]);
    out
}

/// A final monitor value from the summary.
pub fn final_value(out: &RunOutcome, key: &str) -> f64 {
    out.summary["final"][key].as_f64().unwrap_or_else(|| panic!("no final value {key}"))
}
