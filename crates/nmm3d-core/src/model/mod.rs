//! The immutable model: blocks, materials and the scenario they came from.

pub mod block;
pub mod cutting;
pub mod estimate;
pub mod excavate;
pub mod material;
pub mod shape;
pub mod tags;
pub mod touching;
pub mod traverse;
pub mod tunnel;
pub mod union_find;

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
    /// Joint features (sets, then single planes) that made joint faces.
    pub features: Vec<cutting::JointFeature>,
    /// What cutting did.
    pub report: cutting::CutReport,
    /// Origin of the local frame the blocks are in [m] (`Scenario::local_origin`): a block
    /// point x is at x + origin in the scenario's coordinates.
    pub origin: Vec3,
}

impl Geometry {
    /// Build blocks from a validated scenario: bodies, then joints, then excavations — in the
    /// scenario's local frame (`Scenario::local_origin`; the identity near the origin).
    pub fn from_scenario(s: &Scenario) -> Self {
        Self::cut_keeping(s, &vec![false; s.excavation.len()])
    }

    /// An input error when no block is left (excavations that remove every body): nothing to
    /// analyse, and every later step assumes a block.
    pub fn require_blocks(&self, label: &str) -> crate::error::Result<()> {
        match self.blocks.is_empty() {
            true => Err(crate::error::Error::input(
                label,
                "excavation",
                "the excavations remove every block: nothing is left to analyse",
            )),
            false => Ok(()),
        }
    }

    /// The rock mass of a staged analysis: as [`Self::from_scenario`], but the rock inside each
    /// excavation a stage removes stays as plug blocks (after the rock blocks, which are
    /// numbered as without stages) until that stage.
    pub fn staged(s: &Scenario) -> Self {
        let keep: Vec<bool> = (0..s.excavation.len()).map(|e| s.excavating_stage(e).is_some()).collect();
        Self::cut_keeping(s, &keep)
    }

    /// The blocks that stay once the plugs of the excavations `removed` are taken out, with each
    /// kept block's index here.
    pub fn without(&self, removed: &[bool]) -> (Self, Vec<Option<usize>>) {
        let gone = |b: &Block| b.excavation.is_some_and(|e| removed.get(e).copied().unwrap_or(false));
        let mut map = vec![None; self.blocks.len()];
        let mut blocks = Vec::new();
        for (i, b) in self.blocks.iter().enumerate().filter(|(_, b)| !gone(b)) {
            map[i] = Some(blocks.len());
            blocks.push(b.clone());
        }
        let g = Self {
            blocks,
            materials: self.materials.clone(),
            features: self.features.clone(),
            report: self.report.clone(),
            origin: self.origin,
        };
        (g, map)
    }

    fn cut_keeping(s: &Scenario, keep: &[bool]) -> Self {
        let origin = s.local_origin();
        let mut g = Self::cut(&s.shifted(origin), keep);
        g.origin = Vec3::from(origin);
        g
    }

    fn cut(s: &Scenario, keep: &[bool]) -> Self {
        let materials: Vec<Elastic> = s.material.iter().map(Elastic::new).collect();
        let initial = s
            .body
            .iter()
            .enumerate()
            .map(|(k, b)| cutting::RawBlock::new(k, shape::shape_to_pieces(&b.shape).expect("validated")))
            .collect();
        let (raw, report) = cutting::cut(s, initial, keep);
        let blocks = raw
            .into_iter()
            .map(|r| {
                let b = &s.body[r.body];
                let m = s.material.iter().position(|m| m.name == b.material).expect("validated");
                let mut block = Block::new(r.body, m, b.fixed, r.pieces);
                block.whole = b.fixed && !b.fixed_mesh;
                block.velocity = Vec3::from(b.velocity);
                block.angular_velocity = Vec3::from(b.angular_velocity);
                block.excavation = r.excavation;
                block
            })
            .collect();
        Self { blocks, materials, features: cutting::joint_features(s), report, origin: Vec3::zeros() }
    }

    /// Bounding box of all blocks.
    pub fn aabb(&self) -> Aabb {
        self.blocks.iter().map(|b| b.aabb()).reduce(|a, b| a.union(&b)).expect("at least one block")
    }
}
