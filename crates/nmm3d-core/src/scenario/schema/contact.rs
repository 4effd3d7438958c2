//! `[contact]`: the contact springs (a stiffness or "auto"), friction and detection controls.

use serde::{Deserialize, Serialize};

/// A stiffness [N/m] or "auto".
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Stiffness {
    /// Chosen from the model (documented per key).
    #[default]
    Auto,
    /// Given value [N/m].
    Value(f64),
}

impl Serialize for Stiffness {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Stiffness::Auto => s.serialize_str("auto"),
            Stiffness::Value(v) => s.serialize_f64(*v),
        }
    }
}

impl<'de> Deserialize<'de> for Stiffness {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Num(f64),
            Int(i64),
            Text(String),
        }
        match Raw::deserialize(d)? {
            Raw::Num(v) => Ok(Stiffness::Value(v)),
            Raw::Int(v) => Ok(Stiffness::Value(v as f64)),
            Raw::Text(t) if t == "auto" => Ok(Stiffness::Auto),
            Raw::Text(t) => Err(serde::de::Error::custom(format!("expected a number or \"auto\", found \"{t}\""))),
        }
    }
}

/// `[contact]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactSpec {
    /// Contact between blocks (addition; `false` lets blocks pass through each other, for
    /// continuum checks).
    pub enabled: bool,
    /// Normal penalty [N/m] or "auto".
    pub normal_stiffness: Stiffness,
    /// Shear penalty [N/m] or "auto".
    pub shear_stiffness: Stiffness,
    /// Largest contact overlap allowed at the end of a step, as a fraction of the cover size;
    /// beyond it the step is cut (addition) [-].
    pub max_penetration_ratio: f64,
    /// "auto" normal penalty = this × largest Young's modulus × cover size [-] (addition).
    pub auto_penalty_factor: f64,
    /// Support tolerance of the detection as a fraction of the cover size; a new point takes the
    /// history of a previous one within 10 × this [-] (addition).
    pub tolerance_ratio: f64,
    /// Skin of the warning (candidate pair) list as a multiple of the detection margin [-]
    /// (addition).
    pub warning_skin: f64,
    /// A dynamic step detects within tolerance + 2 × this × the reach its start predicts
    /// (|v| Δt + (|a| + |g|) Δt², `time/reach.rs`), at most within the full margin [-] (addition).
    pub reach_safety: f64,
    /// Blocks overlapping deeper than this fraction of the cover size at the start are invalid
    /// input [-] (addition).
    pub overlap_tolerance: f64,
    /// Factor on the penalties when a contact overlaps beyond `max_penetration_ratio` [-]
    /// (addition).
    pub penalty_raise: f64,
    /// Largest number of such raises in a run (addition).
    pub max_penalty_raises: u32,
    /// Half-width of the open–close hysteresis on the gap, as a fraction of the cover size [-]
    /// (addition).
    pub gap_band: f64,
    /// Overlap, as a fraction of the support tolerance, at which a point that opened during a
    /// step's open–close iterations closes again [-] (addition).
    pub reclose_depth: f64,
    /// Closings of a point within one step's open–close iterations after which it stays open,
    /// unless it overlaps beyond the support tolerance (addition).
    pub max_reclose: u32,
    /// Rounds per step of lagged verification: detection on a trial's end configuration adds
    /// the points that arrived during the step unseen, and the step is solved again (0: off)
    /// (addition).
    pub arrival_rounds: u32,
    /// Change of a sliding point's friction force between two open–close iterations, relative
    /// to the largest friction limit, that counts as settled (about a 1° turn) [-] (addition).
    pub slip_turn: f64,
    /// A new point whose gap is below this fraction of the support tolerance is touching
    /// (closed) [-] (addition).
    pub touching: f64,
    /// Smallest stiffness share of a point of an area contact (its area over a cover cell's
    /// face) [-] (addition).
    pub min_area_share: f64,
    /// Facet-overlay corners closer than this × the support tolerance are one point [-]
    /// (addition).
    pub merge_ratio: f64,
    /// Contact dashpots: fraction of critical damping of each block pair's normal mode on its
    /// closed points (0: none; the springs then lose energy only by friction and by the time
    /// scheme) [-] (addition).
    pub damping_ratio: f64,
    /// A contact facet that reaches out of the detection band takes part with its part inside
    /// it when it faces the contact plane within this angle (0: off — only facets wholly in the
    /// band) [°] (addition).
    pub turned_face_angle: f64,
    /// In a dynamic run and in the frictional initial equilibrium, a joint pair on its own
    /// stiffness found again pushing harder than its points did pushes only as hard (its normal
    /// force carried across the detection, as 3DEC's incremental one is); in a dynamic run a
    /// point arriving within a step deeper than the transfer distance pushes from there; false:
    /// the total force of the points as found (addition).
    pub carry_joint_force: bool,
    /// In a static analysis, with `carry_joint_force`, a pair found again is lifted only to push
    /// at most this fraction more than its points did [-] (addition). A static answer is the
    /// total force's, and a joint closing smoothly is found again within a percent of its force
    /// (the eccentric footing beyond its kern: at most 0.8 %; lifted even by that it settled
    /// 3.0 % off the closed form instead of 1.4 %); a turned face found again is a jump (the
    /// thesis tunnel on 1 MPa/m: half of the lifts above 7 %, a tenth above 430 %), and taken
    /// whole such jumps keep the static iterates from settling (`docs/theory/contact.md`,
    /// *Static analyses on soft joints*).
    pub static_carry_slack: f64,
}

impl Default for ContactSpec {
    fn default() -> Self {
        Self {
            enabled: true,
            normal_stiffness: Stiffness::Auto,
            shear_stiffness: Stiffness::Auto,
            max_penetration_ratio: 0.01,
            auto_penalty_factor: 10.0,
            tolerance_ratio: 1e-3,
            warning_skin: 2.0,
            reach_safety: 4.0,
            overlap_tolerance: 1e-3,
            penalty_raise: 10.0,
            max_penalty_raises: 3,
            gap_band: 1e-10,
            reclose_depth: 1e-3,
            max_reclose: 2,
            arrival_rounds: 3,
            slip_turn: 0.017_45,
            touching: 1e-3,
            min_area_share: 0.05,
            merge_ratio: 10.0,
            damping_ratio: 0.0,
            turned_face_angle: 0.0,
            carry_joint_force: true,
            static_carry_slack: 0.05,
        }
    }
}
