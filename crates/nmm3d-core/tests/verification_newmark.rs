//! Verification of the time integrators on a suddenly loaded elastic bar.
//!
//! A bar hangs from its top face; gravity acts from t = 0 on the unstressed bar. An undamped
//! elastic system under a suddenly applied constant load overshoots to twice its static
//! response (dynamic amplification factor 2). The trapezoidal rule (Newmark β = ¼, γ = ½)
//! conserves energy and must reach ≈ 2 × the static stretch ρgL²/(2E); the DDA scheme
//! (β = ½, γ = 1) is dissipative and must decay towards the static stretch. First mode:
//! T = 4L/c = 0.02 s; Δt = 1 ms gives ωΔt ≈ 0.3, where DDA loses ~20 % amplitude per half period.

mod common;

use common::run_ok;

fn bar(integrator: &str) -> String {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/hanging_bar.toml")).unwrap();
    text.replace("kind = \"static\"", &format!("kind = \"dynamic\"\nintegrator = \"{integrator}\""))
        .replace("duration = 1000.0", "duration = 0.2")
        .replace("dt = 1.0", "dt = 0.001")
        .replace("equilibrium_tolerance = 1e-10", "")
}

fn stretch_history(integrator: &str) -> Vec<f64> {
    let out = run_ok(&bar(integrator), &format!("newmark_{integrator}"));
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("newmark_{integrator}"));
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let (top, bottom) = (
        header.iter().position(|h| *h == "top.displacement.z").unwrap(),
        header.iter().position(|h| *h == "bottom.displacement.z").unwrap(),
    );
    assert!(out.completed);
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            v[top] - v[bottom]
        })
        .collect()
}

#[test]
fn suddenly_loaded_bar_overshoots_twice_with_trapezoidal_and_decays_with_dda() {
    let statics = 2500.0 * 10.0 * 100.0 / (2.0 * 10.0e9);
    let trap = stretch_history("newmark");
    let dda = stretch_history("dda");
    let peak = |h: &[f64]| h.iter().cloned().fold(f64::MIN, f64::max);
    let late_swing = |h: &[f64]| {
        let tail = &h[h.len() * 3 / 4..];
        tail.iter().cloned().fold(f64::MIN, f64::max) - tail.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!(
        peak(&trap) > 1.85 * statics && peak(&trap) < 2.15 * statics,
        "trapezoidal peak {} vs static {statics}",
        peak(&trap)
    );
    assert!(peak(&dda) < peak(&trap), "DDA must damp the overshoot");
    assert!(
        late_swing(&dda) < 0.5 * late_swing(&trap),
        "DDA swing {} vs trapezoidal {}",
        late_swing(&dda),
        late_swing(&trap)
    );
}
