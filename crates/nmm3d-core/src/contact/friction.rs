//! Coulomb friction of a sliding point: the return mapping onto the friction limit and its
//! consistent tangent (Wriggers, Computational Contact Mechanics §5.2; 3DEC), and the shear
//! spring carried over an accepted step with the friction it dissipated.

use nmm3d_geom::{Mat3, Vec3};

use super::history::ContactHistory;
use super::record::{tangential, ContactRecord, ContactState};

impl ContactRecord {
    /// Shear force on A of the shear spring stretched by `extension`, with the tangential
    /// preload: t·P − k_s s [N].
    pub fn shear_force(&self, extension: &Vec3) -> Vec3 {
        tangential(&self.normal) * self.preload - self.ks * extension
    }

    /// Coulomb limit at normal gap `gap`: tan φ (n·P − k_n g)⁺ + c [N].
    pub fn coulomb_limit(&self, gap: f64) -> f64 {
        let s = self.strength;
        s.tan_phi * (self.normal.dot(&self.preload) - self.kn * gap).max(0.0) + s.cohesion
    }

    /// Sliding friction on A at the last iterate and its tangent: f = L ĥ with ĥ the direction of
    /// the elastic trial force h = t·P − k_s (s₀ + t·rel) and L the friction limit (`limit`);
    /// df/d(rel) = −K, K = k_s min(L/|h|, 1) (t − ĥ ĥᵀ).
    pub fn friction(&self) -> (Vec3, Mat3) {
        let (ks, t) = (self.ks, tangential(&self.normal));
        let h = self.shear_force(&(self.shear0 + t * self.rel));
        let limit = self.limit;
        if h.norm() <= f64::EPSILON * (limit + ks * self.shear0.norm()) {
            return (-limit * self.slip, Mat3::zeros());
        }
        let hat = h.normalize();
        (limit * hat, ks * (limit / h.norm()).min(1.0) * (t - hat * hat.transpose()))
    }
}

impl ContactHistory {
    /// After an accepted step: carry the shear-spring extension (and let open points hand back
    /// their raised overlap, `ContactRecord::relax_raised`). A sliding point's spring is
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
            r.relax_raised();
        }
        dissipated
    }
}

impl ContactHistory {
    /// Release the lock of the initial equilibrium: a closed point whose locked shear spring
    /// pulls harder than the friction limit is returned onto it (the spring shortened until
    /// |t·P − k_s s₀| = L). The energy that frees is the locked equilibrium's, not the run's:
    /// the run's energy accounts start after it. Returns how many points were returned.
    pub fn release(&mut self) -> usize {
        let mut released = 0;
        for r in self.records.iter_mut().filter(|r| r.state != ContactState::Open) {
            let h = r.shear_force(&r.shear0);
            if h.norm() > r.limit && r.ks > 0.0 {
                // The extension s₀′ with t·P − k_s s₀′ = L ĥ.
                r.shear0 = (tangential(&r.normal) * r.preload - r.limit * h.normalize()) / r.ks;
                released += 1;
            }
        }
        released
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::{test_point, ContactParams};

    fn set_of(r: ContactRecord) -> ContactHistory {
        ContactHistory { records: vec![r], ..ContactHistory::new(ContactParams::for_test()) }
    }

    #[test]
    fn a_sliding_point_keeps_its_spring_at_the_limit_and_dissipates_the_rest() {
        let mut r = test_point(ContactState::Slide, -1e-6);
        (r.limit, r.slip, r.rel) = (500.0, Vec3::x(), Vec3::new(1e-5, 0.0, 0.0));
        let mut set = set_of(r);
        let dissipated = set.accept();
        // The spring holds the Coulomb force (500 N / 1e9 N/m); the rest of the slip is friction work.
        assert!((set.records[0].shear0 - Vec3::new(5e-7, 0.0, 0.0)).norm() < 1e-18);
        assert!((dissipated - 500.0 * (1e-5 - 5e-7)).abs() < 1e-12);
    }

    #[test]
    fn a_stuck_point_carries_its_shear_and_dissipates_nothing() {
        let mut r = test_point(ContactState::Stick, -1e-6);
        (r.shear0, r.rel) = (Vec3::new(1e-7, 0.0, 0.0), Vec3::new(2e-7, 0.0, 5e-7));
        let mut set = set_of(r);
        assert_eq!(set.accept(), 0.0);
        assert!(
            (set.records[0].shear0 - Vec3::new(3e-7, 0.0, 0.0)).norm() < 1e-20,
            "only the tangential motion stretches it"
        );
    }

    #[test]
    fn release_returns_an_overstressed_locked_spring_onto_the_coulomb_limit() {
        // Locked at 3 µm × 1e9 N/m = 3 kN of shear against a limit of 500 N; another within it.
        let mut over = test_point(ContactState::Stick, -1e-6);
        (over.limit, over.shear0) = (500.0, Vec3::new(0.0, -3e-6, 0.0));
        let mut within = over.clone();
        within.shear0 = Vec3::new(2e-7, 0.0, 0.0);
        let mut set = set_of(over);
        set.records.push(within);
        assert_eq!(set.release(), 1);
        assert!((set.records[0].shear0 - Vec3::new(0.0, -5e-7, 0.0)).norm() < 1e-18, "500 N, same direction");
        assert_eq!(set.records[1].shear0, Vec3::new(2e-7, 0.0, 0.0));
    }

    #[test]
    fn friction_opposes_the_trial_shear_with_the_coulomb_magnitude() {
        let mut r = test_point(ContactState::Slide, -1e-6);
        (r.limit, r.shear0) = (500.0, Vec3::new(0.0, -3e-6, 0.0));
        let (f, k) = r.friction();
        assert!((f - Vec3::new(0.0, 500.0, 0.0)).norm() < 1e-9);
        assert!((k - 1e9 * (500.0 / 3000.0) * Mat3::from_diagonal(&Vec3::new(1.0, 0.0, 0.0))).norm() < 1e-3);
    }
}
