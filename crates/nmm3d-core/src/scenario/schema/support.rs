//! Support: rock bolts and cables (addition to v1).

use serde::{Deserialize, Serialize};

/// `[[bolt]]`: an anchored bolt, an axial spring between two material points — its head, in
/// the block it holds, and its anchor, in the rock beyond — with pretension, yield and rupture;
/// or (`grouted`) a fully grouted bolt or cable from `head` (the collar end) to `anchor` (the
/// far end), bonded over its length, reinforcing each joint it crosses.
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
    /// Axial stiffness [N/m] (E A / L of the free length); anchored bolts only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Tension at installation [N] (anchored bolts).
    #[serde(default)]
    pub pretension: f64,
    /// Axial force at which the steel yields [N] (tension and compression); none: elastic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_force: Option<f64>,
    /// Elongation at which it breaks [m] (it then carries nothing); none: it never breaks. A
    /// grouted bolt breaks where a joint it crosses opens this much.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rupture_elongation: Option<f64>,
    /// Grout: the bolt's bar and grout properties (fully grouted bolts and cables).
    #[serde(flatten)]
    pub grout: Grout,
}

/// The keys of a fully grouted bolt or cable ([`Bolt`], [`BoltPattern`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Grout {
    /// Fully grouted from `head` to `anchor` (reinforcement across each joint it crosses).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub grouted: bool,
    /// Axial rigidity E A of the bar [N].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axial_rigidity: Option<f64>,
    /// Shear stiffness of the grout bond per unit length of bar [N/m per m = Pa].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bond_stiffness: Option<f64>,
    /// Shear strength of the grout bond per unit length of bar [N/m]; none: it does not fail.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bond_strength: Option<f64>,
    /// Lateral reaction of the rock and grout on the bar per unit length and unit deflection
    /// [Pa]; none: no dowel action (a cable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub foundation_modulus: Option<f64>,
    /// Bar diameter [m] (its bending rigidity E I = E A d² / 16 for the dowel action).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diameter: Option<f64>,
    /// Shear force across a joint at which the dowel yields [N]; none: elastic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_capacity: Option<f64>,
}

impl Bolt {
    /// The history columns of a bolt.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec![format!("{}.axial_force.value", self.name), format!("{}.elongation.value", self.name)];
        if self.grout.grouted {
            c.push(format!("{}.shear_force.value", self.name));
        }
        c
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
    /// The head of an anchored bolt lies this far into the rock from the collar, inside the held
    /// block [m] (a grouted bar starts at the collar).
    #[serde(default = "head_depth")]
    pub head_depth: f64,
    /// Axial stiffness of each bolt [N/m] (anchored).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<f64>,
    /// Tension at installation [N].
    #[serde(default)]
    pub pretension: f64,
    /// Yield force [N].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yield_force: Option<f64>,
    /// Elongation at rupture [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rupture_elongation: Option<f64>,
    /// Grout of every bolt (grouted patterns).
    #[serde(flatten)]
    pub grout: Grout,
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
        // A grouted bar starts at its collar; an anchored bolt's head lies inside the block.
        let depth = if self.grout.grouted { 0.0 } else { self.head_depth };
        let mut out = Vec::new();
        for i in 0..self.count[0] {
            for j in 0..self.count[1] {
                let collar = [0, 1, 2].map(|k| self.start[k] + i as f64 * self.along[k] + j as f64 * self.across[k]);
                out.push(Bolt {
                    name: format!("{}_{i}_{j}", self.name),
                    head: [0, 1, 2].map(|k| collar[k] + depth * unit[k]),
                    anchor: [0, 1, 2].map(|k| collar[k] + self.length * unit[k]),
                    stiffness: self.stiffness,
                    pretension: self.pretension,
                    yield_force: self.yield_force,
                    rupture_elongation: self.rupture_elongation,
                    grout: self.grout.clone(),
                });
            }
        }
        out
    }
}
