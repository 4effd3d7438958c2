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
