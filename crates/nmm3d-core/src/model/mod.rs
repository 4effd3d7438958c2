//! The immutable model: blocks, materials and the scenario they came from.

pub mod block;
pub mod material;
pub mod shape;

use nmm3d_geom::{Aabb, Vec3};

pub use block::Block;
pub use material::Elastic;

use crate::scenario::Scenario;

/// Blocks and materials of a scenario.
#[derive(Debug, Clone)]
pub struct Geometry {
    /// Blocks, ordered by body then centroid (stable ids).
    pub blocks: Vec<Block>,
    /// Materials in scenario order.
    pub materials: Vec<Elastic>,
}

impl Geometry {
    /// Build blocks from a validated scenario.
    pub fn from_scenario(s: &Scenario) -> Self {
        let materials: Vec<Elastic> = s.material.iter().map(Elastic::new).collect();
        let mut blocks = Vec::new();
        for (k, b) in s.body.iter().enumerate() {
            let m = s.material.iter().position(|m| m.name == b.material).expect("validated");
            let piece = shape::shape_to_convex(&b.shape).expect("validated");
            let mut block = Block::new(k, m, b.fixed, vec![piece]);
            block.velocity = Vec3::from(b.velocity);
            block.angular_velocity = Vec3::from(b.angular_velocity);
            blocks.push(block);
        }
        Self { blocks, materials }
    }

    /// Bounding box of all blocks.
    pub fn aabb(&self) -> Aabb {
        self.blocks.iter().map(|b| b.aabb()).reduce(|a, b| a.union(&b)).expect("at least one block")
    }
}
