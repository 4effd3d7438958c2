//! Blocks a static analysis no longer holds: those whose covers moved beyond
//! `analysis.static_travel_limit` from the reference configuration. The model says which they
//! are so that every layer above treats them alike: contact releases them (no points on them),
//! the stepper pins them where they are and leaves their forces out of the unbalanced force.

use nmm3d_geom::Vec3;

use super::System;
use crate::scenario::AnalysisKind;

impl System {
    /// The blocks whose covers moved beyond the limit (a static analysis with a limit set), with
    /// how far, farthest first (ties by block number).
    pub fn beyond_travel_limit(&self, u: &[Vec3]) -> Vec<(usize, f64)> {
        let a = &self.scenario.analysis;
        if a.kind != AnalysisKind::Static || a.static_travel_limit <= 0.0 {
            return Vec::new();
        }
        let mut per_block = vec![0.0_f64; self.geometry.blocks.len()];
        for (c, d) in u.iter().enumerate() {
            let b = self.covers.covers[c].block;
            per_block[b] = per_block[b].max(d.norm());
        }
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
