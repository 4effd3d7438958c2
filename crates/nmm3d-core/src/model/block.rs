//! Blocks: the solids the analysis moves. A block is a union of convex pieces (one piece for
//! convex bodies); its faces remember where they came from through their tags.

use nmm3d_geom::{Aabb, ConvexPolyhedron, Vec3};

/// One block.
#[derive(Debug, Clone)]
pub struct Block {
    /// Index of the body it was cut from.
    pub body: usize,
    /// Index of its material.
    pub material: usize,
    /// Whether it is held fixed.
    pub fixed: bool,
    /// Whether it is one manifold element (a fixed block not meshed: its surface only).
    pub whole: bool,
    /// Initial translational velocity [m/s].
    pub velocity: Vec3,
    /// Initial angular velocity about the centroid [rad/s].
    pub angular_velocity: Vec3,
    /// Convex pieces (glued along faces that are not joints).
    pub pieces: Vec<ConvexPolyhedron>,
    /// Volume [m³].
    pub volume: f64,
    /// Volume centroid [m].
    pub centroid: Vec3,
    /// The excavation whose opening it fills until a stage removes it (`None`: rock).
    pub excavation: Option<usize>,
}

impl Block {
    /// Build from pieces, computing volume and centroid.
    pub fn new(body: usize, material: usize, fixed: bool, pieces: Vec<ConvexPolyhedron>) -> Self {
        let volume: f64 = pieces.iter().map(|p| p.volume()).sum();
        let centroid = pieces.iter().map(|p| p.volume() * p.centroid()).sum::<Vec3>() / volume;
        Self {
            body,
            material,
            fixed,
            whole: false,
            velocity: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            pieces,
            volume,
            centroid,
            excavation: None,
        }
    }

    /// Bounding box of all pieces.
    pub fn aabb(&self) -> Aabb {
        self.pieces.iter().map(|p| p.aabb()).reduce(|a, b| a.union(&b)).expect("a block has a piece")
    }

    /// Whether `p` lies in the block (within `tol` [m]).
    pub fn contains(&self, p: &Vec3, tol: f64) -> bool {
        self.pieces.iter().any(|c| c.contains(p, tol))
    }

    /// Initial velocity of the material point at `x`: v + ω × (x − c).
    pub fn initial_velocity_at(&self, x: &Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(&(x - self.centroid))
    }
}
