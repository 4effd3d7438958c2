//! The mutable part of a contact set as data (checkpoints): the points with their history, the
//! penalties as raised so far, the warning list and the lock. The contact surfaces are rebuilt
//! from the model.

use serde::{Deserialize, Serialize};

use super::broad::Warning;
use super::record::{ContactParams, ContactRecord};
use super::set::ContactSet;

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
}

impl ContactSet {
    /// The state of the set.
    pub fn snapshot(&self) -> ContactSnapshot {
        ContactSnapshot {
            records: self.records.clone(),
            params: self.params,
            warning: self.warning.clone(),
            locked: self.locked,
        }
    }

    /// Take the state of a snapshot of a set built on the same model.
    pub fn restore(&mut self, s: ContactSnapshot) {
        self.records = s.records;
        self.params = s.params;
        self.warning = s.warning;
        self.locked = s.locked;
    }
}
