//! Thesis dominos, two-end run (`examples/dominos.toml`): the two toppling waves meet, the pair
//! where they meet leans on each other (the final "Λ"), every domino leans the way its wave
//! went, the row comes to rest, and no contact overlaps by 1 % of a domino's thickness.

mod common;

use common::{example, final_value, history, run_ok, with};
use nmm3d_core::simulation::Status;

#[test]
fn dominos_two_end_run_ends_at_rest_with_the_middle_pair_leaning_together() {
    let out = run_ok(&example("dominos.toml"), "dominos");
    let tilt = |k: usize| final_value(&out, &format!("d{k}.rotation.y"));
    // Both waves ran: the left dominos lean towards +x (positive rotation about y), the right ones
    // towards −x, flatter towards the ends; where the waves met, one pair leans together (Λ):
    // one change of sign, with both of that pair clearly tilted. (Where exactly they meet
    // depends on the timing of the two waves, e.g. on Δt.)
    for k in 0..7 {
        assert!(tilt(k) > tilt(k + 1), "tilts not ordered at {k}: {} then {}", tilt(k), tilt(k + 1));
    }
    assert!(tilt(0) > 0.5 && tilt(7) < -0.5, "an end domino did not fall");
    let meet = (0..7).find(|&k| tilt(k) > 0.0 && tilt(k + 1) <= 0.0).expect("the waves never met");
    assert!(tilt(meet) > 0.05 && tilt(meet + 1) < -0.05, "no Λ pair: {} and {}", tilt(meet), tilt(meet + 1));
    // At rest: no domino turns by more than a milliradian over the last second.
    for k in 0..8 {
        let r = history("dominos", &format!("d{k}.rotation.y"));
        let at = |t: f64| r.iter().find(|(s, _)| *s >= t - 1e-9).expect("time").1;
        assert!((at(5.0) - at(4.0)).abs() < 1e-3, "domino {k} still turning");
    }
    let pen = out.summary.max_penetration;
    assert!(pen < 0.01 * 0.1, "overlap {pen} m");
    // The row falls in the x–z plane: a twist about the vertical is an artefact. tet6 splits each
    // cover cell along one diagonal, which makes its MEs slightly anisotropic (the end domino d0
    // turns 0.015 rad, its mirror d7 0.002 rad; it was 0.05 rad for all, issue 14); hex8 below
    // stays within a milliradian.
    assert_twist_within(&out, 0.03);
}

/// No domino turned about the vertical by more than `bound` [rad] at the end.
fn assert_twist_within(out: &nmm3d_core::simulation::RunOutcome, bound: f64) {
    for k in 0..8 {
        let twist = final_value(out, &format!("d{k}.rotation.z"));
        assert!(twist.abs() < bound, "domino {k} twisted {twist} rad about the vertical");
    }
}

#[test]
fn dominos_on_hex8_covers_run_to_the_end_without_deep_overlap() {
    // The same run on hex8 covers (a face warped by the impacts beyond the support tolerance, and
    // tipped dominos meeting top to top once lost their contact points and passed into each other).
    let text = with(&example("dominos.toml"), "pattern = \"tet6\"", "pattern = \"hex8\"");
    let out = run_ok(&text, "dominos_hex8");
    assert_eq!(out.summary.status, Status::Completed);
    let pen = out.summary.max_penetration;
    assert!(pen < 0.01 * 0.1, "overlap {pen} m");
    assert_eq!(out.summary.penalty_raises, 0, "no overlap deep enough to raise the penalties");
    assert_twist_within(&out, 5e-3);
}
