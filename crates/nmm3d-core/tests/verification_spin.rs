//! Verification (a3): a 1 m cube spinning at ω = 2π rad/s about z.
//!
//! Source: `verification-cases.md` (a3). A first-order rotation update inflates a spinning
//! block (DDA's known defect); the co-rotational update must keep the volume: change < 1e-3
//! after one revolution and no growth over a second one. Gravity off, no contact.

mod common;

use common::{final_value, run_ok};

fn spinning(pattern: &str, duration: f64) -> String {
    format!(
        r#"
[analysis]
duration = {duration}
dt = 0.001
max_displacement_ratio = 0.004
gravity = [0.0, 0.0, 0.0]
output_interval = 0.0
history_interval = 0.25

[cover]
pattern = "{pattern}"
size = 0.5
rotation = [0.0, 0.0, 17.0]

[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.25

[[body]]
name = "cube"
material = "rock"
angular_velocity = [0.0, 0.0, 6.283185307179586]
shape = {{ box = {{ min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] }} }}

[[monitor]]
name = "cube"
select = {{ body = "cube" }}
quantities = ["volume", "rotation", "stress"]
"#
    )
}

#[test]
fn spinning_block_keeps_its_volume_a3() {
    for pattern in ["tet6", "hex8"] {
        let one = run_ok(&spinning(pattern, 1.0), &format!("spin1_{pattern}"));
        let two = run_ok(&spinning(pattern, 2.0), &format!("spin2_{pattern}"));
        let v1 = final_value(&one, "cube.volume.value");
        let v2 = final_value(&two, "cube.volume.value");
        assert!((v1 - 1.0).abs() < 1e-3, "{pattern}: volume after one turn {v1}");
        assert!((v2 - 1.0).abs() <= (v1 - 1.0).abs() + 1e-4, "{pattern}: volume grows: {v1} then {v2}");
        // Centripetal stress is ρω²r²/2 ≈ 25 kPa at most; spurious rotation strain would give E·θ ~ GPa.
        let sxx = final_value(&one, "cube.stress.xx").abs();
        assert!(sxx < 1e5, "{pattern}: stress {sxx}");
    }
}
