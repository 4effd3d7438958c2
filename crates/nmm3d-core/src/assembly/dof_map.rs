//! Equation numbering. A physical cover is *free* (three equations), *fixed* (covers of fixed
//! blocks: zero displacement) or *tied*: its displacement is a fixed linear combination of
//! free covers (aggregation of ill-posed covers, see `cover/aggregation.rs`).

/// What carries the displacement of one cover.
#[derive(Debug, Clone, PartialEq)]
pub enum CoverDofs {
    /// Own equations starting here.
    Free(u32),
    /// Held at zero.
    Fixed,
    /// d = Σ w · d_master over free masters.
    Tied(Vec<(usize, f64)>),
}

/// Map from physical covers to equations.
#[derive(Debug, Clone)]
pub struct DofMap {
    /// Per cover.
    pub kind: Vec<CoverDofs>,
    /// Number of equations.
    pub n_eq: usize,
}

impl DofMap {
    /// Number the free covers in order; `tied[c]` gives the masters of a tied cover.
    pub fn new(fixed: &[bool], tied: &[Option<Vec<(usize, f64)>>]) -> Self {
        let mut n = 0u32;
        let kind = fixed
            .iter()
            .zip(tied)
            .map(|(&f, t)| match (f, t) {
                (true, _) => CoverDofs::Fixed,
                (false, Some(m)) => CoverDofs::Tied(m.clone()),
                (false, None) => {
                    n += 3;
                    CoverDofs::Free(n - 3)
                }
            })
            .collect();
        Self { kind, n_eq: n as usize }
    }

    /// Equation of component `i` of cover `c`, if it is free.
    #[inline]
    pub fn eq(&self, c: usize, i: usize) -> Option<usize> {
        match self.kind[c] {
            CoverDofs::Free(f) => Some(f as usize + i),
            _ => None,
        }
    }

    /// Free covers and weights whose combination gives cover `c` (empty if fixed).
    pub fn masters(&self, c: usize) -> Vec<(usize, f64)> {
        match &self.kind[c] {
            CoverDofs::Free(_) => vec![(c, 1.0)],
            CoverDofs::Fixed => Vec::new(),
            CoverDofs::Tied(m) => m.clone(),
        }
    }

    /// Whether cover `c` moves (free or tied).
    pub fn moves(&self, c: usize) -> bool {
        !matches!(self.kind[c], CoverDofs::Fixed)
    }

    /// Whether any cover is tied.
    pub fn has_tied(&self) -> bool {
        self.kind.iter().any(|k| matches!(k, CoverDofs::Tied(_)))
    }
}
