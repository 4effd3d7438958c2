//! Transfer of contact information (thesis Part 3-B, "post-transferring"): a point detected
//! now inherits from the previous step's point of the same block pair nearest it.

use nmm3d_geom::Vec3;

use super::record::{tangential, ContactParams, ContactRecord, ContactState, Strength};
use super::rules::GAP_BAND;

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
        r.offset = old.offset;
    }
    (r.gap0, r.gap) = (q_gap - r.offset, q_gap - r.offset);
    let tan_phi = r.strength.tan_phi;
    if let Some(old) = nearest_old.filter(|o| (o.a.reference - r.a.reference).norm() < 10.0 * p.tolerance) {
        if old.state != ContactState::Open {
            // Still closed unless the springs would pull harder than the bond holds.
            let pull = r.kn * r.gap0 - r.normal.dot(&old.preload);
            let band = GAP_BAND * p.size * r.kn;
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
    r.limit = r.strength.tan_phi * (r.normal.dot(&r.preload) - r.kn * r.gap0).max(0.0) + r.strength.cohesion;
}

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
