//! The open–close state rules (thesis Table 3-1; the table of the module documentation): after
//! each solve of a step's open–close iteration every point is updated from the increments, with
//! hysteresis on gap and friction cone so that points at zero force do not flip with round-off.

use nmm3d_geom::Vec3;

use super::history::ContactHistory;
use super::record::{tangential, ContactRecord, ContactState};
use crate::system::System;

impl ContactHistory {
    /// Update every point from the solved increments `d`: how many changed state (their block
    /// pairs replace those in `changes`, with the pair of the sliding point whose friction
    /// turned beyond `slip_turn`, which also counts as a change), and how far
    /// the forces the solve applied are from the forces of the updated states (summed over the
    /// points, relative to the sum of the updated forces).
    pub fn update_states(&mut self, sys: &System, d: &[Vec3], changes: &mut Vec<(usize, usize)>) -> (usize, f64) {
        let locked = self.locked;
        let p = &self.params;
        let hysteresis = (p.band, p.reclose, p.max_reclose, p.tolerance);
        let mut changed = 0;
        changes.clear();
        // Largest change of a sliding point's friction force, and the largest friction limit.
        let (mut turned, mut largest) = (0.0f64, 0.0f64);
        // The block pair of the point whose friction turned most (named by a cut it causes).
        let mut turned_pair = None;
        let (mut mismatch, mut total) = (0.0f64, 0.0f64);
        for r in &mut self.records {
            // The spring this solve used, linearised about the last iterate.
            let (block, constant) = r.spring();
            let (dashpot, pushed) = r.dashpot();
            // The friction this solve used (linearised about the last iterate).
            let used = (r.state == ContactState::Slide).then(|| r.friction().0);
            r.rel = r.a.of(sys, d) - r.b.of(sys, d);
            r.gap = r.gap0 + r.normal.dot(&r.rel);
            let (kn, ks) = (r.kn, r.ks);
            let n = r.normal;
            let t = tangential(&n);
            if r.state == ContactState::Open && r.gap <= 0.0 {
                // Closing: the shear spring starts where the point entered (the fraction of
                // the step's motion spent closing the gap does not stretch it; DDA's entrance).
                let entered = if r.gap0 > 0.0 { r.gap0 / (r.gap0 - r.gap) } else { 0.0 };
                r.shear0 = -entered * (t * r.rel);
            }
            let shear = r.shear0 + t * r.rel;
            // Elastic trial: forces on A if the springs held (return mapping onto the Coulomb
            // limit, as in 3DEC; a sliding point's spring sits at the limit, see `accept`).
            let normal = n.dot(&r.preload) - kn * r.gap;
            let held = r.shear_force(&shear);
            let limit = r.coulomb_limit(r.gap);
            let closing = r.state == ContactState::Open;
            let new = next_state(r, normal, &held, limit, hysteresis, locked);
            if new == ContactState::Slide && held.norm() > 0.0 {
                // A slips against the force that would hold it.
                largest = largest.max(limit);
                r.slip = -held.normalize();
                // The friction magnitude follows the normal force of the last solve — unless
                // the point was open in it: its overlap there had no spring to stop it, and
                // friction from it would be fictitious (and feed back until the iteration
                // diverges where many points close at once). It starts frictionless and takes
                // its real normal force at the next iteration.
                r.limit = if closing { 0.0 } else { limit };
                if let Some(u) = used {
                    let turn = (-limit * r.slip - u).norm();
                    if turn > turned {
                        (turned, turned_pair) = (turn, Some(r.blocks));
                    }
                }
            }
            if new != r.state {
                changed += 1;
                changes.push(r.blocks);
                if new != ContactState::Stick {
                    r.strength = r.strength.broken();
                }
                if new == ContactState::Open {
                    r.preload = Vec3::zeros();
                    r.opened = true;
                }
                if closing {
                    r.reclosed += 1;
                }
                r.state = new;
            }
            r.force = match r.state {
                ContactState::Open => Vec3::zeros(),
                ContactState::Stick => r.preload - kn * r.gap * n - ks * shear,
                ContactState::Slide => n * n.dot(&r.preload) - kn * r.gap * n + r.friction().0,
            };
            // The dashpot as solved (its state's) and as it acts in the updated state.
            r.damper.end = pushed - dashpot * r.rel;
            r.force += r.damper_force(&r.rel);
            r.applied = constant - block * r.rel;
            mismatch += (r.applied - r.force).norm();
            total += r.force.norm();
        }
        // The friction was linearised about the last iterate (its magnitude from the last
        // normal force, its direction from the last trial): if some sliding point's friction
        // changed by more than the tolerance (relative to the largest friction force), iterate
        // again, as for a change of state.
        if turned > self.params.slip_turn * largest {
            changed += 1;
            changes.extend(turned_pair);
        }
        (changed, relative_mismatch(mismatch, total))
    }
}

/// The mismatch relative to the updated forces' sum; infinite when every force went (all the
/// points opened) while the solve still applied some — that step is not settled.
fn relative_mismatch(mismatch: f64, total: f64) -> f64 {
    match (total > 0.0, mismatch > 0.0) {
        (true, _) => mismatch / total,
        (false, true) => f64::INFINITY,
        (false, false) => 0.0,
    }
}

/// The state of point `r` after a solve (the table of the module documentation), from its
/// normal force, elastic trial shear force `held` and Coulomb limit, with hysteresis of ±`band`
/// on gap and cone; `deep`: the overlap beyond which a point closes however often it flipped.
pub(super) fn next_state(
    r: &ContactRecord,
    normal: f64,
    held: &Vec3,
    limit: f64,
    (band, reclose, max_reclose, deep): (f64, f64, u32, f64),
    locked: bool,
) -> ContactState {
    let closing = r.state == ContactState::Open;
    match r.state {
        // Open until it overlaps beyond the band: a point at zero force (the side faces of
        // neighbouring blocks) must not flip with round-off. A point that closed twice in this
        // step's iterations stays open (it sits where the pressure changes sign and would flip
        // for ever) — unless it overlaps beyond `deep` (the support tolerance): left open there,
        // the Yade-matched dominos accepted steps with open points 1.3 mm deep, found at the
        // next detection as missed overlaps; one that opened closes again only at the
        // re-closing depth (small overlaps there are rocking within the iteration, not contact).
        ContactState::Open if r.gap > -band || (r.reclosed >= max_reclose && r.gap > -deep) => ContactState::Open,
        ContactState::Open if r.opened && r.gap > -reclose => ContactState::Open,
        _ if locked => ContactState::Stick,
        // Tension beyond the bond (and the band's spring force) opens a closed point.
        _ if !closing && normal < -r.strength.tension - r.kn * band => ContactState::Open,
        // A sliding point whose slip would reverse sticks (DDA's rule; the direction of a point
        // barely slipping is noise and would flip between iterations).
        ContactState::Slide if held.dot(&r.slip) > 0.0 => ContactState::Stick,
        ContactState::Slide if held.norm() > limit => ContactState::Slide,
        // A stuck or closing point slides once the trial exceeds the limit by the band's spring
        // force (a point entering while the blocks slip slides at once instead of braking).
        _ if held.norm() > limit + r.ks * band => ContactState::Slide,
        _ => ContactState::Stick,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::test_point;

    const BAND: f64 = 1e-12;
    const RECLOSE: f64 = 1e-6;
    const DEEP: f64 = 1e-4;

    /// One row of thesis Table 3-1 (verification of the contact state) as the rules apply it.
    struct Row {
        what: &'static str,
        from: ContactState,
        gap: f64,
        normal: f64,
        held: [f64; 3],
        limit: f64,
        setup: fn(&mut ContactRecord),
        locked: bool,
        to: ContactState,
    }

    fn none(_: &mut ContactRecord) {}

    #[test]
    fn table_3_1_state_rules() {
        use ContactState::{Open, Slide, Stick};
        #[rustfmt::skip]
        let rows = [
            Row { what: "separate stays separate while apart", from: Open, gap: 1e-4, normal: 0.0, held: [0.0; 3], limit: 0.0, setup: none, locked: false, to: Open },
            Row { what: "separate within the band stays separate", from: Open, gap: -0.5 * BAND, normal: 0.0, held: [0.0; 3], limit: 0.0, setup: none, locked: false, to: Open },
            Row { what: "separate → stick when it overlaps", from: Open, gap: -1e-6, normal: 1e3, held: [100.0, 0.0, 0.0], limit: 500.0, setup: none, locked: false, to: Stick },
            Row { what: "separate → slide when it closes beyond the cone", from: Open, gap: -1e-6, normal: 1e3, held: [600.0, 0.0, 0.0], limit: 500.0, setup: none, locked: false, to: Slide },
            Row { what: "a point that closed twice this step stays separate", from: Open, gap: -1e-6, normal: 1e3, held: [0.0; 3], limit: 500.0, setup: |r| r.reclosed = 2, locked: false, to: Open },
            Row { what: "unless it overlaps beyond the support tolerance", from: Open, gap: -2e-4, normal: 2e5, held: [0.0; 3], limit: 500.0, setup: |r| r.reclosed = 2, locked: false, to: Stick },
            Row { what: "a point that opened this step recloses only deeper than the reclosing depth", from: Open, gap: -0.5 * RECLOSE, normal: 1e3, held: [0.0; 3], limit: 500.0, setup: |r| r.opened = true, locked: false, to: Open },
            Row { what: "… and does reclose beyond it", from: Open, gap: -2.0 * RECLOSE, normal: 1e3, held: [0.0; 3], limit: 500.0, setup: |r| r.opened = true, locked: false, to: Stick },
            Row { what: "stick → separate in tension (P_N < 0)", from: Stick, gap: 1e-6, normal: -1.0, held: [0.0; 3], limit: 0.0, setup: none, locked: false, to: Open },
            Row { what: "a bond holds tension below its strength", from: Stick, gap: 1e-6, normal: -1.0, held: [0.0; 3], limit: 0.0, setup: |r| r.strength.tension = 10.0, locked: false, to: Stick },
            Row { what: "stick stays stick inside the cone", from: Stick, gap: -1e-6, normal: 1e3, held: [400.0, 0.0, 0.0], limit: 500.0, setup: none, locked: false, to: Stick },
            Row { what: "stick → slide beyond the cone (|P_T| ≥ μ|P_N|)", from: Stick, gap: -1e-6, normal: 1e3, held: [0.0, 600.0, 0.0], limit: 500.0, setup: none, locked: false, to: Slide },
            Row { what: "slide → separate in tension", from: Slide, gap: 1e-6, normal: -1.0, held: [0.0; 3], limit: 0.0, setup: |r| r.slip = Vec3::x(), locked: false, to: Open },
            Row { what: "slide → stick when the slip reverses", from: Slide, gap: -1e-6, normal: 1e3, held: [600.0, 0.0, 0.0], limit: 500.0, setup: |r| r.slip = Vec3::x(), locked: false, to: Stick },
            Row { what: "slide stays slide beyond the cone", from: Slide, gap: -1e-6, normal: 1e3, held: [-600.0, 0.0, 0.0], limit: 500.0, setup: |r| r.slip = Vec3::x(), locked: false, to: Slide },
            Row { what: "slide → stick back inside the cone", from: Slide, gap: -1e-6, normal: 1e3, held: [-400.0, 0.0, 0.0], limit: 500.0, setup: |r| r.slip = Vec3::x(), locked: false, to: Stick },
            Row { what: "locked (initial equilibrium): a closed point sticks in tension", from: Stick, gap: 1e-6, normal: -1e3, held: [0.0; 3], limit: 0.0, setup: none, locked: true, to: Stick },
            Row { what: "locked: and beyond the cone", from: Stick, gap: -1e-6, normal: 1e3, held: [1e6, 0.0, 0.0], limit: 500.0, setup: none, locked: true, to: Stick },
        ];
        for row in rows {
            let mut r = test_point(row.from, row.gap);
            (row.setup)(&mut r);
            let held = Vec3::from(row.held);
            let got = next_state(&r, row.normal, &held, row.limit, (BAND, RECLOSE, 2, DEEP), row.locked);
            assert_eq!(got, row.to, "{}", row.what);
        }
    }

    #[test]
    fn a_solve_whose_points_all_opened_is_not_settled_at_any_tolerance() {
        assert_eq!(relative_mismatch(2.0, 4.0), 0.5);
        assert_eq!(relative_mismatch(0.0, 0.0), 0.0);
        // The solve applied forces, the updated states carry none: every point opened.
        assert!(relative_mismatch(1e-9, 0.0) > 0.999);
    }
}
