//! Large strain: a bar with ν = 0 pulled by a dead traction t = 0.2 E on both ends.
//!
//! * co-rotational (Biot stress E(λ − 1) per reference area): λ = 1 + t/E = 1.2;
//! * Green–Lagrange / St Venant–Kirchhoff (first Piola stress F S = E λ(λ² − 1)/2):
//!   λ is the root of λ³ − λ − 2t/E = 0, λ ≈ 1.159705.
//!
//! Both are exact for a uniform stretch, so every pattern must hit them to round-off level.

mod common;

use common::{example, final_value, run_ok, with_each};

/// Root of λ³ − λ − 2t/E = 0 above 1 (Newton).
fn svk_stretch(t_over_e: f64) -> f64 {
    let mut l: f64 = 1.0 + t_over_e;
    for _ in 0..50 {
        l -= (l * l * l - l - 2.0 * t_over_e) / (3.0 * l * l - 1.0);
    }
    l
}

fn stretch(pattern: &str, measure: &str) -> f64 {
    let text = with_each(
        &example("bar_patch.toml"),
        &[
            ("pattern = \"tet6\"", format!("pattern = \"{pattern}\"")),
            ("young = 10.0e9", "young = 1.0e6".to_string()),
            ("poisson = 0.25", "poisson = 0.0".to_string()),
            ("traction = [-1.0e6, 0.0, 0.0]", "traction = [-2.0e5, 0.0, 0.0]".to_string()),
            ("traction = [1.0e6, 0.0, 0.0]", "traction = [2.0e5, 0.0, 0.0]".to_string()),
            ("max_displacement_ratio = 0.01", format!("max_displacement_ratio = 0.05\nstrain_measure = \"{measure}\"")),
            ("equilibrium_tolerance = 1e-12", "equilibrium_tolerance = 1e-11".to_string()),
        ],
    );
    let out = run_ok(&text, &format!("large_strain_{pattern}_{measure}"));
    1.0 + (final_value(&out, "end.displacement.x") - final_value(&out, "start.displacement.x")) / 10.0
}

#[test]
fn uniaxial_stretch_matches_each_strain_measure() {
    let exact_svk = svk_stretch(0.2);
    assert!((exact_svk - 1.159705).abs() < 1e-6);
    for pattern in ["tet6", "hex8"] {
        let c = stretch(pattern, "corotational");
        assert!((c - 1.2).abs() < 1e-8, "{pattern} co-rotational: λ = {c}");
        let g = stretch(pattern, "green_lagrange");
        assert!((g - exact_svk).abs() < 1e-8, "{pattern} green_lagrange: λ = {g} vs {exact_svk}");
    }
}
