//! Penalty springs of a contact point: the linearised spring of its state (normal and
//! tangential springs when stuck, the normal spring and friction when sliding, nothing when open;
//! thesis Table 3-2) and the raising of penalties.

use nmm3d_geom::{Mat3, Vec3};

use super::record::{tangential, ContactRecord, ContactState};

impl ContactRecord {
    /// Multiply the point's penalties by `factor`, each spring keeping its force: the shear
    /// extension and the overlap at the start of the step shrink by `factor` (the rest of the
    /// overlap goes into the zero level, `raised`). Stiffer springs resist further overlap; they
    /// do not push out the one there is, which would release ten times its spring energy. A
    /// joint's own stiffness is physical and stays.
    pub fn stiffen(&mut self, factor: f64) {
        if self.joint_stiffness {
            return;
        }
        self.kn *= factor;
        self.ks *= factor;
        self.shear0 /= factor;
        if self.state != ContactState::Open && self.gap0 < 0.0 {
            self.shift_zero_level(self.gap0 * (1.0 - 1.0 / factor));
        }
    }

    /// An open point hands back the overlap its zero level took (`raised`) as far as its gap
    /// allows: the zero level follows the separating faces back up to the geometric one, so a
    /// point that closes again meets its spring where the faces touch. Open, the spring holds
    /// no force before or after (the gap stays ≥ 0), so no energy changes hands. A raised
    /// level kept after opening would let the point — and, by transfer, its successors — sink
    /// deeper at every closure (`max_penetration` reports −(gap + raised)).
    pub fn relax_raised(&mut self) {
        if self.state == ContactState::Open && self.raised < 0.0 && self.gap > 0.0 {
            self.shift_zero_level(self.gap.min(-self.raised));
        }
    }

    /// Move `shift` of the overlap into the zero level (≤ 0; > 0 hands it back): the spring no
    /// longer pushes it out, `raised` keeps it so the geometric overlap −(gap + raised) is
    /// still reported.
    pub(super) fn shift_zero_level(&mut self, shift: f64) {
        self.offset += shift;
        self.raised += shift;
        self.gap0 -= shift;
        self.gap -= shift;
    }

    /// The point's spring in its current state with its dashpot (`super::damping`),
    /// linearised: stiffness (3 × 3) and the constant force on A (B takes the opposite).
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
        let (damping, damper) = self.dashpot();
        (block + damping, force + damper)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::test_point;

    fn close(a: &Mat3, b: &Mat3) -> bool {
        (a - b).norm() <= 1e-9 * b.norm().max(1.0)
    }

    /// Thesis Table 3-2: which springs each state applies.
    #[test]
    fn table_3_2_springs_of_each_state() {
        let (kn, ks) = (1e9, 1e9);
        let normal = kn * Mat3::from_diagonal(&Vec3::new(0.0, 0.0, 1.0));
        let tangential = ks * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 0.0));

        // Separate: no spring, no force.
        let r = test_point(ContactState::Open, -1e-6);
        assert_eq!(r.spring(), (Mat3::zeros(), Vec3::zeros()));

        // Stick: normal and tangential springs; the shear spring's force acts.
        let mut r = test_point(ContactState::Stick, -1e-6);
        r.shear0 = Vec3::new(1e-7, 0.0, 0.0);
        let (block, force) = r.spring();
        assert!(close(&block, &(normal + tangential)));
        assert!((force - Vec3::new(-100.0, 0.0, 1e3)).norm() < 1e-9);

        // Slide: the normal spring and a friction force of the Coulomb magnitude against the
        // trial shear, stiff only across the slip (the consistent tangent).
        let mut r = test_point(ContactState::Slide, -1e-6);
        r.shear0 = Vec3::new(2e-6, 0.0, 0.0);
        r.limit = 500.0;
        r.slip = Vec3::x();
        let (block, force) = r.spring();
        let across = 0.25 * ks * Mat3::from_diagonal(&Vec3::new(0.0, 1.0, 0.0));
        assert!(close(&block, &(normal + across)));
        assert!((force - Vec3::new(-500.0, 0.0, 1e3)).norm() < 1e-9);
    }

    #[test]
    fn raising_the_penalties_keeps_the_normal_force_and_the_geometric_overlap() {
        // 2 mm into a 1e9 N/m spring: 2 MN before and after a ×10 raise, the rest of the
        // overlap in the zero level; the overlap itself is still 2 mm.
        let mut r = test_point(ContactState::Stick, -2e-3);
        let before = r.spring().1;
        r.stiffen(10.0);
        assert!((r.spring().1 - before).norm() < 1e-6 * before.norm(), "{:?} vs {before:?}", r.spring().1);
        assert!((r.gap0 + 2e-4).abs() < 1e-15 && (r.raised + 1.8e-3).abs() < 1e-15);
        assert!((-(r.gap + r.raised) - 2e-3).abs() < 1e-15);
        // An open point keeps its gap.
        let mut open = test_point(ContactState::Open, 1e-3);
        open.stiffen(10.0);
        assert_eq!((open.gap0, open.raised), (1e-3, 0.0));
    }

    #[test]
    fn an_open_point_hands_its_raised_overlap_back_as_far_as_its_gap_allows() {
        let mut r = test_point(ContactState::Stick, -2e-3);
        r.stiffen(10.0);
        let geometric = |r: &ContactRecord| r.gap + r.raised;
        // Still closed: the raise stays.
        let kept = r.clone();
        r.relax_raised();
        assert_eq!((r.raised, r.gap), (kept.raised, kept.gap));
        // Opened 1 mm past the raised level: 1 mm of the 1.8 mm is handed back, touching at
        // the end; the geometric gap is unchanged.
        (r.state, r.gap) = (ContactState::Open, 1e-3);
        let before = geometric(&r);
        r.relax_raised();
        assert!((r.raised + 0.8e-3).abs() < 1e-15 && r.gap.abs() < 1e-15);
        assert!((geometric(&r) - before).abs() < 1e-15);
        // Apart by more than the raise: all of it, the gap the geometric one.
        r.gap = 5e-3;
        r.relax_raised();
        assert_eq!(r.raised, 0.0);
        assert!((r.gap - 4.2e-3).abs() < 1e-15);
    }

    #[test]
    fn raising_the_penalties_keeps_the_shear_force_but_not_a_joint_stiffness() {
        let mut r = test_point(ContactState::Stick, 0.0);
        r.shear0 = Vec3::new(1e-7, 0.0, 0.0);
        let before = r.ks * r.shear0;
        r.stiffen(10.0);
        assert_eq!((r.kn, r.ks), (1e10, 1e10));
        assert!((r.ks * r.shear0 - before).norm() < 1e-12);
        let mut j = test_point(ContactState::Stick, 0.0);
        j.joint_stiffness = true;
        j.stiffen(10.0);
        assert_eq!((j.kn, j.ks), (1e9, 1e9));
    }
}
