//! Manifold elements: the connected parts of (sub-cell ∩ block).

use nmm3d_geom::ConvexPolyhedron;

use super::poly::TERMS;

/// One manifold element (ME).
#[derive(Debug, Clone)]
pub struct ManifoldElement {
    /// Block index.
    pub block: usize,
    /// Cell (i, j, k) of the mathematical mesh.
    pub cell: [i32; 3],
    /// Sub-cell index within the cell's pattern.
    pub subcell: usize,
    /// Physical cover of each sub-cell node (aligned with the sub-cell's `nodes`).
    pub covers: Vec<usize>,
    /// Geometry in cell-local ξ; faces tagged below `CELL_TAG` lie on the block boundary.
    pub local: ConvexPolyhedron,
    /// Whether the whole sub-cell lies inside the block.
    pub full: bool,
    /// Volume [m³].
    pub volume: f64,
    /// Moments ∫ ξ^a η^b ζ^c dξ over `local` (NaN where the pattern needs none).
    pub moments: [f64; TERMS],
}

impl ManifoldElement {
    /// Whether the ME has a face on the block boundary.
    pub fn on_boundary(&self) -> bool {
        self.local.faces.iter().any(|f| f.tag.0 < super::pattern::CELL_TAG)
    }
}
