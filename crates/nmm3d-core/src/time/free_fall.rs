//! The free-fall bound of a dynamic run: no block's centre of mass faster than a body falling
//! freely from the highest point of the moving blocks at the run's start down to the block's
//! lowest point now, starting at the fastest block's initial speed,
//!
//!   |v_b| ≤ √(v₀² + 2 |g| (top − low_b)).
//!
//! Gravity moves the blocks, contacts and the rock only take energy from them, so a block past
//! the bound was given energy from nowhere — as at the contact event that once threw a key
//! block to 13.9 m/s where 1.34 m/s was right. A sanity bound, not a
//! theorem: a light block struck by a heavy one, or pushed by a row of them, can pass it
//! (`docs/theory/energy.md`), and loads, water, a moving base, bolts or released in-situ
//! stress do work it leaves out (`gravity_only`).

use nmm3d_geom::Vec3;
use serde::{Deserialize, Serialize};

use crate::contact::point::MaterialPoint;
use crate::scenario::Scenario;
use crate::state::Motion;
use crate::system::System;

/// The model's part of the bound, made once: unit vector against gravity, |g|, and per
/// moving block its covers with their lumped masses and its vertices as material points.
#[derive(Debug, Clone, Default)]
pub struct FreeFallPlan {
    up: Vec3,
    g: f64,
    /// Per block (`None`: fixed).
    blocks: Vec<Option<BlockPlan>>,
}

#[derive(Debug, Clone)]
struct BlockPlan {
    /// Covers with their lumped masses [kg], and their sum.
    covers: Vec<(usize, f64)>,
    mass: f64,
    /// The block's vertices: height along `up` at rest [m] and the covers and weights that
    /// move them (a convex block's lowest point is a vertex).
    vertices: Vec<(f64, Vec<(usize, f64)>)>,
}

/// The fastest block relative to its bound so far, and where the bound starts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FreeFall {
    /// Highest point of the moving blocks at the run's start, along −g [m].
    pub top: f64,
    /// Fastest block's centre-of-mass speed at the run's start [m/s].
    pub initial_speed: f64,
    /// Largest speed / bound so far (0 before a block moves).
    pub ratio: f64,
    /// The block of the largest ratio.
    pub block: usize,
    /// Time of the largest ratio [s].
    pub time: f64,
    /// Its speed [m/s].
    pub speed: f64,
    /// Its bound [m/s].
    pub bound: f64,
}

impl FreeFallPlan {
    /// The plan of `sys` (its covers' lumped masses, `System::cover_mass`); empty without gravity.
    pub fn new(sys: &System) -> Self {
        let mass = &sys.cover_mass;
        let g = Vec3::from(sys.scenario.analysis.gravity);
        if g.norm() == 0.0 {
            return Self::default();
        }
        let up = -g.normalize();
        let vertex = |b: usize, x: Vec3| {
            let p = MaterialPoint::new(sys, b, x)?;
            let covers = &sys.covers.elements[p.element].covers;
            Some((x.dot(&up), covers.iter().copied().zip(p.weights).collect()))
        };
        let mut blocks: Vec<Option<BlockPlan>> = (sys.geometry.blocks.iter().enumerate())
            .map(|(i, b)| {
                let vertices = b.pieces.iter().flat_map(|p| p.vertices()).filter_map(|x| vertex(i, x)).collect();
                (!b.fixed).then_some(BlockPlan { covers: Vec::new(), mass: 0.0, vertices })
            })
            .collect();
        for (c, cover) in sys.covers.covers.iter().enumerate() {
            if let Some(p) = blocks[cover.block].as_mut() {
                p.covers.push((c, mass[c]));
                p.mass += mass[c];
            }
        }
        Self { up, g: g.norm(), blocks }
    }

    /// Centre-of-mass speed of block `p` [m/s] and its lowest and highest points now along
    /// `up` [m].
    fn block_now(&self, p: &BlockPlan, motion: &Motion) -> (f64, f64, f64) {
        let momentum: Vec3 = p.covers.iter().map(|&(c, m)| m * motion.v[c]).sum();
        let heights =
            p.vertices.iter().map(|(z, w)| z + w.iter().map(|&(c, w)| w * motion.u[c].dot(&self.up)).sum::<f64>());
        let (low, high) = heights.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), z| (l.min(z), h.max(z)));
        ((momentum / p.mass.max(f64::MIN_POSITIVE)).norm(), low, high)
    }

    /// The bound's start at `motion` (a run's first step): the highest point of the moving
    /// blocks and the fastest one's speed. `None` without gravity or moving blocks.
    pub fn start(&self, motion: &Motion) -> Option<FreeFall> {
        let moving: Vec<(f64, f64, f64)> = (self.blocks.iter().flatten())
            .filter(|p| !p.covers.is_empty() && !p.vertices.is_empty())
            .map(|p| self.block_now(p, motion))
            .collect();
        if self.g == 0.0 || moving.is_empty() {
            return None;
        }
        let top = moving.iter().map(|m| m.2).fold(f64::NEG_INFINITY, f64::max);
        let initial_speed = moving.iter().map(|m| m.0).fold(0.0, f64::max);
        Some(FreeFall { top, initial_speed, ratio: 0.0, block: 0, time: motion.time, speed: 0.0, bound: 0.0 })
    }

    /// Take `motion` (the end of an accepted step) into `f`: the block farthest past its
    /// bound, if farther than any before.
    pub fn observe(&self, motion: &Motion, f: &mut FreeFall) {
        for (b, p) in self.blocks.iter().enumerate() {
            let Some(p) = p.as_ref().filter(|p| !p.covers.is_empty() && !p.vertices.is_empty()) else { continue };
            let (speed, low, _) = self.block_now(p, motion);
            let bound = (f.initial_speed.powi(2) + 2.0 * self.g * (f.top - low).max(0.0)).sqrt();
            let ratio = if bound > 0.0 {
                speed / bound
            } else if speed > 0.0 {
                f64::INFINITY
            } else {
                0.0
            };
            if ratio > f.ratio {
                (f.ratio, f.block, f.time, f.speed, f.bound) = (ratio, b, motion.time, speed, bound);
            }
        }
    }
}

/// Whether gravity alone gives the blocks energy (no loads, water, seismic loading, bolts,
/// in-situ stress, excavation or stages): where a block past the bound is worth a warning.
pub fn gravity_only(s: &Scenario) -> bool {
    s.point_load.is_empty()
        && s.surface_load.is_empty()
        && s.water.is_none()
        && s.seismic.coefficient == [0.0; 3]
        && !s.seismic.moves()
        && s.bolt.is_empty()
        && s.bolt_pattern.is_empty()
        && s.in_situ_stress.is_none()
        && s.excavation.is_empty()
        && s.stage.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One block of two covers of 1 kg each, resting between heights 0 and 1 m, g = 10 m/s².
    fn plan() -> FreeFallPlan {
        let both = vec![(0, 0.5), (1, 0.5)];
        let block =
            BlockPlan { covers: vec![(0, 1.0), (1, 1.0)], mass: 2.0, vertices: vec![(0.0, both.clone()), (1.0, both)] };
        FreeFallPlan { up: Vec3::z(), g: 10.0, blocks: vec![None, Some(block)] }
    }

    fn motion(time: f64, u: [Vec3; 2], v: [Vec3; 2]) -> Motion {
        Motion {
            time,
            step: 0,
            dt: 0.0,
            u: u.to_vec(),
            v: v.to_vec(),
            a: Vec::new(),
            rotations: Vec::new(),
            bolts: Vec::new(),
            base: [Vec3::zeros(); 2],
            travel_origin: Vec::new(),
        }
    }

    #[test]
    fn a_block_falling_freely_reaches_its_bound_and_no_more() {
        let p = plan();
        let rest = [Vec3::zeros(); 2];
        let mut f = p.start(&motion(0.0, rest, rest)).unwrap();
        assert_eq!((f.top, f.initial_speed), (1.0, 0.0));
        // Fallen 0.8 m at √(2 g 0.8) = 4 m/s: its bound counts from the top of the block (1 m
        // above its lowest point), √(2 g 1.8) = 6 m/s.
        let down = Vec3::new(0.0, 0.0, -0.8);
        p.observe(&motion(0.4, [down; 2], [Vec3::new(0.0, 0.0, -4.0); 2]), &mut f);
        assert!((f.bound - 6.0).abs() < 1e-12 && (f.ratio - 4.0 / 6.0).abs() < 1e-12);
        assert_eq!((f.block, f.time), (1, 0.4));
    }

    #[test]
    fn a_block_thrown_faster_than_it_could_fall_is_caught_where_it_happened() {
        let p = plan();
        let rest = [Vec3::zeros(); 2];
        let mut f = p.start(&motion(0.0, rest, rest)).unwrap();
        // 1 cm down, but at 5 m/s (one cover at 10, one at 0: the centre of mass moves at 5).
        let down = Vec3::new(0.0, 0.0, -0.01);
        p.observe(&motion(0.1, [down; 2], [Vec3::new(10.0, 0.0, 0.0), Vec3::zeros()]), &mut f);
        let bound = (2.0_f64 * 10.0 * 1.01).sqrt();
        assert!((f.ratio - 5.0 / bound).abs() < 1e-12 && f.ratio > 1.0);
        // A slower step later does not replace it.
        p.observe(&motion(0.2, [down; 2], rest), &mut f);
        assert_eq!(f.time, 0.1);
    }

    #[test]
    fn without_gravity_there_is_no_bound() {
        let rest = [Vec3::zeros(); 2];
        assert!(FreeFallPlan::default().start(&motion(0.0, rest, rest)).is_none());
    }
}
