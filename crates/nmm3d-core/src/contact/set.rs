//! The contact surfaces of a run (the pieces every block is detected on, and the seconds spent
//! on them), and the blocks found overlapping at the start as input problems.

use super::history::ContactHistory;
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
