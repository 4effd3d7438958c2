//! The system matrix's pattern while contacts come and go: the elements' pattern plus one
//! clique per pair of MEs with a closed contact point. It grows (with a new symbolic analysis)
//! when a pair closes that it lacks — also between a step's open–close iterations — and pairs
//! not closed for [`RETAIN_STEPS`] steps are dropped at the next growth, so the fill follows the
//! contacts of the moment: open points near each other (side faces of neighbouring blocks
//! within the detection margin) add no stiffness and would only add fill.

use rustc_hash::FxHashMap;

use crate::assembly::assembler::masters_of;
use crate::assembly::{Assembler, Coupling, SparsityPattern};
use crate::contact::pair_clique;
use crate::system::System;

/// Steps a pair of MEs stays in the pattern after its last closed point: a pair that touched
/// recently (rocking, bouncing) likely touches again, and keeping it spares a symbolic analysis.
pub const RETAIN_STEPS: u64 = 50;

/// Pattern, element scatter, mass and contact couplings of the current system matrix.
pub struct ContactPattern {
    /// Element scatter maps onto the current pattern.
    pub assembler: Assembler,
    /// Consistent mass on the current pattern.
    pub mass_values: Vec<f64>,
    couplings: FxHashMap<(usize, usize), Coupling>,
    /// Step at which each pair (lower ME first) last had a closed point.
    last_closed: FxHashMap<(usize, usize), u64>,
    /// Times the pattern grew.
    pub rebuilds: u64,
}

impl ContactPattern {
    /// The elements' pattern alone.
    pub fn new(sys: &System) -> Self {
        Self {
            assembler: sys.assembler.clone(),
            mass_values: sys.mass_values.clone(),
            couplings: FxHashMap::default(),
            last_closed: FxHashMap::default(),
            rebuilds: 0,
        }
    }

    /// The scatter of a pair of MEs (lower first) the pattern holds.
    pub fn coupling(&self, pair: (usize, usize)) -> &Coupling {
        &self.couplings[&pair]
    }

    /// Make the pattern hold every pair in `closed` (lower ME first), marked closed at `step`.
    /// When it had to grow, returns the map from the old pattern's entries to the new ones.
    pub fn ensure(&mut self, sys: &System, closed: &[(usize, usize)], step: u64) -> Option<Vec<u32>> {
        for &p in closed {
            let _ = self.last_closed.insert(p, step);
        }
        if closed.iter().all(|p| self.couplings.contains_key(p)) {
            return None;
        }
        self.last_closed.retain(|_, &mut last| last + RETAIN_STEPS >= step);
        let mut pairs: Vec<(usize, usize)> = self.last_closed.keys().copied().collect();
        pairs.sort_unstable();
        let cliques: Vec<Vec<usize>> = pairs.iter().map(|&(a, b)| pair_clique(sys, a, b)).collect();
        let masters: Vec<Vec<usize>> = cliques.iter().map(|c| masters_of(&sys.dofs, c).0).collect();
        let pattern = sys.assembler.pattern.with_cliques(&sys.dofs, masters.iter().map(|c| c.as_slice()));
        let from_elements = sys.assembler.pattern.embedding(&pattern);
        let from_old = self.assembler.pattern.embedding(&pattern);
        self.mass_values = SparsityPattern::embed(&sys.mass_values, &from_elements, &pattern);
        self.couplings = pairs.iter().zip(&cliques).map(|(&p, c)| (p, Coupling::new(&pattern, &sys.dofs, c))).collect();
        self.assembler = sys.assembler.remapped(pattern, &from_elements);
        self.rebuilds += 1;
        Some(from_old)
    }
}
