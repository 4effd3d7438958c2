//! Result writers: `summary.json`, `history.csv`, `blocks.csv`, `result.pvd` + `frames/*.vtu`.

pub mod atomic;
pub mod checks;
pub mod progress;
pub mod tables;
pub mod vtu;
