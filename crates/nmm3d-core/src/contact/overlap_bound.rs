//! Overlaps a step starts with but did not make: a point that begins the step overlapping
//! while holding no force (missed by the step before, or measured against another contact
//! plane) would have its spring push that overlap out within the step — energy from nowhere,
//! more the smaller the step (`docs/theory/energy.md`, "Overlaps found at a step's start").

use nmm3d_geom::Vec3;

use super::history::ContactHistory;
use super::record::ContactRecord;
use super::transfer::{bound_missed_overlap, missed_floor};

impl ContactHistory {
    /// Points that started the step overlapping but holding no force — found so by the step's
    /// detection or its lagged verification, or held open by the open–close rules — and whose
    /// springs, pushing that overlap out in the trial just solved, did more work on the blocks
    /// than `budget` [J] (γ: the scheme's). That overlap was made before the step, unresisted,
    /// and its release is energy from nowhere (the Goodman tunnel's roof block: a corner found
    /// 1.9 mm in, +490 J in one 2 ms step). Their overlap beyond the deepest of their pair's
    /// points that held a force goes into their zero level in `saved`, the step's start
    /// records, as a missed overlap's does ([`bound_missed_overlap`]); the step is then solved
    /// again. Returns how many were bounded (counted in `missed_overlaps`).
    pub fn bound_pushed_overlaps(&mut self, saved: &mut [ContactRecord], gamma: f64, budget: f64) -> usize {
        let mut bounded = 0;
        if budget == f64::INFINITY {
            return bounded; // not guarded (a static step, `max_energy_gain = 0`): no scan
        }
        for k in 0..saved.len().min(self.records.len()) {
            let (r, s) = (&self.records[k], &saved[k]);
            if s.gap0 >= 0.0 || s.force != Vec3::zeros() || r.scheme_work(s, gamma) <= budget {
                continue;
            }
            let held = |j: &usize| *j != k && saved[*j].blocks == s.blocks && saved[*j].force != Vec3::zeros();
            let same: Vec<usize> = (0..saved.len()).filter(held).collect();
            let floor = missed_floor(saved, Some(&same), 0.0);
            if bound_missed_overlap(&mut saved[k], floor) {
                bounded += 1;
            }
        }
        self.missed_overlaps += bounded as u64;
        bounded
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::{test_point, ContactParams, ContactState};

    /// A point of blocks (1, 0) at x whose start record is `start` and whose solved trial
    /// pushed A out by `out` [m] along the normal with `force` [N].
    fn pushed(start: ContactRecord, x: f64, out: f64, force: f64) -> (ContactRecord, ContactRecord) {
        let mut s = start;
        s.a.reference.x = x;
        let mut r = s.clone();
        (r.rel, r.applied) = (Vec3::new(0.0, 0.0, out), Vec3::new(0.0, 0.0, force));
        (s, r)
    }

    #[test]
    fn an_overlap_held_with_no_force_and_pushed_out_with_energy_is_bounded() {
        let mut held = test_point(ContactState::Stick, -1e-6);
        held.force = Vec3::new(0.0, 0.0, 1e3);
        let found = test_point(ContactState::Stick, -1e-3);
        let points = [
            pushed(held.clone(), 0.0, 0.0, 1e3), // a spring that held its force: the pair's level
            pushed(found.clone(), 1.0, 1e-3, 1e6), // 1 mm out under 1 MN: 1 000 J
            pushed(found, 2.0, 1e-5, 1e5),       // 1 J: within the budget
            pushed(held, 3.0, 1e-3, 1e6),        // its overlap held a force: not from nowhere
        ];
        let (mut saved, records): (Vec<_>, Vec<_>) = points.into_iter().unzip();
        let mut h = ContactHistory { records, ..ContactHistory::new(ContactParams::for_test()) };
        assert_eq!(h.bound_pushed_overlaps(&mut saved, 1.0, 10.0), 1);
        assert_eq!(h.missed_overlaps, 1);
        // Bounded at the pair's deepest point that held a force; the overlap is still reported.
        assert!((saved[1].gap0 + 1e-6).abs() < 1e-18, "{}", saved[1].gap0);
        assert!((saved[1].gap0 + saved[1].raised + 1e-3).abs() < 1e-15);
        assert_eq!((saved[2].gap0, saved[3].gap0), (-1e-3, -1e-6));
        // Bounded, it no longer releases energy: a second pass finds nothing.
        assert_eq!(h.bound_pushed_overlaps(&mut saved, 1.0, 10.0), 0);
    }
}
