//! Result writers: `summary.json`, `history.csv`, `diagnostics.csv`, `cuts.csv`, `blocks.csv`,
//! `result.pvd` + `frames/*.vtu`.

pub mod atomic;
pub mod checks;
pub mod cuts;
pub mod frame;
pub mod layout;
pub mod progress;
pub mod run_dir;
pub mod summary;
pub mod tables;
pub mod vtu;
