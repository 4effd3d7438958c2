//! The system matrix's pattern while contacts come and go: the elements' pattern plus one
//! clique per pair of MEs with a closed contact point. It grows when a pair closes whose covers
//! it does not couple yet — also between a step's open–close iterations — with a new symbolic
//! analysis unless the factor's structure holds the new entries (`solver::faer_cholesky`); a
//! pair whose covers it couples already (a block on a fixed block) only gets its scatter. A growth adds the new pairs' cliques to the pattern as it is (the scatters it holds
//! are moved, not made again); once a tenth of its pairs have not closed for
//! [`RETAIN_STEPS`] steps it is made anew without them, so the fill follows the contacts of the
//! moment: open points near each other (side faces of neighbouring blocks within the detection
//! margin) add no stiffness and would only add fill.
//!
//! The elastic tangent and the mass stay on the elements' pattern (their scatter maps never
//! change); each matrix to factorise is gathered onto the current pattern through one map.

use rustc_hash::FxHashMap;

use crate::assembly::assembler::masters_of;
use crate::assembly::{Coupling, SparsityPattern};
use crate::contact::pair_clique;
use crate::system::System;

/// Steps a pair of MEs stays in the pattern after its last closed point: a pair that touched
/// recently (rocking, bouncing) likely touches again, and keeping it spares a symbolic analysis.
pub const RETAIN_STEPS: u64 = 50;

/// The current pattern and the contact couplings on it.
#[derive(Default)]
pub struct ContactPattern {
    /// The pattern with contact couplings (`None`: the elements' pattern alone).
    grown: Option<Grown>,
    /// Step at which each pair (lower ME first) last had a closed point.
    last_closed: FxHashMap<(usize, usize), u64>,
    /// Times the pattern grew.
    pub rebuilds: u64,
}

/// A pattern grown by contact couplings.
struct Grown {
    pattern: SparsityPattern,
    /// Position of each entry of the elements' pattern in `pattern`.
    from_elements: Vec<u32>,
    couplings: FxHashMap<(usize, usize), Coupling>,
}

impl ContactPattern {
    /// The current pattern.
    pub fn pattern<'a>(&'a self, sys: &'a System) -> &'a SparsityPattern {
        self.grown.as_ref().map_or(&sys.assembler.pattern, |g| &g.pattern)
    }

    /// The scatter of a pair of MEs (lower first) the pattern holds.
    pub fn coupling(&self, pair: (usize, usize)) -> &Coupling {
        &self.grown.as_ref().expect("a pattern with contact couplings").couplings[&pair]
    }

    /// `out` = a·`k` + b·`m` on the current pattern, for `k` and `m` on the elements' pattern.
    pub fn combine(&self, sys: &System, (a, k): (f64, &[f64]), (b, m): (f64, &[f64]), out: &mut Vec<f64>) {
        out.clear();
        match &self.grown {
            None => out.extend(k.iter().zip(m).map(|(k, m)| a * k + b * m)),
            Some(g) => {
                out.resize(g.pattern.nnz(), 0.0);
                for ((&at, k), m) in g.from_elements.iter().zip(k).zip(m) {
                    out[at as usize] = a * k + b * m;
                }
            }
        }
        debug_assert_eq!(out.len(), self.pattern(sys).nnz());
    }

    /// Make the pattern hold every pair in `closed` (lower ME first), marked closed at `step`;
    /// true when it had to grow.
    pub fn ensure(&mut self, sys: &System, closed: &[(usize, usize)], step: u64) -> bool {
        for &p in closed {
            let _ = self.last_closed.insert(p, step);
        }
        let held = |p: &&(usize, usize)| self.grown.as_ref().is_some_and(|g| g.couplings.contains_key(*p));
        let missing: Vec<(usize, usize)> = closed.iter().filter(|p| !held(p)).copied().collect();
        if missing.is_empty() || self.fit(sys, &missing) {
            return false;
        }
        self.last_closed.retain(|_, &mut last| last + RETAIN_STEPS >= step);
        // A tenth: on thesis case A (10 MPa/m joints) a quarter kept so many stale pairs that
        // the factor grew by 16 % and its factorisations cost more than the growths saved.
        let fresh = self.grown.as_ref().is_some_and(|g| {
            let stale = g.couplings.keys().filter(|p| !self.last_closed.contains_key(p)).count();
            !g.couplings.is_empty() && 10 * stale <= g.couplings.len()
        });
        if fresh {
            self.extend(sys, &missing);
        } else {
            let mut pairs: Vec<(usize, usize)> = self.last_closed.keys().copied().collect();
            pairs.sort_unstable();
            self.grow(sys, &pairs);
        }
        self.rebuilds += 1;
        true
    }

    /// The grown pattern with the cliques of `pairs` added: the same pattern and scatters as
    /// [`Self::grow`] over all its pairs and these (a union of cliques), the held scatters moved
    /// along the embedding instead of searched again.
    fn extend(&mut self, sys: &System, pairs: &[(usize, usize)]) {
        let g = self.grown.as_mut().expect("a grown pattern to extend");
        let cliques: Vec<Vec<usize>> = pairs.iter().map(|&(a, b)| pair_clique(sys, a, b)).collect();
        let masters: Vec<Vec<usize>> = cliques.iter().map(|c| masters_of(&sys.dofs, c).0).collect();
        let pattern = g.pattern.with_cliques(&sys.dofs, masters.iter().map(|c| c.as_slice()));
        let moved = g.pattern.embedding(&pattern);
        for c in g.couplings.values_mut() {
            c.move_to(&g.pattern, &pattern, &moved);
        }
        g.from_elements.iter_mut().for_each(|at| *at = moved[*at as usize]);
        g.couplings.extend(pairs.iter().zip(&cliques).map(|(&p, c)| (p, Coupling::new(&pattern, &sys.dofs, c))));
        g.pattern = pattern;
    }

    /// Add the pairs whose covers the pattern already couples, if all are (a block on a fixed
    /// one: the fixed covers carry no equations; covers that an earlier pair or an ME couples):
    /// the pattern and its symbolic analysis stay. False (nothing added) if one is not.
    fn fit(&mut self, sys: &System, pairs: &[(usize, usize)]) -> bool {
        let pattern = self.pattern(sys);
        let fitted: Option<Vec<_>> = pairs
            .iter()
            .map(|&(a, b)| Coupling::try_new(pattern, &sys.dofs, &pair_clique(sys, a, b)).map(|c| ((a, b), c)))
            .collect();
        let Some(fitted) = fitted else { return false };
        let grown = self.grown.get_or_insert_with(|| {
            let elements = &sys.assembler.pattern;
            Grown {
                pattern: elements.clone(),
                from_elements: elements.embedding(elements),
                couplings: FxHashMap::default(),
            }
        });
        grown.couplings.extend(fitted);
        true
    }

    /// The pattern of the elements plus a clique per pair in `pairs` (sorted).
    fn grow(&mut self, sys: &System, pairs: &[(usize, usize)]) {
        let cliques: Vec<Vec<usize>> = pairs.iter().map(|&(a, b)| pair_clique(sys, a, b)).collect();
        let masters: Vec<Vec<usize>> = cliques.iter().map(|c| masters_of(&sys.dofs, c).0).collect();
        let elements = &sys.assembler.pattern;
        let pattern = elements.with_cliques(&sys.dofs, masters.iter().map(|c| c.as_slice()));
        let from_elements = elements.embedding(&pattern);
        let couplings = pairs.iter().zip(&cliques).map(|(&p, c)| (p, Coupling::new(&pattern, &sys.dofs, c))).collect();
        self.grown = Some(Grown { pattern, from_elements, couplings });
    }

    /// What rebuilds this pattern exactly (checkpoints): its pairs and their last closing steps.
    pub fn snapshot(&self) -> PatternSnapshot {
        let mut pairs: Vec<(usize, usize)> =
            self.grown.as_ref().map(|g| g.couplings.keys().copied().collect()).unwrap_or_default();
        pairs.sort_unstable();
        let mut last_closed: Vec<((usize, usize), u64)> = self.last_closed.iter().map(|(&p, &s)| (p, s)).collect();
        last_closed.sort_unstable();
        PatternSnapshot { grown: self.grown.is_some(), pairs, last_closed, rebuilds: self.rebuilds }
    }

    /// The pattern a snapshot describes.
    pub fn restore(sys: &System, s: &PatternSnapshot) -> Self {
        let mut p = Self { grown: None, last_closed: s.last_closed.iter().copied().collect(), rebuilds: s.rebuilds };
        if s.grown {
            p.grow(sys, &s.pairs);
        }
        p
    }
}

/// A [`ContactPattern`] as data.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PatternSnapshot {
    /// Whether the pattern holds contact couplings at all.
    pub grown: bool,
    /// The pairs of MEs (lower first) with a clique, sorted.
    pub pairs: Vec<(usize, usize)>,
    /// Step at which each pair last had a closed point, sorted.
    pub last_closed: Vec<((usize, usize), u64)>,
    /// Times the pattern grew.
    pub rebuilds: u64,
}
