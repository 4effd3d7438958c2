//! Blocks a static analysis no longer holds: those that moved beyond
//! `analysis.static_travel_limit` from the reference configuration. Their forces leave the
//! unbalanced force, so a static run can stop once the other blocks are in equilibrium — a
//! verdict for every block from one run, without following a failing one down its slope.

use std::borrow::Cow;

use nmm3d_geom::Vec3;

use crate::scenario::AnalysisKind;
use crate::system::System;

/// The blocks whose covers moved beyond the limit (a static analysis with a limit set), with
/// how far, farthest first (ties by block number).
pub fn beyond_limit(sys: &System, u: &[Vec3]) -> Vec<(usize, f64)> {
    let a = &sys.scenario.analysis;
    if a.kind != AnalysisKind::Static || a.static_travel_limit <= 0.0 {
        return Vec::new();
    }
    let mut per_block = vec![0.0_f64; sys.geometry.blocks.len()];
    for (c, d) in u.iter().enumerate() {
        let b = sys.covers.covers[c].block;
        per_block[b] = per_block[b].max(d.norm());
    }
    let mut gone: Vec<(usize, f64)> =
        per_block.into_iter().enumerate().filter(|(_, d)| *d > a.static_travel_limit).collect();
    gone.sort_by(|p, q| q.1.total_cmp(&p.1).then(p.0.cmp(&q.0)));
    gone
}

/// Per-cover forces `f` without those on the covers of blocks beyond the limit.
pub(super) fn of_held<'a>(sys: &System, u: &[Vec3], f: &'a [Vec3]) -> Cow<'a, [Vec3]> {
    let gone = beyond_limit(sys, u);
    if gone.is_empty() {
        return Cow::Borrowed(f);
    }
    let mut out = f.to_vec();
    for (c, x) in out.iter_mut().enumerate() {
        if gone.iter().any(|(b, _)| *b == sys.covers.covers[c].block) {
            *x = Vec3::zeros();
        }
    }
    Cow::Owned(out)
}
