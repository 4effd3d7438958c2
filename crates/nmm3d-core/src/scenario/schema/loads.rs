//! Boundary conditions and loads: constraints, fixed points, point and surface loads, in-situ
//! stress.

use serde::{Deserialize, Serialize};

/// A region of space.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Region {
    /// Axis-aligned box.
    Box {
        /// Lower corner [m].
        min: [f64; 3],
        /// Upper corner [m].
        max: [f64; 3],
    },
}

/// Axis names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// East.
    X,
    /// North.
    Y,
    /// Up.
    Z,
}

/// `[[constraint]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    /// Region whose boundary vertices are held.
    pub select: Region,
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[fixed_point]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FixedPoint {
    /// Point [m].
    pub point: [f64; 3],
    /// Held directions.
    pub directions: Vec<Axis>,
}

/// `[[point_load]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointLoad {
    /// Point [m].
    pub point: [f64; 3],
    /// Force [N].
    pub force: [f64; 3],
}

/// `[[surface_load]]`: a dead traction on the block boundary faces inside a region.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceLoad {
    /// Region: boundary faces with every vertex inside are loaded.
    pub select: Region,
    /// Only faces whose outward normal lies within 1° of this direction (optional).
    #[serde(default)]
    pub normal: Option<[f64; 3]>,
    /// Traction [Pa].
    pub traction: [f64; 3],
}

/// `[in_situ_stress]`, compression negative.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InSituStress {
    /// xx, yy, zz, xy, yz, zx [Pa].
    pub stress: [f64; 6],
    /// Gradient in z [Pa/m].
    #[serde(default)]
    pub gradient: [f64; 6],
    /// Height where `stress` applies [m].
    #[serde(default)]
    pub reference_z: f64,
}
