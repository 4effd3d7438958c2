//! Penalty springs of a contact point: the linearised spring of its state (normal and
//! tangential springs when stuck, the normal spring and friction when sliding, nothing when open;
//! thesis Table 3-2) and the raising of penalties.

use nmm3d_geom::{Mat3, Vec3};

use super::record::{tangential, ContactRecord, ContactState};

impl ContactRecord {
    /// Multiply the point's penalties by `factor`; the shear spring keeps its force. A joint's
    /// own stiffness is physical and stays.
    pub fn stiffen(&mut self, factor: f64) {
        if self.joint_stiffness {
            return;
        }
        self.kn *= factor;
        self.ks *= factor;
        self.shear0 /= factor;
    }

    /// The point's spring in its current state, linearised: stiffness (3 × 3) and the constant
    /// force on A (B takes the opposite).
    pub fn spring(&self) -> (Mat3, Vec3) {
        let (kn, ks) = (self.kn, self.ks);
        let n = self.normal;
        let t = tangential(&n);
        let mut block = kn * n * n.transpose();
        let mut force = -kn * self.gap0 * n;
        match self.state {
            ContactState::Stick => {
                block += ks * t;
                force += self.preload - ks * self.shear0;
            }
            ContactState::Slide => {
                // Friction linearised about the last iterate (return mapping, consistent
                // tangent; Wriggers, Computational Contact Mechanics §5.2): the force keeps
                // the Coulomb magnitude and turns with the trial direction, so sideways motion
                // of a sliding point meets stiffness instead of a fixed-direction force.
                let (f_k, k_t) = self.friction();
                block += k_t;
                force += n * n.dot(&self.preload) + f_k + k_t * self.rel;
            }
            ContactState::Open => return (Mat3::zeros(), Vec3::zeros()),
        }
        (block, force)
    }
}
