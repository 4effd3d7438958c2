//! `[[stage]]` (addition to v1): a staged analysis. The stages run one after the other on one
//! rock mass, the state carried across: each may excavate (remove the rock of named
//! excavations), install named bolts, and change strengths and loads (`set`, addressed like
//! `--set`), then runs for its duration or to equilibrium.

use serde::{Deserialize, Serialize};

use super::Scenario;

/// One stage.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stage {
    /// Unique name (outputs name the stage by it).
    pub name: String,
    /// Simulated time the stage runs [s] (at most: see `equilibrium`).
    pub duration: f64,
    /// End the stage early once the unbalanced-force ratio falls to
    /// `analysis.equilibrium_tolerance` (a static analysis always does).
    #[serde(default)]
    pub equilibrium: bool,
    /// Named `[[excavation]]`s removed at the stage's start (until then their rock is in place).
    #[serde(default)]
    pub excavate: Vec<String>,
    /// `[[bolt]]` or `[[bolt_pattern]]` names installed at the stage's start, unstressed in the
    /// displaced rock (until then they are absent).
    #[serde(default)]
    pub install: Vec<String>,
    /// Changes from this stage on, `KEY = VALUE` as `--set` takes them (strengths, loads, water,
    /// earthquake, materials' elastic constants, analysis controls).
    #[serde(default)]
    pub set: toml::Table,
}

/// The top-level tables a stage may change: strengths, loads and controls, never the geometry
/// (bodies, joints' planes, excavations' shapes, the cover) the state is carried on.
pub const STAGE_SETTABLE: [&str; 9] =
    ["joint", "interface", "material", "water", "seismic", "point_load", "surface_load", "bolt", "analysis"];

impl Scenario {
    /// Whether the scenario is a staged analysis.
    pub fn staged(&self) -> bool {
        !self.stage.is_empty()
    }

    /// The stage that removes excavation `e`, if one does.
    pub fn excavating_stage(&self, e: usize) -> Option<usize> {
        let name = self.excavation[e].name.as_ref()?;
        self.stage.iter().position(|s| s.excavate.contains(name))
    }

    /// Which excavations are open during stage `k`: those no stage names, and those a stage up
    /// to `k` removes.
    pub fn open_excavations(&self, k: usize) -> Vec<bool> {
        (0..self.excavation.len()).map(|e| self.excavating_stage(e).is_none_or(|j| j <= k)).collect()
    }

    /// The scenario stage `k` runs: this one with the `set`s of the stages up to `k` applied, the
    /// bolts of later stages left out, no stages of its own. `Err((key path, reason))`.
    pub fn at_stage(&self, k: usize) -> Result<Scenario, (String, String)> {
        let mut s = self.clone();
        s.stage.clear();
        let later: Vec<&String> = self.stage.iter().skip(k + 1).flat_map(|st| &st.install).collect();
        s.bolt.retain(|b| !later.contains(&&b.name));
        let sets: Vec<(&String, &String, &toml::Value)> =
            self.stage[..=k].iter().flat_map(|st| st.set.iter().map(move |(key, v)| (&st.name, key, v))).collect();
        if sets.is_empty() {
            return Ok(s);
        }
        let mut tree = toml::Value::try_from(&s).map_err(|e| ("stage".to_string(), e.to_string()))?;
        for (stage, key, v) in sets {
            let at = format!("stage.{stage}.set.{key}");
            if !STAGE_SETTABLE.contains(&key.split('.').next().unwrap_or("")) {
                return Err((at, format!("a stage can change only {}", STAGE_SETTABLE.join(", "))));
            }
            super::super::overrides::set(&mut tree, key, v.clone()).map_err(|(_, r)| (at, r))?;
        }
        serde_path_to_error::deserialize(tree).map_err(|e| (e.path().to_string(), e.inner().message().to_string()))
    }
}
