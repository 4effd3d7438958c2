//! Blocks a static analysis no longer holds: those with a vertex moved beyond
//! `analysis.static_travel_limit` from where it started (`Motion::travel`: the reference
//! configuration, or the initial equilibrium's). A vertex, not a cover: a cover's node may lie
//! a cell away from its block, and a block that tips moves it by the tilt times that lever —
//! on 10 MPa/m joints the tunnel's roof key block, held at 45°, crossed 2 cm by its covers
//! while its centroid moved 14 mm. The model says which they
//! are so that every layer above treats them alike: contact releases them (no points on them),
//! the stepper pins them where they are and leaves their forces out of the unbalanced force.

use nmm3d_geom::Vec3;

use super::System;
use crate::cover::Covers;
use crate::element::loads::weights_at;
use crate::model::Geometry;
use crate::scenario::{AnalysisKind, Scenario};

/// Each block's vertices as its covers move them: (cover, weight) per vertex; for a static
/// analysis with a travel limit, nothing otherwise (or for a fixed block).
pub type TravelPoints = Vec<Vec<Vec<(usize, f64)>>>;

/// The [`TravelPoints`] of a model.
pub(super) fn travel_points(scenario: &Scenario, geometry: &Geometry, covers: &Covers) -> TravelPoints {
    let a = &scenario.analysis;
    if a.kind != AnalysisKind::Static || a.static_travel_limit <= 0.0 {
        return Vec::new();
    }
    let tol = 1e-7 * covers.mesh().size;
    let vertex = |b: usize, x: Vec3| {
        let e = covers.locate(b, &x, tol)?;
        Some(covers.elements[e].covers.iter().copied().zip(weights_at(covers, &covers.elements[e], &x)).collect())
    };
    (geometry.blocks.iter().enumerate())
        .map(|(b, block)| match block.fixed {
            true => Vec::new(),
            false => block.pieces.iter().flat_map(|p| p.vertices()).filter_map(|x| vertex(b, x)).collect(),
        })
        .collect()
}

impl System {
    /// The blocks with a vertex moved beyond the limit (a static analysis with a limit set), with
    /// how far, farthest first (ties by block number); `u`: the covers' travel.
    pub fn beyond_travel_limit(&self, u: &[Vec3]) -> Vec<(usize, f64)> {
        let a = &self.scenario.analysis;
        if a.kind != AnalysisKind::Static || a.static_travel_limit <= 0.0 {
            return Vec::new();
        }
        let moved = |w: &Vec<(usize, f64)>| w.iter().map(|&(c, w)| w * u[c]).sum::<Vec3>().norm();
        let per_block: Vec<f64> = self.travel_points.iter().map(|v| v.iter().map(moved).fold(0.0, f64::max)).collect();
        let mut gone: Vec<(usize, f64)> =
            per_block.into_iter().enumerate().filter(|(_, d)| *d > a.static_travel_limit).collect();
        gone.sort_by(|p, q| q.1.total_cmp(&p.1).then(p.0.cmp(&q.0)));
        gone
    }

    /// Per block, whether it is beyond the travel limit (all `false` without one).
    pub fn released(&self, u: &[Vec3]) -> Vec<bool> {
        let mut out = vec![false; self.geometry.blocks.len()];
        for (b, _) in self.beyond_travel_limit(u) {
            out[b] = true;
        }
        out
    }
}
