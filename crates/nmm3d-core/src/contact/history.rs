//! The contact history of a run: the points with their springs, states and bonds, the
//! penalties as raised so far, the candidate pairs, the lock and the blocks' travel — the part
//! of the run's state that contact adds (the surfaces it is detected on are rebuilt from the
//! model, [`super::ContactSurfaces`]) — and what the stepper asks of it (overlaps, closed
//! pairs, penetration, raising the penalties).

use serde::{Deserialize, Serialize};

use super::broad::Warning;
use super::record::{ContactParams, ContactRecord, ContactState};
use super::travel::Travel;

/// The contact points and what they carry from step to step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactHistory {
    /// Current contact points.
    pub records: Vec<ContactRecord>,
    /// Penalties and tolerances (raised penalties included).
    pub params: ContactParams,
    /// The candidate pairs and the positions they were built at.
    pub warning: Warning,
    /// Closed points stay closed and stuck whatever the force (initial equilibrium).
    pub locked: bool,
    /// How far the blocks have moved since each pair was last detected (absent in checkpoints
    /// written before it existed: every pair is detected again at the next detection).
    #[serde(default)]
    pub travel: Travel,
    /// Points found overlapping deeper than a detection lets one arise, so far (bounded, see
    /// `transfer::bound_missed_overlap`).
    #[serde(default)]
    pub missed_overlaps: u64,
    /// Joint pairs found again whose points were lifted to push no harder than before, and
    /// arrivals lifted to push from where they were at the step's start (`joint_force`), so far.
    #[serde(default)]
    pub carried_forces: u64,
}

impl ContactHistory {
    /// No points yet, with penalties and tolerances `params`.
    pub fn new(params: ContactParams) -> Self {
        Self {
            records: Vec::new(),
            params,
            warning: Warning::default(),
            locked: false,
            travel: Travel::default(),
            missed_overlaps: 0,
            carried_forces: 0,
        }
    }
}

impl ContactHistory {
    /// Points overlapping deeper than `depth` [m].
    pub fn overlaps(&self, depth: f64) -> impl Iterator<Item = &ContactRecord> {
        self.records.iter().filter(move |r| r.gap0 + r.offset < -depth)
    }

    /// Pairs of MEs (lower first) with a closed point, sorted, each once.
    pub fn closed_pairs(&self) -> Vec<(usize, usize)> {
        let mut pairs: Vec<_> =
            self.records.iter().filter(|r| r.state != ContactState::Open).map(ContactRecord::element_pair).collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }

    /// Whether some point is closed (its springs are in the system matrix).
    pub fn any_closed(&self) -> bool {
        self.records.iter().any(|r| r.state != ContactState::Open)
    }

    /// Multiply every penalty by `factor` (new points too), keeping the shear springs' forces.
    pub fn stiffen(&mut self, factor: f64) {
        self.params.kn *= factor;
        self.params.ks *= factor;
        self.records.iter_mut().for_each(|r| r.stiffen(factor));
    }

    /// Whether a closed point's spring is compressed by more than `depth` [m] and more than at
    /// the start of the step: the overlap is growing beyond the allowed depth (what a raise of
    /// the penalty moved into the zero level is not counted again). (A point found already deeper — a
    /// corner that came in during the last step without a point, detected now — is being pushed
    /// out; no smaller step can undo an overlap that is there at the start.)
    pub fn overlap_growing_beyond(&self, depth: f64) -> bool {
        self.records
            .iter()
            .any(|r| r.state != ContactState::Open && !r.joint_stiffness && -r.gap > depth && r.gap < r.gap0)
    }

    /// Largest penetration among closed points [m].
    pub fn max_penetration(&self) -> f64 {
        self.records.iter().filter(|r| r.state != ContactState::Open).map(|r| -(r.gap + r.raised)).fold(0.0, f64::max)
    }
}
