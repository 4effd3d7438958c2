//! Global assembly: equation numbering, sparsity pattern, scatter.

pub mod assembler;
pub mod coupling;
pub mod dof_map;
mod product;
pub mod sparsity;

pub use assembler::Assembler;
pub use coupling::Coupling;
pub use dof_map::DofMap;
pub use sparsity::SparsityPattern;
