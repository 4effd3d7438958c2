//! How far each pair of blocks has moved against each other since it was last detected: the
//! bound that lets detection skip the pairs whose relative position has not changed (a pile in
//! which most blocks rest while a few slide over them; a layer of blocks sliding down a slope
//! together).
//!
//! A material point's displacement is the weighted mean of its covers' (the weights are
//! non-negative and sum to one). Per step, write each cover's displacement as its block's mean
//! cover displacement t plus a deviation e, |e| ≤ s (the block's spread). Since a pair's last
//! detection, any point of A has then moved by ΣtA plus at most ΣsA, any point of B by ΣtB plus
//! at most ΣsB: their relative position has changed by at most |ΣtA − ΣtB| + ΣsA + ΣsB — and by
//! at most the two blocks' run distances (the sums of their largest cover displacements), the
//! smaller of the two bounds counting. A pair whose relative position has changed by less than
//! the contact tolerance cannot have come within the detection margin (twice the tolerance) of
//! a touch it did not have: its points are kept, re-measured, as the stepper keeps every point
//! while nothing at all has moved that far.

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use nmm3d_geom::Vec3;

use crate::system::System;

/// One block's motion over a step or a trial.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BlockMove {
    /// Its largest cover displacement [m].
    pub largest: f64,
    /// The mean of its covers' displacements [m].
    pub mean: Vec3,
    /// The largest distance of a cover's displacement from that mean [m].
    pub spread: f64,
}

/// Per block, the sums over accepted steps of its [`BlockMove`]s, and where each pair was last
/// detected (serialised as a [`TravelSnapshot`]: pairs sorted, so equal travels give equal files).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(from = "TravelSnapshot", into = "TravelSnapshot")]
pub struct Travel {
    /// Per block: the sum of its largest cover displacements [m].
    odometer: Vec<f64>,
    /// Per block: the sum of its mean cover displacements [m].
    drift: Vec<Vec3>,
    /// Per block: the sum of its spreads [m].
    spread: Vec<f64>,
    /// Per pair of blocks: the sums at its last detection.
    seen: FxHashMap<(usize, usize), Seen>,
}

/// The two blocks' (drift, spread) when a pair was detected.
type Relative = ((Vec3, f64), (Vec3, f64));

/// The two blocks' odometers when a pair was detected, and their [`Relative`] (`None` in a
/// checkpoint written before it was kept).
type Seen = ((f64, f64), Option<Relative>);

/// A [`Travel`] as data, pairs sorted.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TravelSnapshot {
    odometer: Vec<f64>,
    seen: Vec<((usize, usize), (f64, f64))>,
    #[serde(default)]
    drift: Vec<Vec3>,
    #[serde(default)]
    spread: Vec<f64>,
    /// Each pair's relative part of [`Seen`], where kept.
    #[serde(default)]
    seen_relative: Vec<((usize, usize), Relative)>,
}

impl Travel {
    /// Every block's motion by the cover displacements `d` [m].
    pub fn per_block(sys: &System, d: &[Vec3]) -> Vec<BlockMove> {
        let n = sys.geometry.blocks.len();
        let (mut out, mut count) = (vec![BlockMove::default(); n], vec![0usize; n]);
        for (c, d) in sys.covers.covers.iter().zip(d) {
            let m = &mut out[c.block];
            m.largest = m.largest.max(d.norm());
            m.mean += d;
            count[c.block] += 1;
        }
        for (m, k) in out.iter_mut().zip(&count) {
            m.mean /= (*k).max(1) as f64;
        }
        for (c, d) in sys.covers.covers.iter().zip(d) {
            let m = &mut out[c.block];
            m.spread = m.spread.max((d - m.mean).norm());
        }
        out
    }

    /// Add an accepted step's displacements `d`.
    pub fn add(&mut self, sys: &System, d: &[Vec3]) {
        let moved = Self::per_block(sys, d);
        self.odometer.resize(moved.len(), 0.0);
        self.drift.resize(moved.len(), Vec3::zeros());
        self.spread.resize(moved.len(), 0.0);
        for (k, m) in moved.iter().enumerate() {
            self.odometer[k] += m.largest;
            self.drift[k] += m.mean;
            self.spread[k] += m.spread;
        }
    }

    /// How far the blocks of `pair` have moved against each other since it was last detected,
    /// with `extra` per block (a trial's motion) [m]; infinite for a pair never detected.
    pub fn since(&self, pair: (usize, usize), extra: Option<&[BlockMove]>) -> f64 {
        let Some(&((a, b), relative)) = self.seen.get(&pair) else { return f64::INFINITY };
        let more = |k: usize| extra.and_then(|e| e.get(k)).copied().unwrap_or_default();
        let run = |k: usize| self.odometer.get(k).copied().unwrap_or(0.0) + more(k).largest;
        let apart = (run(pair.0) - a) + (run(pair.1) - b);
        let Some(((ta, sa), (tb, sb))) = relative else { return apart };
        let drift = |k: usize| self.drift.get(k).copied().unwrap_or_else(Vec3::zeros) + more(k).mean;
        let spread = |k: usize| self.spread.get(k).copied().unwrap_or(0.0) + more(k).spread;
        let together =
            ((drift(pair.0) - ta) - (drift(pair.1) - tb)).norm() + (spread(pair.0) - sa) + (spread(pair.1) - sb);
        apart.min(together)
    }

    /// `pair` detected now.
    pub fn mark(&mut self, pair: (usize, usize)) {
        let at = |k: usize| {
            let o = self.odometer.get(k).copied().unwrap_or(0.0);
            (o, (self.drift.get(k).copied().unwrap_or_else(Vec3::zeros), self.spread.get(k).copied().unwrap_or(0.0)))
        };
        let ((oa, ra), (ob, rb)) = (at(pair.0), at(pair.1));
        let _ = self.seen.insert(pair, ((oa, ob), Some((ra, rb))));
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
        let seen_relative = seen.iter().filter_map(|(p, (_, r))| r.map(|r| (*p, r))).collect();
        let seen = seen.into_iter().map(|(p, (o, _))| (p, o)).collect();
        Self { odometer: t.odometer, seen, drift: t.drift, spread: t.spread, seen_relative }
    }
}

impl From<TravelSnapshot> for Travel {
    fn from(s: TravelSnapshot) -> Self {
        let relative: FxHashMap<_, _> = s.seen_relative.into_iter().collect();
        let seen = s.seen.into_iter().map(|(p, o)| (p, (o, relative.get(&p).copied()))).collect();
        Self { odometer: s.odometer, drift: s.drift, spread: s.spread, seen }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A travel of three blocks after steps whose per-block motions are given directly.
    fn after(steps: &[[BlockMove; 3]]) -> Travel {
        let mut t =
            Travel { odometer: vec![0.0; 3], drift: vec![Vec3::zeros(); 3], spread: vec![0.0; 3], ..Travel::default() };
        for step in steps {
            for (k, m) in step.iter().enumerate() {
                t.odometer[k] += m.largest;
                t.drift[k] += m.mean;
                t.spread[k] += m.spread;
            }
        }
        t
    }

    fn shift(x: f64, spread: f64) -> BlockMove {
        BlockMove { largest: x.abs() + spread, mean: Vec3::new(x, 0.0, 0.0), spread }
    }

    #[test]
    fn a_pair_has_moved_by_its_blocks_relative_motion_since_it_was_seen() {
        let mut t = after(&[]);
        assert_eq!(t.since((0, 1), None), f64::INFINITY, "never detected");
        t.mark((0, 1));
        t.mark((0, 2));
        // Blocks 0 and 1 slide together 2 m along x (and deform by 1 mm); block 2 stays.
        let step = [shift(0.5, 0.00025), shift(0.5, 0.0), BlockMove::default()];
        let mut t2 = after(&[step; 4]);
        t2.seen = t.seen.clone();
        assert!((t2.since((0, 1), None) - 0.001).abs() < 1e-12, "together: only the spread counts");
        assert!((t2.since((0, 2), None) - 2.001).abs() < 1e-12, "against a block at rest: the run");
        // A trial moving block 1 back by 3 mm.
        let trial = [BlockMove::default(), shift(-0.003, 0.0), BlockMove::default()];
        assert!((t2.since((0, 1), Some(&trial)) - 0.004).abs() < 1e-12);
        // Opposite motions: the odometers' bound is the smaller one.
        let apart = [shift(0.5, 0.0), shift(-0.5, 0.0), BlockMove::default()];
        let mut t3 = after(&[apart; 2]);
        t3.seen = t.seen.clone();
        assert!((t3.since((0, 1), None) - 2.0).abs() < 1e-12);
        t2.mark((0, 1));
        assert_eq!(t2.since((0, 1), None), 0.0);
        let text = serde_json::to_string(&t2).unwrap();
        assert_eq!(serde_json::from_str::<Travel>(&text).unwrap(), t2);
        t2.retain(|_| false);
        assert_eq!(t2.since((0, 1), None), f64::INFINITY);
    }

    #[test]
    fn a_checkpoint_without_relative_motion_falls_back_on_the_runs() {
        let old = r#"{"odometer":[1.0,1.0],"seen":[[[0,1],[0.25,0.5]]]}"#;
        let t: Travel = serde_json::from_str(old).unwrap();
        assert_eq!(t.since((0, 1), None), 1.25);
    }
}
