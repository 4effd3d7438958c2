//! The cover system: mathematical mesh and patterns, manifold elements, physical covers.

pub mod aggregation;
pub mod build;
pub mod manifold_element;
pub mod mesh;
pub mod meshes;
mod numbering;
pub mod pattern;
pub mod physical_cover;
pub mod poly;

pub use build::Covers;
pub use manifold_element::ManifoldElement;
pub use mesh::MathMesh;
pub use pattern::PatternTable;
pub use physical_cover::PhysicalCover;
