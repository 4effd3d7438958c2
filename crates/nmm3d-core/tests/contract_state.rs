//! Contract: `State` is the whole mutable state of a run. A mid-run state with contact points,
//! serialised and read back, equals the original; a stepper rebuilt from the model (with the
//! caches of the one in use: matrix pattern, factor) continues from it bit for bit as the run
//! that never stopped, step by step.

mod common;

use common::{example, started, with};
use nmm3d_core::time::{State, Stepper};

#[test]
fn a_mid_run_state_with_contacts_round_trips_and_continues_bit_identically() {
    let text = with(&example("dominos.toml"), "duration = 5.0", "duration = 0.1");
    let (sys, mut a, mut stepper) = started(&text, "dominos");
    while a.motion.step < 40 {
        let _ = stepper.step(&sys, &mut a, f64::INFINITY).unwrap_or_else(|e| panic!("{e}"));
    }
    let points = a.contact.as_ref().map_or(0, |c| c.records.len());
    assert!(points > 0, "the state holds contact points");
    assert!(a.stepper.energy.is_some(), "and the energy accounts");

    let mut b: State = serde_json::from_str(&serde_json::to_string(&a).unwrap()).unwrap();
    assert_eq!(a, b, "the state round-trips exactly");
    let mut resumed = Stepper::resume(&sys, stepper.snapshot()).unwrap();
    for _ in 0..40 {
        let ra = stepper.step(&sys, &mut a, f64::INFINITY).unwrap_or_else(|e| panic!("{e}"));
        let rb = resumed.step(&sys, &mut b, f64::INFINITY).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(ra, rb, "step {}", a.motion.step);
        assert_eq!(a, b, "step {}", a.motion.step);
    }
    // The state changed: a comparison that cannot fail would show nothing.
    let mut c = b.clone();
    c.stepper.penalty_raises += 1;
    assert_ne!(a, c);
}
