//! Transfer of contact information (thesis Part 3-B, "post-transferring"): a point detected
//! now inherits from the previous step's point of the same block pair nearest it.

use nmm3d_geom::Vec3;

use super::record::{tangential, ContactParams, ContactRecord, ContactState, Strength};

/// Transfer to a new point `r` what its predecessor — the previous point of the same block
/// pair nearest it — carried: zero level always; state, shear, slip, preload and bond when the
/// predecessor is within the transfer distance and closed; a pair already sliding makes a new
/// point slide at the Coulomb limit instead of braking as a fresh stuck spring.
pub(super) fn inherit(
    r: &mut ContactRecord,
    previous: &[ContactRecord],
    candidates: Option<&Vec<usize>>,
    p: &ContactParams,
    locked: bool,
) {
    let q_gap = r.gap0;
    let nearest_old = nearest(previous, candidates, &r.a.reference, f64::INFINITY);
    if let Some(old) = nearest_old {
        (r.offset, r.raised) = (old.offset, old.raised);
    }
    (r.gap0, r.gap) = (q_gap - r.offset, q_gap - r.offset);
    let tan_phi = r.strength.tan_phi;
    if let Some(old) = nearest_old.filter(|o| (o.a.reference - r.a.reference).norm() < REACH * p.tolerance) {
        if old.state != ContactState::Open {
            // Still closed unless the springs would pull harder than the bond holds.
            let pull = r.kn * r.gap0 - r.normal.dot(&old.preload);
            let band = p.band * r.kn;
            r.state = if locked || pull <= old.strength.tension + band { old.state } else { ContactState::Open };
            r.shear0 = tangential(&r.normal) * old.shear0;
            r.slip = old.slip;
            r.preload = old.preload;
            r.strength = Strength { tan_phi, ..old.strength };
            r.force = old.force;
            if r.state == ContactState::Slide {
                // Linearise the friction about the last step's slip, not about rest.
                r.rel = old.rel;
            }
        }
    } else if let Some(old) = nearest_old {
        if old.state == ContactState::Slide && r.state == ContactState::Stick {
            r.state = ContactState::Slide;
            r.slip = old.slip;
            r.rel = old.rel;
            r.shear0 = r.slip * (tan_phi * (-r.kn * r.gap0).max(0.0) / r.ks);
        }
    }
    r.limit = r.coulomb_limit(r.gap0);
}

/// Bound an overlap found deeper than one can arise between two detections (`floor`, a gap
/// [m]; see [`missed_floor`]). It was
/// missed by an earlier detection, not made in this step, and its spring would push it out at
/// once with energy from nowhere (½ k_n δ² — 4 MJ on the thesis slope from a 10 cm overlap that
/// a corrected material point revealed). The excess goes into the zero level (`raised`, as a
/// raise of the penalty does): the spring resists further overlap and `max_penetration` still
/// reports the geometric one. True if the point's overlap was bounded.
pub(super) fn bound_missed_overlap(r: &mut ContactRecord, floor: f64) -> bool {
    if r.gap0 >= floor {
        return false;
    }
    r.shift_zero_level(r.gap0 - floor);
    r.limit = r.coulomb_limit(r.gap0);
    true
}

/// The deepest gap at which a detection can find a new point: beyond the deepest previous point
/// of its pair (beyond touching where there was none) by `reach` [m], the transfer distance — a
/// pair closes by at most the support tolerance between two detections, and the lagged
/// verification adds every point arriving deeper within a step unless a point of the pair lies
/// within the transfer distance. (Arrivals are not bounded: at one tolerance their bounded
/// levels, handed on by transfer, left the dominos 1 mm and case A 76 mm deep.)
pub(super) fn missed_floor(previous: &[ContactRecord], candidates: Option<&Vec<usize>>, reach: f64) -> f64 {
    let deepest = candidates.into_iter().flatten().map(|&k| previous[k].gap.min(previous[k].gap0));
    deepest.fold(0.0, f64::min) - reach
}

/// The transfer distance, in support tolerances: a new point within it of a previous one is
/// that point (thesis Part 3-B; the lagged verification's "known" points likewise).
pub(super) const REACH: f64 = 10.0;

/// The previous point (among `candidates`) nearest `x` within `reach`.
fn nearest<'a>(
    previous: &'a [ContactRecord],
    candidates: Option<&Vec<usize>>,
    x: &Vec3,
    reach: f64,
) -> Option<&'a ContactRecord> {
    candidates?
        .iter()
        .map(|&k| &previous[k])
        .map(|o| ((o.a.reference - x).norm(), o))
        .filter(|(d, _)| *d < reach)
        .min_by(|p, q| p.0.total_cmp(&q.0))
        .map(|(_, o)| o)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::test_point;

    /// A new point at x on the joint, stuck and touching (as `fresh` makes it).
    fn new_at(x: f64, gap: f64) -> ContactRecord {
        let mut r = test_point(ContactState::Stick, gap);
        r.a.reference.x = x;
        r.strength.tan_phi = 0.7;
        r
    }

    /// The previous step's point at x.
    fn old_at(x: f64, state: ContactState) -> ContactRecord {
        let mut r = test_point(state, -1e-6);
        r.a.reference.x = x;
        r.offset = 2e-5;
        r.shear0 = Vec3::new(3e-7, 0.0, 1e-7);
        r.slip = Vec3::x();
        r.preload = Vec3::new(0.0, 0.0, 1e3);
        r.strength.cohesion = 40.0;
        r
    }

    fn transferred(new: ContactRecord, old: ContactRecord, locked: bool) -> ContactRecord {
        let mut r = new;
        inherit(&mut r, &[old], Some(&vec![0]), &ContactParams::for_test(), locked);
        r
    }

    #[test]
    fn a_point_with_no_predecessor_keeps_its_fresh_state() {
        let mut r = new_at(0.0, -1e-6);
        inherit(&mut r, &[], None, &ContactParams::for_test(), false);
        assert_eq!((r.state, r.offset, r.shear0), (ContactState::Stick, 0.0, Vec3::zeros()));
    }

    #[test]
    fn a_closed_predecessor_within_reach_hands_over_its_history() {
        for state in [ContactState::Stick, ContactState::Slide] {
            let r = transferred(new_at(0.001, -1e-6), old_at(0.0, state), false);
            assert_eq!(r.state, state);
            assert_eq!(r.offset, 2e-5, "the zero level is carried");
            assert_eq!(r.gap0, -1e-6 - 2e-5);
            assert_eq!(r.shear0, Vec3::new(3e-7, 0.0, 0.0), "shear projected on the new tangent plane");
            assert_eq!((r.slip, r.preload), (Vec3::x(), Vec3::new(0.0, 0.0, 1e3)));
            assert_eq!((r.strength.cohesion, r.strength.tan_phi), (40.0, 0.7), "bond kept, friction of the joint now");
        }
    }

    #[test]
    fn springs_pulling_beyond_the_bond_open_the_new_point_unless_locked() {
        let old = old_at(0.0, ContactState::Stick);
        // 2e-5 m apart once the zero level is taken off: k_n g = 20 kN of pull against a 1 kN preload.
        assert_eq!(transferred(new_at(0.001, 4e-5), old.clone(), false).state, ContactState::Open);
        assert_eq!(transferred(new_at(0.001, 4e-5), old, true).state, ContactState::Stick);
    }

    #[test]
    fn beyond_reach_only_sliding_carries_over() {
        // 10 × the tolerance away: no history, but a pair already sliding keeps sliding.
        let r = transferred(new_at(0.02, -1e-6), old_at(0.0, ContactState::Slide), false);
        assert_eq!((r.state, r.slip, r.strength.cohesion), (ContactState::Slide, Vec3::x(), 0.0));
        let r = transferred(new_at(0.02, -1e-6), old_at(0.0, ContactState::Stick), false);
        assert_eq!((r.state, r.shear0), (ContactState::Stick, Vec3::zeros()));
    }

    #[test]
    fn an_overlap_found_deeper_than_a_detection_lets_one_arise_is_bounded() {
        let p = ContactParams::for_test();
        let tol = p.tolerance;
        // No point in the pair before: found 30 tolerances deep, kept at the transfer distance
        // (10), the rest in the zero level.
        let mut r = new_at(0.0, -30.0 * tol);
        assert!(bound_missed_overlap(&mut r, missed_floor(&[], None, REACH * p.tolerance)));
        assert!((r.gap0 + 10.0 * tol).abs() < 1e-15 && (r.raised + 20.0 * tol).abs() < 1e-15);
        assert!((-(r.gap + r.raised) - 30.0 * tol).abs() < 1e-15, "the geometric overlap is still reported");
        // A point of the pair as deep, however far away: nothing was missed.
        let mut old = old_at(5.0, ContactState::Stick);
        (old.gap0, old.gap) = (-25.0 * tol, -25.0 * tol);
        let mut r = new_at(0.0, -30.0 * tol);
        assert!(!bound_missed_overlap(&mut r, missed_floor(&[old], Some(&vec![0]), REACH * p.tolerance)));
        assert_eq!(r.gap0, -30.0 * tol);
        // Within the transfer distance of touching: an arrival near a known point, left as it is.
        let mut r = new_at(0.0, -9.0 * tol);
        assert!(!bound_missed_overlap(&mut r, missed_floor(&[], None, REACH * p.tolerance)));
    }

    #[test]
    fn an_open_predecessor_hands_over_only_the_zero_level() {
        let r = transferred(new_at(0.001, -1e-6), old_at(0.0, ContactState::Open), false);
        assert_eq!((r.state, r.offset, r.shear0), (ContactState::Stick, 2e-5, Vec3::zeros()));
    }
}
