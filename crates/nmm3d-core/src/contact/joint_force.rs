//! What a joint on its own stiffness keeps when its pair is detected again, or a point arrives.
//!
//! Springs on a joint's stiffness (Pa/m × area) carry the total force k_n A_p g_p of each point,
//! so whatever a re-detection changes — other points, other areas — changes the force at once.
//! Three rules bound that (`docs/theory/contact.md`, *Joint stiffness*):
//!
//! * while the initial equilibrium settles, a joint found with less area than its points had
//!   keeps their area ([`Redetection::keep_area`]);
//! * in a dynamic run and while the initial equilibrium settles, a pair found pushing harder
//!   than its points did at the same configuration pushes only as hard
//!   ([`Redetection::carry_force`]): its new points share a zero level that takes the
//!   difference; in a static analysis only what exceeds the previous force by more than a
//!   slack (`contact.static_carry_slack`): its answer is the total force's where a joint
//!   closes smoothly, and only a face found again as a jump is lifted. A face contact tens of
//!   centimetres deep found again as an edge's point contacts (each a cover cell's face)
//!   otherwise sets ½ k_n A g² of spring energy at once — one pair on the thesis slope on
//!   10 MPa/m joints went from 1.0 to 190.6 kJ. 3DEC's
//!   sub-contacts carry their normal force incrementally (ΔF_n = −k_n ΔU_n A_c, Itasca 3DEC
//!   manual, *Theory*: contact mechanics), and a new geometry takes only the increments; here the
//!   springs keep their stiffness, so further closure is resisted as before, and a point that
//!   opens hands its share of the level back (`ContactRecord::relax_raised`);
//! * in a dynamic run, a point that arrives within a step already overlapping at its start by
//!   more than the transfer distance pushes from there ([`arrived`]).

use rustc_hash::FxHashMap;

use super::record::{ContactRecord, ContactState};
use super::transfer::bound_missed_overlap;

/// What a re-detected joint pair keeps from its previous points; neither: the points as found
/// ([`Redetection::TOTAL`]: the first detection and the lock).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Redetection {
    /// The previous contact area, when less is found (the frictional initial equilibrium only:
    /// a heel that lifts loses area, which keeping it would deny a static analysis).
    pub keep_area: bool,
    /// `Some(slack)`: at most (1 + slack) × the previous normal force (with
    /// `contact.carry_joint_force`: 0 in dynamic runs and the frictional initial equilibrium,
    /// `contact.static_carry_slack` in static analyses).
    pub carry_force: Option<f64>,
}

impl Redetection {
    /// The points as found.
    pub const TOTAL: Self = Self { keep_area: false, carry_force: None };
}

/// How many re-detected pairs a rule changed: their area kept, their force carried.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Redetected {
    /// Pairs whose points were scaled up to the previous area.
    pub kept_area: usize,
    /// Pairs whose points' zero level was lifted to push the previous force.
    pub carried_force: usize,
}

/// Bisections for the common zero level: its bracket, the deepest overlap, halves each time.
const LEVEL_BISECTIONS: usize = 60;

/// Apply `rule` to the joint points among `records` whose pair was detected before (`by_pair`:
/// the pair's previous points, indices into `previous`): first the area, then the force on the
/// springs that keeping the area set. Returns how many pairs each changed.
pub(super) fn redetected(
    rule: Redetection,
    previous: &[ContactRecord],
    by_pair: &FxHashMap<(usize, usize), Vec<usize>>,
    records: &mut [ContactRecord],
) -> Redetected {
    let mut now: FxHashMap<(usize, usize), Vec<usize>> = FxHashMap::default();
    for (k, r) in records.iter().enumerate() {
        if r.joint_stiffness && by_pair.contains_key(&r.blocks) {
            now.entry(r.blocks).or_default().push(k);
        }
    }
    let mut pairs: Vec<_> = now.into_iter().collect();
    pairs.sort_unstable_by_key(|(blocks, _)| *blocks);
    let mut changed = Redetected::default();
    for (blocks, now) in &pairs {
        let was = || by_pair[blocks].iter().map(|&k| &previous[k]);
        if rule.keep_area {
            changed.kept_area += keep_area(was().map(|r| r.area).sum(), now, records) as usize;
        }
        if let Some(slack) = rule.carry_force {
            let before: f64 = was().filter(|r| closed(r)).map(ContactRecord::normal_force).sum();
            changed.carried_force += carry_force((1.0 + slack) * before, now, records) as usize;
        }
    }
    changed
}

/// Scale the pair's points' areas and springs up to `before` [m²] if they hold less. The
/// overlay shares only the area of the facets it finds on the contact plane, and faces turned
/// by millimetres over a metre drop out of it: on the thesis tunnel at 1 MPa/m the roof key
/// block's carrying joint went from 0.27 to 0.05 m², its springs softened six-fold and the
/// settling swung between two states. Only while blocks settle, where a joint closed at the
/// start stays the same joint; in a run, a pair's area shrinks as blocks slide apart.
fn keep_area(before: f64, now: &[usize], records: &mut [ContactRecord]) -> bool {
    let area: f64 = now.iter().map(|&k| records[k].area).sum();
    if !(area > 0.0 && area < before) {
        return false;
    }
    let f = before / area;
    for &k in now {
        let r = &mut records[k];
        (r.area, r.kn, r.ks) = (r.area * f, r.kn * f, r.ks * f);
    }
    true
}

/// Lift the closed points' zero level by the common depth at which they push `before` [N] (what
/// the previous points pushed), if they push harder.
fn carry_force(before: f64, now: &[usize], records: &mut [ContactRecord]) -> bool {
    let push = |depth: f64| now.iter().map(|&k| lifted_force(&records[k], depth)).sum::<f64>();
    if push(0.0) <= before {
        return false;
    }
    let (mut lo, mut hi) = (0.0, now.iter().map(|&k| -records[k].gap0).fold(0.0, f64::max));
    for _ in 0..LEVEL_BISECTIONS {
        let mid = 0.5 * (lo + hi);
        *(if push(mid) > before { &mut lo } else { &mut hi }) = mid;
    }
    for &k in now {
        let r = &mut records[k];
        if closed(r) && r.gap0 < 0.0 {
            r.shift_zero_level(-hi.min(-r.gap0));
            r.limit = r.coulomb_limit(r.gap0);
        }
    }
    true
}

/// An arrival (a point the lagged verification found within a step, added as a point of the
/// step's start) on a joint's own stiffness that already overlapped at the start by more than
/// `reach` [m] (the transfer distance: how far a pair closes between two detections) pushes from
/// that depth: the rest goes into its zero level. It pushed nothing while it was unseen, and a
/// spring set at that overlap would give it back at once — on the thesis slope on 10 MPa/m joints
/// such arrivals, found centimetres deep at a block's corner, made 0.6 MJ in 3 s after the
/// re-detected pairs carried their force. Within `reach` it is the joint's own closure, which its
/// neighbours share: lifted from zero, the points a wedge slid onto on a meshed rock carried too
/// little and it swayed 0.02 m/s off its path. True if it was lifted.
pub(super) fn arrived(r: &mut ContactRecord, reach: f64) -> bool {
    r.joint_stiffness && closed(r) && bound_missed_overlap(r, -reach)
}

fn closed(r: &ContactRecord) -> bool {
    r.state != ContactState::Open
}

/// The normal force [N] of a new point whose zero level is lowered by `depth` [m] (at most its
/// overlap); none if it is open.
fn lifted_force(r: &ContactRecord, depth: f64) -> f64 {
    if !closed(r) {
        return 0.0;
    }
    r.normal_force_at(r.gap0 + depth.min((-r.gap0).max(0.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::record::test_point;

    /// A point of pair (1, 0) with `area` [m²] on a joint of 1 MPa/m (or on a penalty), `gap` deep.
    fn point(area: f64, joint: bool, gap: f64) -> ContactRecord {
        let mut r = test_point(ContactState::Stick, gap);
        (r.blocks, r.area, r.kn, r.ks, r.joint_stiffness) = ((1, 0), area, 1e6 * area, 1e6 * area, joint);
        r
    }

    const KEEP_AREA: Redetection = Redetection { keep_area: true, carry_force: None };
    const CARRY_FORCE: Redetection = Redetection { keep_area: false, carry_force: Some(0.0) };
    /// A static analysis's, at `contact.static_carry_slack`'s default.
    const STATIC: Redetection = Redetection { keep_area: false, carry_force: Some(0.05) };

    fn pair() -> FxHashMap<(usize, usize), Vec<usize>> {
        [((1, 0), vec![0, 1])].into_iter().collect()
    }

    fn force(records: &[ContactRecord]) -> f64 {
        records.iter().map(ContactRecord::normal_force).sum()
    }

    #[test]
    fn a_joint_redetected_with_less_area_keeps_what_its_points_held() {
        let previous = vec![point(0.5, true, -1e-3), point(0.5, true, -1e-3)];
        let mut now = vec![point(0.1, true, -1e-3), point(0.15, true, -1e-3)];
        assert_eq!(redetected(KEEP_AREA, &previous, &pair(), &mut now).kept_area, 1);
        assert!((now.iter().map(|r| r.area).sum::<f64>() - 1.0).abs() < 1e-12);
        assert!((now[0].kn - 0.4e6).abs() < 1e-6 && (now[1].ks - 0.6e6).abs() < 1e-6);
        // More area than before, or a penalty contact (its spring is no joint's), stays as found.
        let mut more = vec![point(1.5, true, -1e-3)];
        assert_eq!(redetected(KEEP_AREA, &previous, &pair(), &mut more).kept_area, 0);
        assert_eq!(more[0].area, 1.5);
        let mut penalty = vec![point(0.1, false, -1e-3)];
        redetected(KEEP_AREA, &previous, &pair(), &mut penalty);
        assert_eq!(penalty[0].kn, 1e5);
    }

    #[test]
    fn a_joint_found_pushing_harder_pushes_as_before_on_springs_as_stiff() {
        // Before: 2 × 0.1 m² at 10 cm, 20 kN. Found again as two 2 m² points, 10 and 4 cm deep:
        // 280 kN, 11.6 kJ in the springs instead of 1 kJ.
        let previous = vec![point(0.1, true, -0.1), point(0.1, true, -0.1)];
        let mut now = vec![point(2.0, true, -0.1), point(2.0, true, -0.04)];
        assert_eq!(redetected(CARRY_FORCE, &previous, &pair(), &mut now).carried_force, 1);
        assert!((force(&now) - 20e3).abs() < 1e-6, "{}", force(&now));
        assert_eq!((now[0].kn, now[1].kn), (2e6, 2e6), "the springs as stiff");
        // A common level 9 cm down: the 4 cm point holds nothing, the 10 cm one all 20 kN.
        assert!((now[0].gap0 + 0.01).abs() < 1e-12 && now[1].gap0.abs() < 1e-12, "{now:?}");
        assert!((now[0].raised + 0.09).abs() < 1e-12, "the geometric overlap still reported");
        // Pushing less, or taken as found (the lock), or on a penalty: as found.
        for (rule, joint, area) in
            [(CARRY_FORCE, true, 0.05), (Redetection::TOTAL, true, 2.0), (CARRY_FORCE, false, 2.0)]
        {
            let mut now = vec![point(area, joint, -0.1)];
            assert_eq!(redetected(rule, &previous, &pair(), &mut now), Redetected::default());
            assert_eq!(now[0].gap0, -0.1);
        }
    }

    #[test]
    fn a_static_joint_found_pushing_a_little_harder_keeps_the_total_force() {
        // Before: 2 × 0.1 m² at 10 cm, 20 kN. Found at 10.4 cm (4 % harder): as found. At 20 cm
        // (twice as hard): lifted to push 5 % more than before, 21 kN, not 20 kN.
        let previous = vec![point(0.1, true, -0.1), point(0.1, true, -0.1)];
        let mut near = vec![point(0.1, true, -0.104), point(0.1, true, -0.104)];
        assert_eq!(redetected(STATIC, &previous, &pair(), &mut near), Redetected::default());
        assert!((force(&near) - 20.8e3).abs() < 1e-6, "{}", force(&near));
        let mut jump = vec![point(0.1, true, -0.2), point(0.1, true, -0.2)];
        assert_eq!(redetected(STATIC, &previous, &pair(), &mut jump).carried_force, 1);
        assert!((force(&jump) - 21e3).abs() < 1e-6, "{}", force(&jump));
    }

    #[test]
    fn a_settling_joint_keeps_its_area_then_pushes_as_before_on_the_kept_springs() {
        // Before: 2 × 0.5 m² at 1 mm, 1 kN. Found again as 0.1 + 0.15 m², both 10 mm deep: the
        // area goes back to 1 m² (springs 0.4 and 0.6 MN/m), which at 10 mm would push 10 kN.
        let previous = vec![point(0.5, true, -1e-3), point(0.5, true, -1e-3)];
        let mut now = vec![point(0.1, true, -0.01), point(0.15, true, -0.01)];
        let both = Redetection { keep_area: true, carry_force: Some(0.0) };
        let changed = redetected(both, &previous, &pair(), &mut now);
        assert_eq!(changed, Redetected { kept_area: 1, carried_force: 1 });
        assert!((force(&now) - 1e3).abs() < 1e-6, "{}", force(&now));
        assert!((now[0].kn - 0.4e6).abs() < 1e-6 && (now[1].kn - 0.6e6).abs() < 1e-6, "the kept springs");
        assert!(now.iter().all(|r| (r.gap0 + 1e-3).abs() < 1e-12), "a common level 9 mm down: {now:?}");
    }

    #[test]
    fn open_points_neither_pushed_before_nor_take_the_level() {
        let mut open = point(1.0, true, -0.1);
        open.state = ContactState::Open;
        let previous = vec![open.clone(), point(0.1, true, -0.1)];
        let mut now = vec![open, point(1.0, true, -0.1)];
        assert_eq!(redetected(CARRY_FORCE, &previous, &pair(), &mut now).carried_force, 1);
        assert!((now[1].normal_force() - 10e3).abs() < 1e-6);
        assert_eq!(now[0].gap0, -0.1);
    }

    #[test]
    fn an_arrival_deep_at_the_start_pushes_from_the_transfer_distance() {
        let mut r = point(1.0, true, -0.02);
        assert!(arrived(&mut r, 0.005));
        assert!((r.gap0 + 0.005).abs() < 1e-15 && (r.raised + 0.015).abs() < 1e-15, "{r:?}");
        assert_eq!(r.kn, 1e6, "the spring as stiff");
        // Within the transfer distance (the joint's own closure), open, or a penalty contact: as found.
        for (joint, gap, state) in
            [(true, -4e-3, ContactState::Stick), (true, -0.02, ContactState::Open), (false, -0.02, ContactState::Stick)]
        {
            let mut r = point(1.0, joint, gap);
            r.state = state;
            assert!(!arrived(&mut r, 0.005));
            assert_eq!(r.gap0, gap);
        }
    }
}
