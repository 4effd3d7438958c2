//! The three-dimensional numerical manifold method (NMM).
//!
//! | symbol | meaning | where |
//! |---|---|---|
//! | $w_i(\mathbf x)$ | weight function of a mathematical cover (mesh node) | [`cover::pattern`] |
//! | $\mathbf d_i$ | displacement of physical cover $i$ (3 DOFs, constant cover function) | [`cover::PhysicalCover`] |
//! | ME | manifold element = connected part of (sub-cell ∩ block) | [`cover::ManifoldElement`] |
//! | $\mathbf K_e, \mathbf M_e$ | element stiffness and consistent mass | [`element`] |
//! | $(\mathbf K + \mathbf M/(\beta\Delta t^2))\,\mathbf d = \dots$ | implicit step | [`time`] |
//!
//! Layers, lowest first (a module uses only its own layer and those below; the table and its
//! test are in `ARCHITECTURE.md`): `error` → `scenario` → `model` → `input` → `cover` →
//! `element` → `assembly` → `solver` → `system` → `state` → `contact` → `time` → `monitor` →
//! `output` → `checkpoint` → `blocks` → `simulation`.
#![warn(missing_docs)]

pub mod assembly;
pub mod blocks;
pub mod checkpoint;
pub mod contact;
pub mod cover;
pub mod element;
pub mod error;
pub mod input;
pub mod model;
pub mod monitor;
pub mod output;
pub mod packed;
pub mod scenario;
pub mod simulation;
pub mod solver;
pub mod state;
pub mod system;
pub mod time;

pub use error::{Error, Result};
