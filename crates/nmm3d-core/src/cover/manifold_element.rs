//! Manifold elements: the connected parts of (sub-cell ∩ block).

use nmm3d_geom::{ConvexPolyhedron, Vec3};

use super::mesh::{cell_corner, MathMesh};
use super::poly::TERMS;

/// One manifold element (ME).
#[derive(Debug, Clone)]
pub struct ManifoldElement {
    /// Block index.
    pub block: usize,
    /// Index of its mesh in `Covers::meshes`.
    pub mesh: usize,
    /// Cell (i, j, k) of the mathematical mesh.
    pub cell: [i32; 3],
    /// Sub-cell index within the cell's pattern.
    pub subcell: usize,
    /// Physical cover of each sub-cell node (aligned with the sub-cell's `nodes`).
    pub covers: Vec<usize>,
    /// Geometry in cell-local ξ: convex parts (one for convex blocks; several glued parts of a
    /// non-convex block). Faces with boundary tags (`model::tags::is_boundary`) lie on the
    /// block surface.
    pub parts: Vec<ConvexPolyhedron>,
    /// Whether the whole sub-cell lies inside the block.
    pub full: bool,
    /// Volume [m³].
    pub volume: f64,
    /// Moments ∫ ξ^a η^b ζ^c dξ over `local` (NaN where the pattern needs none).
    pub moments: [f64; TERMS],
}

impl ManifoldElement {
    /// Volume centroid [m] (from the moments, in `mesh`).
    pub fn centroid(&self, mesh: &MathMesh) -> Vec3 {
        let m = &self.moments;
        let local = Vec3::new(m[1], m[3], m[9]) / m[0];
        mesh.to_global(&(cell_corner(self.cell) + local))
    }

    /// Every face of every part.
    pub fn faces(&self) -> impl Iterator<Item = &nmm3d_geom::Face> {
        self.parts.iter().flat_map(|p| p.faces.iter())
    }

    /// Faces on the block surface.
    pub fn boundary_faces(&self) -> impl Iterator<Item = &nmm3d_geom::Face> {
        self.faces().filter(|f| crate::model::tags::is_boundary(f.tag))
    }

    /// Whether a cell-local point lies in the ME (within `tol`).
    pub fn contains(&self, xi: &nmm3d_geom::Vec3, tol: f64) -> bool {
        self.parts.iter().any(|p| p.contains(xi, tol))
    }
}
