//! Equation numbering: three equations per free physical cover; covers of fixed blocks have none.

/// Map from physical covers to equations.
#[derive(Debug, Clone)]
pub struct DofMap {
    /// First equation of each cover (`u32::MAX` if the cover is fixed).
    pub first: Vec<u32>,
    /// Number of equations.
    pub n_eq: usize,
}

/// Marker of a fixed cover.
pub const FIXED: u32 = u32::MAX;

impl DofMap {
    /// Number the free covers in order.
    pub fn new(free: impl Iterator<Item = bool>) -> Self {
        let mut n = 0u32;
        let first = free
            .map(|f| {
                if f {
                    n += 3;
                    n - 3
                } else {
                    FIXED
                }
            })
            .collect();
        Self { first, n_eq: n as usize }
    }

    /// Equation of component `i` of cover `c`, if free.
    #[inline]
    pub fn eq(&self, c: usize, i: usize) -> Option<usize> {
        let f = self.first[c];
        (f != FIXED).then(|| f as usize + i)
    }
}
