//! Verification (a): free fall and ballistic flight of a 1 m cube.
//!
//! Source: `verification-cases.md` (a); closed form u(t) = v₀t + ½gt², v(t) = v₀ + gt.
//! Setup: `examples/free_fall.toml` (ρ = 2500, g = 10 m/s², no contact), every pattern, the
//! cover rotated by (20°, 35°, −10°).
//! Tolerance: 1e-6 relative at t = 1 s. The DDA scheme integrates constant acceleration
//! exactly, so anything beyond round-off is a bug. Stress must stay ≈ 0.

mod common;

use common::{example, final_value, run_ok, with};

/// u(t) = v₀ t + ½ g t².
fn ballistic(v0: [f64; 3], g: [f64; 3], t: f64) -> ([f64; 3], [f64; 3]) {
    let u = [0, 1, 2].map(|i| v0[i] * t + 0.5 * g[i] * t * t);
    let v = [0, 1, 2].map(|i| v0[i] + g[i] * t);
    (u, v)
}

fn cube(pattern: &str, v0: [f64; 3]) -> String {
    let text = with(&example("free_fall.toml"), "pattern = \"tet6\"", &format!("pattern = \"{pattern}\""));
    with(&text, "velocity = [0.0, 0.0, 0.0]", &format!("velocity = [{}, {}, {}]", v0[0], v0[1], v0[2]))
}

fn check(pattern: &str, v0: [f64; 3]) {
    let out = run_ok(&cube(pattern, v0), &format!("free_fall_{pattern}_{}", v0[2]));
    let (u, v) = ballistic(v0, [0.0, 0.0, -10.0], 1.0);
    let unorm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
    let vnorm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for (i, c) in ["x", "y", "z"].iter().enumerate() {
        let du = final_value(&out, &format!("cube.displacement.{c}"));
        let dv = final_value(&out, &format!("cube.velocity.{c}"));
        assert!((du - u[i]).abs() <= 1e-6 * unorm, "{pattern}: u_{c} = {du}, exact {}", u[i]);
        assert!((dv - v[i]).abs() <= 1e-6 * vnorm, "{pattern}: v_{c} = {dv}, exact {}", v[i]);
    }
    for c in ["xx", "yy", "zz", "xy", "yz", "zx"] {
        let s = final_value(&out, &format!("cube.stress.{c}"));
        // ρ g L = 25 kPa is the scale of gravity stresses; free fall carries none.
        assert!(s.abs() < 1e-6 * 25e3, "{pattern}: stress {c} = {s}");
    }
}

#[test]
fn free_fall_from_rest_a1_every_pattern() {
    for p in ["tet5", "tet6", "tet24", "hex8"] {
        check(p, [0.0, 0.0, 0.0]);
    }
}

#[test]
fn ballistic_flight_a2_every_pattern() {
    for p in ["tet5", "tet6", "tet24", "hex8"] {
        check(p, [1.0, 2.0, 3.0]);
    }
}
