//! Element matrices and loads: kernels make local blocks, the assembler scatters them.

pub mod bolt;
pub mod grout;
pub mod kernel;
pub mod loads;
pub mod penalty;

pub use kernel::{element_kernel, ElementKernel};
pub use penalty::PointConstraint;
