//! The bodies' motion: the part of a run's state the elements and the contact points are
//! measured on (the whole state, with the contact history and the stepper's counters, is
//! [`crate::time::State`]).

use std::borrow::Cow;

use nmm3d_geom::{Mat3, Vec3};

use crate::element::bolt::BoltState;
use crate::scenario::AnalysisKind;
use crate::system::System;

/// Time, and the positions, velocities and accelerations of the physical covers, the MEs'
/// co-rotations and the bolts' plastic state.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Motion {
    /// Simulated time [s].
    pub time: f64,
    /// Accepted steps.
    pub step: u64,
    /// Time step to try next [s].
    pub dt: f64,
    /// Displacement of each cover [m]; positions are reference + displacement, kept apart
    /// so that small displacements of far-away blocks keep full precision.
    pub u: Vec<Vec3>,
    /// Velocity of each cover [m/s].
    pub v: Vec<Vec3>,
    /// Acceleration of each cover [m/s²] (used by Newmark with β ≠ ½).
    pub a: Vec<Vec3>,
    /// Co-rotation of each ME (warm start of the polar decomposition).
    #[serde(with = "crate::packed::mat3s")]
    pub rotations: Vec<Mat3>,
    /// Plastic elongation and rupture of each bolt.
    #[serde(default)]
    pub bolts: Vec<BoltState>,
    /// Velocity and displacement of a shaking base (`[seismic]`), which the run's own
    /// displacements are relative to [m/s, m].
    #[serde(default)]
    pub base: [Vec3; 2],
    /// Where a static analysis measures `analysis.static_travel_limit` from: each cover's
    /// displacement at the end of its initial equilibrium or at the start of its stage [m]
    /// (empty: the reference configuration).
    #[serde(default)]
    pub travel_origin: Vec<Vec3>,
}

impl Motion {
    /// The state at t = 0: reference positions and the blocks' initial velocities.
    pub fn initial(sys: &System) -> Self {
        let dynamic = sys.scenario.analysis.kind == AnalysisKind::Dynamic;
        let n = sys.covers.covers.len();
        let v = sys
            .covers
            .covers
            .iter()
            .map(|c| {
                let b = &sys.geometry.blocks[c.block];
                if dynamic && !b.fixed {
                    b.initial_velocity_at(&c.position)
                } else {
                    Vec3::zeros()
                }
            })
            .collect();
        Self {
            time: 0.0,
            step: 0,
            dt: sys.scenario.analysis.dt,
            a: vec![Vec3::zeros(); n],
            u: vec![Vec3::zeros(); n],
            v,
            rotations: vec![Mat3::identity(); sys.covers.elements.len()],
            bolts: vec![BoltState::default(); sys.bolts.len()],
            base: [Vec3::zeros(); 2],
            travel_origin: Vec::new(),
        }
    }

    /// Each cover's displacement since the travel origin [m] (`travel_origin`).
    pub fn travel(&self) -> Cow<'_, [Vec3]> {
        if self.travel_origin.is_empty() {
            return Cow::Borrowed(&self.u);
        }
        Cow::Owned(self.u.iter().zip(&self.travel_origin).map(|(u, o)| u - o).collect())
    }

    /// Displacement of cover `c` [m].
    pub fn displacement(&self, _sys: &System, c: usize) -> Vec3 {
        self.u[c]
    }

    /// Current position of cover `c`'s node [m].
    pub fn position(&self, sys: &System, c: usize) -> Vec3 {
        sys.covers.covers[c].position + self.u[c]
    }
}
