//! Loading a scenario whole: parsed and its keys checked (`scenario`), its shapes checked by the
//! model that will build them (`model`); every problem reported together, each with its key
//! path, and its estimated memory within `analysis.max_memory` (`model::estimate`). The one
//! entry point for files, TOML text and JSON (Python dictionaries).

use std::path::Path;

use crate::error::{Error, Result};
use crate::model::estimate;
use crate::model::shape::shape_problems;
use crate::scenario::{self, Scenario};

/// Read, override and validate a scenario file.
pub fn load_file(path: &Path, overrides: &[String]) -> Result<Scenario> {
    checked(scenario::read_file(path, overrides)?, &path.display().to_string())
}

/// Parse TOML text (`label` names the source in messages), apply overrides, validate.
pub fn from_toml_str(text: &str, label: &str, overrides: &[String]) -> Result<Scenario> {
    let s = scenario::parse_toml(text, label, overrides)?;
    checked(scenario::spell_out(s, Path::new("."), label)?, label)
}

/// Parse a JSON document (from Python dictionaries), apply overrides, validate.
pub fn from_json_str(text: &str, label: &str, overrides: &[String]) -> Result<Scenario> {
    checked(scenario::parse_json(text, label, overrides)?, label)
}

fn checked(s: Scenario, label: &str) -> Result<Scenario> {
    let mut problems = scenario::problems(&s);
    // Shapes are judged where the model is cut: in its local frame (far from the origin, a
    // solid's round-off would be judged instead).
    let local = s.shifted(s.local_origin());
    problems.extend(shape_problems(&local));
    if problems.is_empty() {
        // Only a scenario whose every value is valid can be costed.
        problems.extend(estimate::problems(&local));
    }
    if problems.is_empty() {
        Ok(s)
    } else {
        Err(Error::Scenario { file: label.to_string(), problems })
    }
}
