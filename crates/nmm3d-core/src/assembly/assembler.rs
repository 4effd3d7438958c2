//! Scatter of local (3n × 3n) blocks into the global lower-triangular matrix through maps
//! precomputed per ME, so the hot loop is an indexed add. An ME with tied covers first maps
//! its block through T (n × m weights over its m free masters): L' = Tᵀ L T.

use rayon::prelude::*;

use super::dof_map::DofMap;
use super::sparsity::SparsityPattern;

/// Precomputed scatter maps.
#[derive(Debug, Clone)]
pub struct Assembler {
    /// The global pattern.
    pub pattern: SparsityPattern,
    offsets: Vec<usize>,
    targets: Vec<u32>,
    /// Per ME: (number of masters m, T row-major n × m) when it has tied covers.
    transforms: Vec<Option<(usize, Vec<f64>)>>,
}

const SKIP: u32 = u32::MAX;

/// The free covers an ME couples, and T when any of its covers is tied.
pub fn masters_of(dofs: &DofMap, covers: &[usize]) -> (Vec<usize>, Option<Vec<f64>>) {
    if !covers.iter().any(|&c| matches!(dofs.kind[c], super::dof_map::CoverDofs::Tied(_))) {
        return (covers.to_vec(), None);
    }
    let mut masters: Vec<usize> = Vec::new();
    for &c in covers {
        for (m, _) in dofs.masters(c) {
            if !masters.contains(&m) {
                masters.push(m);
            }
        }
    }
    let m = masters.len();
    let mut t = vec![0.0; covers.len() * m];
    for (a, &c) in covers.iter().enumerate() {
        for (mc, w) in dofs.masters(c) {
            let p = masters.iter().position(|&x| x == mc).expect("listed");
            t[a * m + p] += w;
        }
    }
    (masters, Some(t))
}

impl Assembler {
    /// Maps for the given cover lists (one per ME), made in parallel.
    pub fn new(pattern: SparsityPattern, dofs: &DofMap, elements: &[&[usize]]) -> Self {
        let masters: Vec<(Vec<usize>, Option<Vec<f64>>)> = elements.par_iter().map(|c| masters_of(dofs, c)).collect();
        let mut offsets = Vec::with_capacity(elements.len() + 1);
        offsets.push(0);
        for (m, _) in &masters {
            offsets.push(offsets[offsets.len() - 1] + 9 * m.len() * m.len());
        }
        let mut targets = vec![SKIP; offsets[elements.len()]];
        // Each ME's share of `targets`, filled independently.
        let mut rest = targets.as_mut_slice();
        let mut shares = Vec::with_capacity(elements.len());
        for w in offsets.windows(2) {
            let (share, tail) = std::mem::take(&mut rest).split_at_mut(w[1] - w[0]);
            shares.push(share);
            rest = tail;
        }
        shares.into_par_iter().zip(&masters).for_each(|(share, (m, _))| {
            let eqs: Vec<Option<usize>> = m.iter().flat_map(|&c| (0..3).map(move |i| dofs.eq(c, i))).collect();
            for (t, (r, c)) in share.iter_mut().zip(eqs.iter().flat_map(|r| eqs.iter().map(move |c| (r, c)))) {
                if let (Some(r), Some(c)) = (r, c) {
                    if r >= c {
                        *t = pattern.position(*r, *c).map_or(SKIP, |p| p as u32);
                    }
                }
            }
        });
        let transforms = masters.into_iter().map(|(m, t)| t.map(|t| (m.len(), t))).collect();
        Self { pattern, offsets, targets, transforms }
    }

    /// values += local (row-major, size (3n)²) of element `e`.
    #[inline]
    pub fn add(&self, values: &mut [f64], e: usize, local: &[f64]) {
        match &self.transforms[e] {
            None => self.add_mapped(values, e, local),
            Some((m, tm)) => self.add_mapped(values, e, &transform(local, tm, *m)),
        }
    }

    /// Element `e`'s block `local` as [`Self::add_mapped`] scatters it: itself, or Tᵀ L T with
    /// tied covers — made where the blocks are made (in parallel), not in the serial scatter.
    pub fn mapped(&self, e: usize, local: Vec<f64>) -> Vec<f64> {
        match &self.transforms[e] {
            None => local,
            Some((m, tm)) => transform(&local, tm, *m),
        }
    }

    /// values += a block of element `e` already [`Self::mapped`].
    #[inline]
    pub fn add_mapped(&self, values: &mut [f64], e: usize, local: &[f64]) {
        let t = &self.targets[self.offsets[e]..self.offsets[e + 1]];
        debug_assert_eq!(t.len(), local.len());
        for (&pos, &v) in t.iter().zip(local) {
            if pos != SKIP {
                values[pos as usize] += v;
            }
        }
    }

    /// The positions in the global values that element `e`'s block adds to.
    pub fn positions(&self, e: usize) -> impl Iterator<Item = usize> + '_ {
        self.targets[self.offsets[e]..self.offsets[e + 1]].iter().filter(|&&p| p != SKIP).map(|&p| p as usize)
    }

    /// Set the values element `e` adds to to zero.
    pub fn zero(&self, values: &mut [f64], e: usize) {
        self.positions(e).for_each(|p| values[p] = 0.0);
    }
}

/// Tᵀ L T for a (3n)² block L and scalar weights T (n × m), applied per 3 × 3 block.
fn transform(l: &[f64], t: &[f64], m: usize) -> Vec<f64> {
    let n = t.len() / m;
    // Each cover's nonzero weights (node, weight): the filters once, not per pair of covers.
    let nonzero: Vec<Vec<(usize, f64)>> =
        t.chunks_exact(m).map(|row| row.iter().copied().enumerate().filter(|&(_, w)| w != 0.0).collect()).collect();
    let mut out = vec![0.0; 9 * m * m];
    for (a, ta) in nonzero.iter().enumerate() {
        for (b, tb) in nonzero.iter().enumerate() {
            for &(p, wp) in ta {
                for &(q, wq) in tb {
                    let w = wp * wq;
                    for i in 0..3 {
                        let (dst, src) = ((3 * p + i) * 3 * m + 3 * q, (3 * a + i) * 3 * n + 3 * b);
                        for j in 0..3 {
                            out[dst + j] += w * l[src + j];
                        }
                    }
                }
            }
        }
    }
    out
}
