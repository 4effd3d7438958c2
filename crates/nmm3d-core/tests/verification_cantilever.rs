//! Verification (f): cantilever, L = 10 m, 1 × 1 m section, E = 10 GPa, ν = 0.25, ρ = 2500.
//!
//! Clamped face x = 0 (every boundary vertex held in x, y, z). Tip load 100 kN as a uniform
//! shear traction on x = L: 3-D reference 0.04009 m (Euler–Bernoulli PL³/(3EI) = 0.04000 m).
//! Linear tetrahedra lock in bending, so the suite asserts monotone convergence under
//! refinement and the finest error of this fast version; the full table (down to s = 0.125 m)
//! is written to `docs/verification.md` by `python bench/verification.py`.

mod common;

use common::{final_value, run_ok};

/// Euler–Bernoulli tip deflection P L³ / (3 E I) of a square section b × b.
fn euler_bernoulli_tip(p: f64, l: f64, e: f64, b: f64) -> f64 {
    p * l.powi(3) / (3.0 * e * b.powi(4) / 12.0)
}

/// 3-D elastic reference of this case (docs/verification.md (f)).
const REFERENCE_TIP: f64 = 0.04009;

fn tip_deflection(pattern: &str, size: f64) -> f64 {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cantilever.toml")).unwrap();
    assert!(text.contains("pattern = \"hex8\"\nsize = 0.125"), "the example's cover changed: update this test");
    let text = text
        .replace("pattern = \"hex8\"", &format!("pattern = \"{pattern}\""))
        .replace("size = 0.125", &format!("size = {size}"));
    let out = run_ok(&text, &format!("cantilever_{pattern}_{size}"));
    -final_value(&out, "tip.displacement.z")
}

#[test]
fn cantilever_tip_load_converges_monotonically() {
    assert!((euler_bernoulli_tip(1e5, 10.0, 10e9, 1.0) - 0.04).abs() < 1e-15);
    for pattern in ["hex8", "tet24", "tet6"] {
        let coarse = tip_deflection(pattern, 0.5);
        let fine = tip_deflection(pattern, 0.25);
        assert!(coarse < fine && fine < REFERENCE_TIP * 1.01, "{pattern}: {coarse} then {fine}");
        let err = (REFERENCE_TIP - fine) / REFERENCE_TIP;
        let bound = if pattern == "tet6" { 0.25 } else { 0.06 };
        assert!(err < bound, "{pattern} at s = 0.25: error {err:.4}");
    }
}

/// Equilibrium with few factorisations: the Newton iterations of the static run are solved by
/// PCG on an earlier factor (renewed once, when the beam's rotation has moved the tangent), and
/// reach the same tip deflection as factorising at every iteration. The last step finds the
/// beam balanced at its start and solves nothing.
#[test]
fn cantilever_equilibrium_reuses_its_first_factor() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/cantilever.toml")).unwrap();
    let text = common::with(&text, "size = 0.125", "size = 0.25");
    let every = common::with(&text, "[analysis]", "[analysis]\nfactor_reuse = false");
    let (reused, direct) = (run_ok(&text, "cantilever_reused"), run_ok(&every, "cantilever_direct"));
    let (a, b) = (final_value(&reused, "tip.displacement.z"), final_value(&direct, "tip.displacement.z"));
    assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
    let (reused, direct) = (&reused.summary, &direct.summary);
    assert_eq!(direct.factorizations, direct.steps - 1);
    assert!(direct.steps >= 4);
    // The first factor and its one renewal; every other iteration by PCG.
    assert!(reused.factorizations <= 2 && reused.krylov_solves >= 3, "{reused:?}");
    assert_eq!(reused.krylov_solves + reused.factorizations, reused.steps - 1);
}
