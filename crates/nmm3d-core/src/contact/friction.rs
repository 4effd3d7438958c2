//! Coulomb friction of a sliding point: the return mapping onto the friction limit and its
//! consistent tangent (Wriggers, Computational Contact Mechanics §5.2; 3DEC), and the shear
//! spring carried over an accepted step with the friction it dissipated.

use nmm3d_geom::{Mat3, Vec3};

use super::record::{tangential, ContactRecord, ContactState};
use super::set::ContactSet;

impl ContactRecord {
    /// Sliding friction on A at the last iterate and its tangent: f = L ĥ with ĥ the direction of
    /// the elastic trial force h = t·P − k_s (s₀ + t·rel) and L the friction limit (`limit`);
    /// df/d(rel) = −K, K = k_s min(L/|h|, 1) (t − ĥ ĥᵀ).
    pub fn friction(&self) -> (Vec3, Mat3) {
        let ks = self.ks;
        let t = tangential(&self.normal);
        let h = t * self.preload - ks * (self.shear0 + t * self.rel);
        let limit = self.limit;
        if h.norm() <= f64::EPSILON * (limit + ks * self.shear0.norm()) {
            return (-limit * self.slip, Mat3::zeros());
        }
        let hat = h.normalize();
        (limit * hat, ks * (limit / h.norm()).min(1.0) * (t - hat * hat.transpose()))
    }
}

impl ContactSet {
    /// After an accepted step: carry the shear-spring extension. A sliding point's spring is
    /// left at the Coulomb limit, so the force is continuous when it sticks again (a reset
    /// spring would drop the friction force at every stick–slip flip and ratchet the block).
    /// Returns the energy friction dissipated in the step: at each sliding point the limit
    /// times the slip beyond the spring's elastic change [J].
    pub fn accept(&mut self) -> f64 {
        let mut dissipated = 0.0;
        for r in &mut self.records {
            let t = tangential(&r.normal);
            let shear = match r.state {
                ContactState::Stick => r.shear0 + t * r.rel,
                ContactState::Slide => (t * r.preload + r.limit * r.slip) / r.ks,
                ContactState::Open => Vec3::zeros(),
            };
            if r.state == ContactState::Slide {
                dissipated += r.limit * (t * r.rel - (shear - r.shear0)).norm();
            }
            r.shear0 = shear;
        }
        dissipated
    }
}
