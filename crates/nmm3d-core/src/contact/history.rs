//! The contact history of a run: the points with their springs, states and bonds, the
//! penalties as raised so far, the candidate pairs, the lock and the blocks' travel — the part
//! of the run's state that contact adds (the surfaces it is detected on are rebuilt from the
//! model, [`super::ContactSurfaces`]).

use serde::{Deserialize, Serialize};

use super::broad::Warning;
use super::record::{ContactParams, ContactRecord};
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
        }
    }
}
