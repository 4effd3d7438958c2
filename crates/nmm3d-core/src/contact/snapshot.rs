//! The mutable part of a contact set as data (checkpoints): the points with their history, the
//! penalties as raised so far, the warning list, the lock and the blocks' travel. The contact surfaces are rebuilt
//! from the model.

use serde::{Deserialize, Serialize};

use super::broad::Warning;
use super::record::{ContactParams, ContactRecord};
use super::set::ContactSet;
use super::travel::{Travel, TravelSnapshot};

/// A [`ContactSet`]'s state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContactSnapshot {
    /// Current contact points.
    pub records: Vec<ContactRecord>,
    /// Penalties and tolerances (raised penalties included).
    pub params: ContactParams,
    /// The candidate pairs and the positions they were built at.
    pub warning: Warning,
    /// Contacts locked (initial equilibrium).
    pub locked: bool,
    /// How far the blocks have moved since each pair was last detected (absent in checkpoints
    /// written before it existed: every pair is detected again at the next detection).
    #[serde(default)]
    pub travel: TravelSnapshot,
    /// Points found overlapping deeper than a detection lets one arise, so far.
    #[serde(default)]
    pub missed_overlaps: u64,
}

impl ContactSet {
    /// The state of the set.
    pub fn snapshot(&self) -> ContactSnapshot {
        ContactSnapshot {
            records: self.records.clone(),
            params: self.params,
            warning: self.warning.clone(),
            locked: self.locked,
            travel: self.travel.snapshot(),
            missed_overlaps: self.missed_overlaps,
        }
    }

    /// Take the state of a snapshot of a set built on the same model.
    pub fn restore(&mut self, s: ContactSnapshot) {
        self.records = s.records;
        self.params = s.params;
        self.warning = s.warning;
        self.locked = s.locked;
        self.travel = Travel::restore(s.travel);
        self.missed_overlaps = s.missed_overlaps;
    }
}
