//! The mutable state of a run: cheap to clone (rejected steps, checkpoints).

use nmm3d_geom::{Mat3, Vec3};

use crate::scenario::AnalysisKind;
use crate::system::System;

/// Positions, velocities and accelerations of the physical covers, and time.
#[derive(Debug, Clone)]
pub struct State {
    /// Simulated time [s].
    pub time: f64,
    /// Accepted steps.
    pub step: u64,
    /// Time step to try next [s].
    pub dt: f64,
    /// Current position of each cover's node [m] (reference + displacement).
    pub x: Vec<Vec3>,
    /// Velocity of each cover [m/s].
    pub v: Vec<Vec3>,
    /// Acceleration of each cover [m/s²] (used by Newmark with β ≠ ½).
    pub a: Vec<Vec3>,
    /// Co-rotation of each ME (warm start of the polar decomposition).
    pub rotations: Vec<Mat3>,
}

impl State {
    /// The state at t = 0: reference positions and the blocks' initial velocities.
    pub fn initial(sys: &System) -> Self {
        let dynamic = sys.scenario.analysis.kind == AnalysisKind::Dynamic;
        let x: Vec<Vec3> = sys.covers.covers.iter().map(|c| c.position).collect();
        let v = sys
            .covers
            .covers
            .iter()
            .map(|c| {
                let b = &sys.geometry.blocks[c.block];
                if dynamic && !b.fixed { b.initial_velocity_at(&c.position) } else { Vec3::zeros() }
            })
            .collect();
        Self {
            time: 0.0,
            step: 0,
            dt: sys.scenario.analysis.dt,
            a: vec![Vec3::zeros(); x.len()],
            x,
            v,
            rotations: vec![Mat3::identity(); sys.covers.elements.len()],
        }
    }

    /// Displacement of cover `c` [m].
    pub fn displacement(&self, sys: &System, c: usize) -> Vec3 {
        self.x[c] - sys.covers.covers[c].position
    }
}
