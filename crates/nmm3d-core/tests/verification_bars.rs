//! Verification (f): bars.
//!
//! * End-loaded bar (the patch test): L = 10 m, 1 × 1 m, E = 10 GPa, ν = 0.25, traction 1 MPa
//!   pulling on both ends, held by six statically determinate point constraints (so they carry
//!   no force and cannot disturb the field). The exact solution is linear, so every pattern
//!   must reproduce σ_xx = 1 MPa in every ME and u(L) − u(0) = σL/E = 1.000 mm to 1e-6.
//! * Hanging bar under self-weight: u(bottom) − u(top) = ρgL²/(2E) = 0.125 mm, within 1 %.

mod common;

use common::{example, solve_static, with};
use nmm3d_core::element::kernel::stress_components;
use nmm3d_core::element::loads::weights_at;
use nmm3d_core::state::Motion;
use nmm3d_core::system::System;
use nmm3d_core::time::corotation::element_stress;
use nmm3d_geom::Vec3;

const E: f64 = 10.0e9;

fn bar(pattern: &str, rotation: &str) -> String {
    let text = with(&example("bar_patch.toml"), "pattern = \"tet6\"", &format!("pattern = \"{pattern}\""));
    with(&text, "rotation = [10.0, 25.0, 40.0]", &format!("rotation = {rotation}"))
}

fn displacement_at(sys: &System, state: &Motion, p: Vec3) -> Vec3 {
    let (_, e) = sys.locate(&p).unwrap();
    let me = &sys.covers.elements[e];
    me.covers.iter().zip(weights_at(&sys.covers, me, &p)).map(|(&c, w)| w * state.u[c]).sum()
}

#[test]
fn end_loaded_bar_patch_test_every_pattern() {
    for pattern in ["tet5", "tet6", "tet24", "hex8"] {
        for rotation in ["[0.0, 0.0, 0.0]", "[10.0, 25.0, 40.0]"] {
            let (sys, state) = solve_static(&bar(pattern, rotation));
            for e in 0..sys.covers.elements.len() {
                let s = stress_components(&element_stress(&sys, &state, e));
                assert!((s[0] - 1e6).abs() < 1e-6 * 1e6, "{pattern} {rotation}: ME {e} σxx = {}", s[0]);
                for c in &s[1..] {
                    assert!(c.abs() < 1e-6 * 1e6, "{pattern} {rotation}: ME {e} stress {s:?}");
                }
            }
            let stretch = displacement_at(&sys, &state, Vec3::new(10.0, 0.5, 0.5)).x
                - displacement_at(&sys, &state, Vec3::new(0.0, 0.5, 0.5)).x;
            let exact = 1e6 * 10.0 / E;
            assert!((stretch - exact).abs() < 1e-6 * exact, "{pattern} {rotation}: {stretch} vs {exact}");
        }
    }
}

/// u(bottom) − u(top) of a bar hanging under its own weight: ρ g L² / (2E).
fn hanging_bar_stretch(rho: f64, g: f64, l: f64, e: f64) -> f64 {
    rho * g * l * l / (2.0 * e)
}

#[test]
fn hanging_bar_under_self_weight() {
    let text = example("hanging_bar.toml");
    for pattern in ["hex8", "tet24", "tet6"] {
        let (sys, state) = solve_static(&text.replace("pattern = \"hex8\"", &format!("pattern = \"{pattern}\"")));
        let top = displacement_at(&sys, &state, Vec3::new(0.5, 0.5, 10.0)).z;
        let bottom = displacement_at(&sys, &state, Vec3::new(0.5, 0.5, 0.0)).z;
        let exact = hanging_bar_stretch(2500.0, 10.0, 10.0, 10.0e9);
        let got = top - bottom;
        assert!((got - exact).abs() < 0.01 * exact, "{pattern}: {got} vs {exact}");
    }
}
