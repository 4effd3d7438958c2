//! The contact surfaces of a run, and what the stepper asks of its contact points (overlaps,
//! closed pairs, penetration, raising the penalties).

use super::history::ContactHistory;
use super::record::{ContactRecord, ContactState};
use super::surface::ContactPiece;
use crate::error::Problem;
use crate::system::System;

/// The contact surfaces of every block (built from the model) and the seconds spent on them;
/// the points found on them are the run's [`ContactHistory`].
pub struct ContactSurfaces {
    pub(super) pieces: Vec<ContactPiece>,
    /// Seconds spent so far.
    pub times: ContactTimes,
}

/// Seconds spent in the contact phases.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactTimes {
    /// Warning (candidate pairs, including the current geometry of the pieces).
    pub warning: f64,
    /// Detection and transfer.
    pub detection: f64,
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

/// Blocks overlapping deeper than `depth` at the start, as input problems naming the bodies.
pub fn overlap_problems(sys: &System, set: &ContactHistory, depth: f64) -> Vec<Problem> {
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
