//! The mathematical mesh: a cubic grid of edge `size`, through `origin`, rotated by
//! `rotation`. Mesh-local coordinates are measured in cell edges: ξ = Rᵀ(x − o)/s, so cell
//! (i, j, k) is [i, i+1] × [j, j+1] × [k, k+1]. Nodes are keyed in half-cell units so that
//! face and body centres (tet24) have integer keys.

use nmm3d_geom::{math::rotation_xyz_deg, Mat3, Vec3};

/// Key of a mesh node in half-cell units.
pub type NodeKey = [i32; 3];

/// The cubic mathematical mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MathMesh {
    /// Cell edge s [m].
    pub size: f64,
    /// A mesh node o [m].
    pub origin: Vec3,
    /// Rotation R of the mesh axes.
    pub rotation: Mat3,
}

impl MathMesh {
    /// Mesh with the rotation given as angles about x, then y, then z [deg].
    /// The origin is moved by whole cells to the node nearest the frame's origin (the same
    /// mesh): cell coordinates then stay small near the model, whose frame is local.
    pub fn new(size: f64, origin: Vec3, rotation_deg: [f64; 3]) -> Self {
        let rotation = rotation_xyz_deg(rotation_deg);
        let cells = (rotation.transpose() * origin / size).map(f64::round);
        Self { size, origin: origin - size * (rotation * cells), rotation }
    }

    /// Mesh-local coordinates (cell units) of a global point.
    pub fn to_local(&self, x: &Vec3) -> Vec3 {
        self.rotation.transpose() * (x - self.origin) / self.size
    }

    /// Global point of mesh-local coordinates.
    pub fn to_global(&self, l: &Vec3) -> Vec3 {
        self.origin + self.size * (self.rotation * l)
    }

    /// Global position of a node.
    pub fn node_position(&self, key: NodeKey) -> Vec3 {
        self.to_global(&(Vec3::new(key[0] as f64, key[1] as f64, key[2] as f64) * 0.5))
    }

    /// Cell holding the mesh-local point.
    pub fn cell_of(&self, local: &Vec3) -> [i32; 3] {
        [local.x.floor() as i32, local.y.floor() as i32, local.z.floor() as i32]
    }
}

/// Mesh-local coordinates of a cell's corner.
pub fn cell_corner(cell: [i32; 3]) -> Vec3 {
    Vec3::new(cell[0] as f64, cell[1] as f64, cell[2] as f64)
}
