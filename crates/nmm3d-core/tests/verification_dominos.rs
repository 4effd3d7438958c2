//! Thesis dominos, two-end run (`examples/dominos.toml`): the two toppling waves meet in the
//! middle, the middle pair leans on each other (the final "Λ"), every domino leans the way its
//! wave went, the row comes to rest, and no contact overlaps by 1 % of a domino's thickness.

mod common;

use common::{example, final_value, history, run_ok};

#[test]
fn dominos_two_end_run_ends_at_rest_with_the_middle_pair_leaning_together() {
    let out = run_ok(&example("dominos.toml"), "dominos");
    let tilt = |k: usize| final_value(&out, &format!("d{k}.rotation.y"));
    // Left half toppled towards +x (positive rotation about y), right half towards −x.
    for k in 0..4 {
        assert!(tilt(k) > 0.05, "domino {k} leans {} rad", tilt(k));
        assert!(tilt(7 - k) < -0.05, "domino {} leans {} rad", 7 - k, tilt(7 - k));
    }
    // The middle pair (3, 4) leans on each other; the others lie on their neighbours, flatter
    // towards the ends.
    for k in 0..3 {
        assert!(tilt(k) > tilt(k + 1), "left wave not ordered at {k}");
        assert!(tilt(7 - k) < tilt(6 - k), "right wave not ordered at {}", 7 - k);
    }
    // At rest: no domino turns by more than a milliradian over the last second.
    for k in 0..8 {
        let r = history("dominos", &format!("d{k}.rotation.y"));
        let at = |t: f64| r.iter().find(|(s, _)| *s >= t - 1e-9).expect("time").1;
        assert!((at(5.0) - at(4.0)).abs() < 1e-3, "domino {k} still turning");
    }
    let pen = out.summary["max_penetration"].as_f64().unwrap();
    assert!(pen < 0.01 * 0.1, "overlap {pen} m");
}
