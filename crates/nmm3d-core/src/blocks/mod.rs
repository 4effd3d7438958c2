//! Block reports without running: `nmm3d blocks` (the table, the files) and the block surfaces
//! the key-block analysis reads (`nmm3d keyblocks`).

mod report;
mod surfaces;

pub use report::{cover_report, report, table};
pub use surfaces::surfaces;
