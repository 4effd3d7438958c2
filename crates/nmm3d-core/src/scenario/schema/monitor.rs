//! What a run records and checks: monitors and expectations.

use serde::{Deserialize, Serialize};

/// Which block a monitor follows.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum MonitorSelect {
    /// The block containing this point at t = 0.
    Point([f64; 3]),
    /// A body made of a single block.
    Body(String),
    /// The block with this id (as in `blocks.csv`; addition to v1).
    Block(usize),
}

/// Monitored quantities.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    /// Centroid displacement [m].
    Displacement,
    /// Centroid velocity [m/s].
    Velocity,
    /// Rotation vector [rad].
    Rotation,
    /// Volume [m³].
    Volume,
    /// Volume-mean stress [Pa].
    Stress,
}

/// `[[monitor]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Monitor {
    /// Unique name.
    pub name: String,
    /// The block followed.
    pub select: MonitorSelect,
    /// Quantities recorded.
    pub quantities: Vec<Quantity>,
    /// Where displacement and velocity are taken (addition to v1): the block's centroid, or
    /// the material point at `select.point`.
    #[serde(default)]
    pub location: MonitorLocation,
}

/// Where a monitor takes displacement and velocity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MonitorLocation {
    /// Volume-weighted mean over the block (its centroid).
    #[default]
    Centroid,
    /// The material point at `select.point`.
    Point,
}

impl Quantity {
    /// Name used in column headers.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Displacement => "displacement",
            Quantity::Velocity => "velocity",
            Quantity::Rotation => "rotation",
            Quantity::Volume => "volume",
            Quantity::Stress => "stress",
        }
    }
    /// Component names in column headers.
    pub fn components(self) -> &'static [&'static str] {
        match self {
            Quantity::Volume => &["value"],
            Quantity::Stress => &["xx", "yy", "zz", "xy", "yz", "zx"],
            _ => &["x", "y", "z"],
        }
    }
}

/// `[[expect]]` (addition to v1): the value a monitored quantity should have at the end of the
/// run, from a closed form or an independent reference. Printed beside the answer and reported
/// in `summary.json` under `checks`; it never changes how the run goes.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// A column of `history.csv`: `<monitor>.<quantity>.<component>`.
    pub quantity: String,
    /// Reference value, in the column's unit (absent: only the bounds are checked).
    #[serde(default)]
    pub reference: Option<f64>,
    /// The final value must be at least this, in the column's unit (a qualitative outcome:
    /// "the domino falls") (addition).
    #[serde(default)]
    pub at_least: Option<f64>,
    /// The final value must be at most this, in the column's unit (addition).
    #[serde(default)]
    pub at_most: Option<f64>,
    /// Allowed relative difference, a fraction of |reference| [-].
    #[serde(default = "Expect::default_tolerance")]
    pub tolerance: f64,
    /// Allowed absolute difference, in the column's unit (for references near zero).
    #[serde(default)]
    pub absolute_tolerance: f64,
    /// Where the reference comes from.
    #[serde(default)]
    pub source: String,
}

impl Expect {
    fn default_tolerance() -> f64 {
        0.01
    }
}
