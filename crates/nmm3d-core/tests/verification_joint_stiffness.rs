//! Joint stiffness in Pa/m (`[[joint]] normal_stiffness`, `shear_stiffness`), as rock engineers
//! give it: a block resting on a joint closes it by σ_n / k_n and shears it by τ / k_s, however
//! finely the contact points fall.
//!
//! `examples/block_on_joint.toml` without the sideways gravity: a 1 m cube (W = 25 kN) on a
//! fixed slab, started from its initial equilibrium; at the centre of its base (a material
//! point 1 mm above it) the closed form is w = W / (k_n A). The cube is stiff (E = 100 GPa) and the cover sizes and patterns
//! put 9 to 25 contact points on the joint. (The shear, u = T / (k_s A), is checked in
//! `tests/test_joint_stiffness.py`.)

mod common;

use common::{final_value, run_ok};

/// `examples/block_on_joint.toml`'s normal stiffness [Pa/m].
const KN: f64 = 1.0e8;

fn cube_on_joint(size: f64, pattern: &str, name: &str) -> f64 {
    let text = common::with_each(
        &common::example("block_on_joint.toml"),
        &[
            ("gravity = [1.0, 0.0, -10.0]", "gravity = [0.0, 0.0, -10.0]".to_string()),
            ("pattern = \"hex8\"", format!("pattern = \"{pattern}\"")),
            ("size = 0.5", format!("size = {size}")),
        ],
    );
    let out = run_ok(&text, name);
    -final_value(&out, "base.displacement.z")
}

#[test]
fn a_block_closes_its_joint_by_the_stress_over_the_joint_stiffness_however_the_points_fall() {
    let closure = 25_000.0 / KN;
    for (size, pattern) in [(0.5, "tet6"), (0.25, "tet6"), (0.5, "hex8")] {
        let settled = cube_on_joint(size, pattern, &format!("joint_stiffness_{pattern}_{size}"));
        assert!(
            (settled - closure).abs() < 0.002 * closure,
            "{pattern} cover {size} m: closed {settled} m, W/(k_n A) = {closure} m"
        );
    }
}
