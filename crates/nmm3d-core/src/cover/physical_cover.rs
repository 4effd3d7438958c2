//! Physical covers: connected components of (mathematical cover ∩ block). Each carries
//! three displacement DOFs (first-order NMM, constant cover function).

use nmm3d_geom::Vec3;

use super::mesh::NodeKey;

/// One physical cover.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalCover {
    /// Block it belongs to.
    pub block: usize,
    /// Its mathematical node.
    pub node: NodeKey,
    /// Reference (initial) position of the node [m].
    pub position: Vec3,
}

/// Union–find with path halving; deterministic (the smaller index becomes the root).
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    /// `n` singletons.
    pub fn new(n: usize) -> Self {
        Self { parent: (0..n).collect() }
    }
    /// Representative of `x`.
    pub fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }
    /// Merge the sets of `a` and `b`.
    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.parent[hi] = lo;
        }
    }
}
