//! A dynamic step detects contacts within its own margin — twice how far its points can move —
//! not within the step control's bound, which grows with the model (`time/reach.rs`).

mod common;

use common::scenario;
use nmm3d_core::system::System;
use nmm3d_core::time::{State, Stepper};

/// A 1 m cube sliding at 1 m/s on a frictionless fixed base past a cube at rest, their facing
/// sides `gap` apart; the side pair's contact points after the first detection and after
/// `steps` steps of 1 ms.
fn side_points(gap: f64, steps: usize) -> (usize, usize) {
    let text = format!(
        r#"
[analysis]
duration = 1.0
dt = 0.001
max_displacement_ratio = 0.05
gravity = [0.0, 0.0, -10.0]
output_interval = 0.0

[cover]
pattern = "tet6"
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.0

[[joint]]
name = "j"
friction_angle = 0.0

[[body]]
name = "base"
material = "rock"
fixed = true
joint = "j"
shape = {{ box = {{ min = [-2.0, -2.0, -1.0], max = [4.0, 4.0, 0.0] }} }}

[[body]]
name = "sliding"
material = "rock"
joint = "j"
velocity = [0.0, 1.0, 0.0]
shape = {{ box = {{ min = [-1.0, -0.5, 0.0], max = [0.0, 0.5, 1.0] }} }}

[[body]]
name = "resting"
material = "rock"
joint = "j"
shape = {{ box = {{ min = [{gap}, -0.5, 0.0], max = [{}, 0.5, 1.0] }} }}
"#,
        gap + 1.0
    );
    let sys = System::build(scenario(&text), "<test>").unwrap_or_else(|e| panic!("{e}"));
    let mut whole = State::initial(&sys);
    let mut stepper = Stepper::new(&sys, &mut whole, "<test>").unwrap_or_else(|e| panic!("{e}"));
    stepper.initialize(&sys, &mut whole).unwrap();
    let block = |name: &str| {
        let named = |b: &usize| sys.scenario.body[sys.geometry.blocks[*b].body].name == name;
        (0..sys.geometry.blocks.len()).find(named).expect("a block of that body")
    };
    let (a, b) = (block("sliding"), block("resting"));
    let pair = (a.max(b), a.min(b));
    let sides = |w: &State| w.contact.as_ref().unwrap().records.iter().filter(|r| r.blocks == pair).count();
    let first = sides(&whole);
    for _ in 0..steps {
        stepper.step(&sys, &mut whole, 1.0).unwrap_or_else(|e| panic!("{e}"));
    }
    (first, sides(&whole))
}

#[test]
fn a_moving_step_detects_within_twice_its_reach_not_the_step_controls_bound() {
    // The step control allows 0.05 × 3 m = 0.15 m per step, so the first detection (no motion
    // known yet) takes the sides 50 mm apart as open points. Sliding at 1 m/s a step moves
    // 1 mm, and later detections look 0.5 mm + 2 × 4 (`reach_safety`) × 1 mm far: they leave
    // the sides 50 mm apart out and keep those 2 mm apart.
    let (first, later) = side_points(0.05, 20);
    assert!(first > 0, "the first detection takes the sides within the step control's margin");
    assert_eq!(later, 0, "sides 50 mm apart are beyond the step's margin");
    let (first, later) = side_points(0.002, 20);
    assert!(first > 0 && later > 0, "sides 2 mm apart are within it: {first}, {later}");
}
