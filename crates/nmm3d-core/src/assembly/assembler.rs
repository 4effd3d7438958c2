//! Scatter of local (3n × 3n) blocks into the global lower-triangular matrix, through maps
//! precomputed per ME, so the hot loop is an indexed add.

use super::dof_map::DofMap;
use super::sparsity::SparsityPattern;

/// Precomputed scatter maps.
#[derive(Debug, Clone)]
pub struct Assembler {
    /// The global pattern.
    pub pattern: SparsityPattern,
    offsets: Vec<usize>,
    targets: Vec<u32>,
}

const SKIP: u32 = u32::MAX;

impl Assembler {
    /// Maps for the given cover lists (one per ME).
    pub fn new(pattern: SparsityPattern, dofs: &DofMap, elements: &[&[usize]]) -> Self {
        let mut offsets = Vec::with_capacity(elements.len() + 1);
        let mut targets = Vec::new();
        for covers in elements {
            offsets.push(targets.len());
            let eqs: Vec<Option<usize>> = covers.iter().flat_map(|&c| (0..3).map(move |i| dofs.eq(c, i))).collect();
            for r in &eqs {
                for c in &eqs {
                    let t = match (r, c) {
                        (Some(r), Some(c)) if r >= c => pattern.position(*r, *c).map_or(SKIP, |p| p as u32),
                        _ => SKIP,
                    };
                    targets.push(t);
                }
            }
        }
        offsets.push(targets.len());
        Self { pattern, offsets, targets }
    }

    /// values += local (row-major, size (3n)²) of element `e`.
    #[inline]
    pub fn add(&self, values: &mut [f64], e: usize, local: &[f64]) {
        let t = &self.targets[self.offsets[e]..self.offsets[e + 1]];
        debug_assert_eq!(t.len(), local.len());
        for (&pos, &v) in t.iter().zip(local) {
            if pos != SKIP {
                values[pos as usize] += v;
            }
        }
    }
}
