//! How far each block has moved since each pair of blocks was last detected: the bound that lets
//! detection skip the pairs whose blocks have not moved (a pile in which most blocks rest while
//! a few slide over them).
//!
//! A material point's displacement is the weighted mean of its covers' (the weights are
//! non-negative and sum to one), so it is at most the largest displacement among its block's
//! covers. A pair whose two blocks have together moved less than the contact tolerance since
//! its last detection cannot have come within the detection margin (twice the tolerance) of a
//! touch it did not have: its points are kept, re-measured, as the stepper keeps every point
//! while nothing at all has moved that far.

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use nmm3d_geom::Vec3;

use crate::system::System;

/// Distance run per block and where each pair was last detected (serialised as a
/// [`TravelSnapshot`]: pairs sorted, so equal travels give equal files).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(from = "TravelSnapshot", into = "TravelSnapshot")]
pub struct Travel {
    /// Per block: the sum over accepted steps of its largest cover displacement [m].
    odometer: Vec<f64>,
    /// Per pair of blocks: the two odometers at its last detection.
    seen: FxHashMap<(usize, usize), (f64, f64)>,
}

/// A [`Travel`] as data, pairs sorted.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TravelSnapshot {
    odometer: Vec<f64>,
    seen: Vec<((usize, usize), (f64, f64))>,
}

impl Travel {
    /// Every block's largest cover displacement in `d` [m].
    pub fn per_block(sys: &System, d: &[Vec3]) -> Vec<f64> {
        let mut out = vec![0.0; sys.geometry.blocks.len()];
        for (c, d) in sys.covers.covers.iter().zip(d) {
            out[c.block] = f64::max(out[c.block], d.norm());
        }
        out
    }

    /// Add an accepted step's displacements `d`.
    pub fn add(&mut self, sys: &System, d: &[Vec3]) {
        let moved = Self::per_block(sys, d);
        self.odometer.resize(moved.len(), 0.0);
        self.odometer.iter_mut().zip(moved).for_each(|(o, m)| *o += m);
    }

    /// How far the blocks of `pair` have moved together since it was last detected, plus
    /// `extra` per block (a trial's displacement) [m]; infinite for a pair never detected.
    pub fn since(&self, pair: (usize, usize), extra: Option<&[f64]>) -> f64 {
        let Some(&(a, b)) = self.seen.get(&pair) else { return f64::INFINITY };
        let now = |k: usize| self.odometer.get(k).copied().unwrap_or(0.0) + extra.map_or(0.0, |e| e[k]);
        (now(pair.0) - a) + (now(pair.1) - b)
    }

    /// `pair` detected now.
    pub fn mark(&mut self, pair: (usize, usize)) {
        let at = |k: usize| self.odometer.get(k).copied().unwrap_or(0.0);
        let _ = self.seen.insert(pair, (at(pair.0), at(pair.1)));
    }

    /// Forget the pairs not in `keep` (no longer candidates: far apart).
    pub fn retain(&mut self, keep: impl Fn(&(usize, usize)) -> bool) {
        self.seen.retain(|p, _| keep(p));
    }
}

impl From<Travel> for TravelSnapshot {
    fn from(t: Travel) -> Self {
        let mut seen: Vec<_> = t.seen.into_iter().collect();
        seen.sort_unstable_by_key(|x| x.0);
        Self { odometer: t.odometer, seen }
    }
}

impl From<TravelSnapshot> for Travel {
    fn from(s: TravelSnapshot) -> Self {
        Self { odometer: s.odometer, seen: s.seen.into_iter().collect() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_has_moved_by_what_its_two_blocks_ran_since_it_was_seen() {
        let mut t = Travel { odometer: vec![0.0, 0.0, 0.0], ..Travel::default() };
        assert_eq!(t.since((0, 1), None), f64::INFINITY, "never detected");
        t.mark((0, 1));
        t.odometer = vec![0.5, 0.25, 4.0];
        assert_eq!(t.since((0, 1), None), 0.75);
        assert_eq!(t.since((0, 1), Some(&[0.125, 0.0, 9.0])), 0.875);
        t.mark((0, 1));
        assert_eq!(t.since((0, 1), None), 0.0);
        t.retain(|_| false);
        assert_eq!(t.since((0, 1), None), f64::INFINITY);
        let text = serde_json::to_string(&t).unwrap();
        assert_eq!(serde_json::from_str::<Travel>(&text).unwrap(), t);
    }
}
