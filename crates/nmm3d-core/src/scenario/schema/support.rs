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
