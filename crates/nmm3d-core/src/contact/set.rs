//! All contact points of a run with the surfaces they are found on, and what the stepper asks
//! of them (overlaps, closed pairs, penetration, raising the penalties).

use super::broad::Warning;
use super::record::{ContactParams, ContactRecord, ContactState};
use super::surface::ContactPiece;
use super::travel::Travel;
use crate::error::Problem;
use crate::system::System;

/// All contact surfaces and the current contact points.
pub struct ContactSet {
    pub(super) pieces: Vec<ContactPiece>,
    /// Current contact points.
    pub records: Vec<ContactRecord>,
    /// Penalties and tolerances.
    pub params: ContactParams,
    /// The warning (candidate pair) list.
    pub warning: Warning,
    /// Seconds spent so far.
    pub times: ContactTimes,
    /// Closed points stay closed and stuck whatever the force (initial equilibrium).
    pub locked: bool,
    /// Block pairs of the points that changed state in the last open–close iteration.
    pub last_changes: Vec<(usize, usize)>,
    /// How far the blocks have moved since each pair was last detected.
    pub travel: Travel,
    /// Points found overlapping deeper than a detection lets one arise (bounded, see
    /// `transfer::bound_missed_overlap`).
    pub missed_overlaps: u64,
}

/// Seconds spent in the contact phases.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactTimes {
    /// Warning (candidate pairs, including the current geometry of the pieces).
    pub warning: f64,
    /// Detection and transfer.
    pub detection: f64,
}

impl ContactSet {
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

/// Blocks overlapping deeper than `depth` at the start, as input problems naming the bodies.
pub fn overlap_problems(sys: &System, set: &ContactSet, depth: f64) -> Vec<Problem> {
    let mut seen = std::collections::BTreeSet::new();
    set.overlaps(depth)
        .filter(|r| seen.insert(r.blocks))
        .map(|r| {
            let name = |b: usize| &sys.scenario.body[sys.geometry.blocks[b].body].name;
            let x = r.a.reference;
            Problem {
                path: format!("body.{}", name(r.blocks.0)),
                reason: format!(
                    "block {} of body '{}' overlaps block {} of body '{}' by {:.3e} m at ({:.4}, {:.4}, {:.4}) (allowed {:.1e} m)",
                    r.blocks.0, name(r.blocks.0), r.blocks.1, name(r.blocks.1), -(r.gap0 + r.offset), x.x, x.y, x.z, depth
                ),
            }
        })
        .collect()
}
