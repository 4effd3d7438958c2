//! Support: rock bolts and cables (addition to v1).

use serde::{Deserialize, Serialize};

/// `[[bolt]]`: an anchored bolt, an axial spring between two material points — its head, in
/// the block it holds, and its anchor, in the rock beyond — with pretension, yield and rupture.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bolt {
    /// Unique name; history columns `<name>.axial_force.value` [N] and
    /// `<name>.elongation.value` [m].
    pub name: String,
    /// Head: a point inside the held block [m].
    pub head: [f64; 3],
    /// Anchor: a point inside the rock the bolt is anchored in [m].
    pub anchor: [f64; 3],
    /// Axial stiffness [N/m] (E A / L of the free length).
    pub stiffness: f64,
    /// Tension at installation [N].
    #[serde(default)]
    pub pretension: f64,
    /// Axial force at which the steel yields [N] (tension and compression); none: elastic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_force: Option<f64>,
    /// Elongation at which it breaks [m] (it then carries nothing); none: it never breaks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rupture_elongation: Option<f64>,
}

impl Bolt {
    /// The history columns of a bolt.
    pub fn columns(&self) -> [String; 2] {
        [format!("{}.axial_force.value", self.name), format!("{}.elongation.value", self.name)]
    }
}

/// `[[bolt_pattern]]`: a grid of equal bolts over a face (addition to v1), expanded into
/// `[[bolt]]` entries named `<name>_<i>_<j>` when the scenario is loaded.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoltPattern {
    /// Prefix of the bolts' names.
    pub name: String,
    /// Collar of bolt (0, 0): a point on the face [m].
    pub start: [f64; 3],
    /// From one collar to the next along the excavation [m] (its length is the spacing).
    pub along: [f64; 3],
    /// From one collar to the next across [m].
    #[serde(default)]
    pub across: [f64; 3],
    /// Bolts along and across.
    pub count: [usize; 2],
    /// Direction of the bolts, into the rock (normalised here).
    pub direction: [f64; 3],
    /// Collar to anchor [m].
    pub length: f64,
    /// The head lies this far into the rock from the collar, inside the held block [m].
    #[serde(default = "head_depth")]
    pub head_depth: f64,
    /// Axial stiffness of each bolt [N/m].
    pub stiffness: f64,
    /// Tension at installation [N].
    #[serde(default)]
    pub pretension: f64,
    /// Yield force [N].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_force: Option<f64>,
    /// Elongation at rupture [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rupture_elongation: Option<f64>,
}

fn head_depth() -> f64 {
    0.05
}

impl BoltPattern {
    /// The bolts of the pattern (a zero direction gives no bolts; validation names it).
    pub fn bolts(&self) -> Vec<Bolt> {
        let d = self.direction;
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(n > 0.0) {
            return Vec::new();
        }
        let unit = d.map(|x| x / n);
        let mut out = Vec::new();
        for i in 0..self.count[0] {
            for j in 0..self.count[1] {
                let collar = [0, 1, 2].map(|k| self.start[k] + i as f64 * self.along[k] + j as f64 * self.across[k]);
                out.push(Bolt {
                    name: format!("{}_{i}_{j}", self.name),
                    head: [0, 1, 2].map(|k| collar[k] + self.head_depth * unit[k]),
                    anchor: [0, 1, 2].map(|k| collar[k] + self.length * unit[k]),
                    stiffness: self.stiffness,
                    pretension: self.pretension,
                    yield_force: self.yield_force,
                    rupture_elongation: self.rupture_elongation,
                });
            }
        }
        out
    }
}
