//! Verification (a3): a 1 m cube spinning at ω = 2π rad/s about z.
//!
//! Source: `verification-cases.md` (a3). A first-order rotation update inflates a spinning
//! block (DDA's known defect); the co-rotational update must keep the volume: change < 1e-3
//! after one revolution and no growth over a second one. Gravity off, no contact.

mod common;

use common::{example, final_value, run_ok, with};

fn spinning(pattern: &str, duration: f64) -> String {
    let text = with(&example("spinning_block.toml"), "pattern = \"tet6\"", &format!("pattern = \"{pattern}\""));
    with(&text, "duration = 1.0", &format!("duration = {duration}"))
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
