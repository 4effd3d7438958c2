//! The scenario file, version 1 (`docs/scenario.md`): typed, with defaults and units.
//! Unknown keys are rejected. Semantic checks live in `validate/`.

mod contact;
mod controls;
mod loads;
mod monitor;
mod rock;
mod stages;
mod support;

pub use contact::*;
pub use controls::*;
pub use loads::*;
pub use monitor::*;
pub use rock::*;
pub use stages::*;
pub use support::*;

use serde::{Deserialize, Serialize};

/// A whole scenario.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Name and description.
    #[serde(default)]
    pub scenario: Meta,
    /// Analysis controls.
    #[serde(default)]
    pub analysis: Analysis,
    /// The mathematical cover.
    #[serde(default)]
    pub cover: CoverSpec,
    /// Contact penalties.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Block cutting controls (addition to v1).
    #[serde(default)]
    pub cutting: CuttingSpec,
    /// Key-block analysis controls (addition to v1).
    #[serde(default)]
    pub keyblocks: KeyBlocksSpec,
    /// Materials (unique names).
    #[serde(default)]
    pub material: Vec<Material>,
    /// Joint strengths (unique names).
    #[serde(default)]
    pub joint: Vec<Joint>,
    /// Bodies (unique names).
    #[serde(default)]
    pub body: Vec<Body>,
    /// Joint sets (cutting).
    #[serde(default)]
    pub joint_set: Vec<JointSet>,
    /// Single joints (cutting).
    #[serde(default)]
    pub joint_plane: Vec<JointPlane>,
    /// Excavations.
    #[serde(default)]
    pub excavation: Vec<Excavation>,
    /// Joint between two bodies.
    #[serde(default)]
    pub interface: Vec<Interface>,
    /// Penalty constraints on boundary vertices in a region.
    #[serde(default)]
    pub constraint: Vec<Constraint>,
    /// Penalty constraints at points.
    #[serde(default)]
    pub fixed_point: Vec<FixedPoint>,
    /// Dead point loads.
    #[serde(default)]
    pub point_load: Vec<PointLoad>,
    /// Dead tractions on block boundary faces in a region (addition to v1).
    #[serde(default)]
    pub surface_load: Vec<SurfaceLoad>,
    /// Initial stress.
    #[serde(default)]
    pub in_situ_stress: Option<InSituStress>,
    /// Rock bolts (addition to v1).
    #[serde(default)]
    pub bolt: Vec<Bolt>,
    /// Patterns of bolts, expanded into `bolt` on loading (addition to v1).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bolt_pattern: Vec<BoltPattern>,
    /// A water table (addition to v1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub water: Option<Water>,
    /// Earthquake loading: pseudo-static coefficients and base motion (addition to v1).
    #[serde(default)]
    pub seismic: Seismic,
    /// Stages of a staged analysis (addition to v1); none: one stage of `analysis.duration`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stage: Vec<Stage>,
    /// Monitored quantities.
    #[serde(default)]
    pub monitor: Vec<Monitor>,
    /// Reference values the monitored quantities should reach (addition to v1).
    #[serde(default)]
    pub expect: Vec<Expect>,
    /// A study over many runs (addition to v1): kept as given here and validated and run by the
    /// Python package (`nmm3d study`, `docs/studies.md`); a single run ignores it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<toml::Table>,
}

/// `[scenario]`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    /// Short name.
    #[serde(default)]
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
}
