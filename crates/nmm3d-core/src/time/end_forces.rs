//! The elements' rotations and forces where a step's equilibrium left it, for the next step's
//! start (`residual`).

use nmm3d_geom::{Mat3, Vec3};

/// The moving elements' rotations and forces at the displacements `u`, each rotation found from
/// the guess in `guesses` (the rotations of the state then). A step's last equilibrium
/// correction measures them where the step ends; the next step starts there from the same
/// guesses, and would find the same rotations and forces bit for bit — so it takes them and
/// only adds what they lack (tension, tangent), one element loop fewer per step.
pub(super) struct EndForces {
    pub(super) u: Vec<Vec3>,
    pub(super) guesses: Vec<Mat3>,
    pub(super) elements: Vec<ElementForces>,
}

/// An ME's index, rotation and internal force per cover.
pub(super) type ElementForces = (usize, Mat3, Vec<Vec3>);
