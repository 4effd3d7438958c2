//! Verification of the initial (in-situ) stress terms, compression negative.
//!
//! * Relaxation: a free cube with uniform initial σ_xx = −1 MPa (held by six statically
//!   determinate points) expands until its stress vanishes: u_x(1) − u_x(0) = −σ₀L/E = +0.1 mm,
//!   final stress ≈ 0.
//! * Lithostatic column: σ_zz(z) = ρg(z − z_top) (gradient ρg) is already in equilibrium with
//!   gravity on a column supported at its base, so nothing moves (gradient and sign check).

mod common;

use common::{final_value, run_ok};

const BASE: &str = r#"
[analysis]
kind = "static"
duration = 1000.0
dt = 1.0
max_displacement_ratio = 0.05
equilibrium_tolerance = 1e-10
output_interval = 0.0

[cover]
pattern = "tet24"
size = 0.5
rotation = [5.0, 10.0, 20.0]

[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.25

[[body]]
name = "block"
material = "rock"
"#;

#[test]
fn free_block_relaxes_its_initial_stress() {
    let text = format!(
        "{BASE}gravity = [0.0, 0.0, 0.0]\nshape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }} }}\n{}",
        r#"
[in_situ_stress]
stress = [-1.0e6, 0.0, 0.0, 0.0, 0.0, 0.0]

[[fixed_point]]
point = [0.0, 0.0, 0.0]
directions = ["x", "y", "z"]

[[fixed_point]]
point = [0.0, 1.0, 0.0]
directions = ["x", "z"]

[[fixed_point]]
point = [0.0, 0.0, 1.0]
directions = ["x"]

[[monitor]]
name = "a"
select = { point = [0.0, 0.5, 0.5] }
quantities = ["displacement"]
location = "point"

[[monitor]]
name = "b"
select = { point = [1.0, 0.5, 0.5] }
quantities = ["displacement", "stress"]
location = "point"
"#
    )
    .replace("gravity = [0.0, 0.0, 0.0]\nshape", "shape")
    .replace("output_interval = 0.0", "output_interval = 0.0\ngravity = [0.0, 0.0, 0.0]");
    let out = run_ok(&text, "in_situ_relaxation");
    let stretch = final_value(&out, "b.displacement.x") - final_value(&out, "a.displacement.x");
    let exact = 1.0e6 * 1.0 / 10.0e9;
    assert!((stretch - exact).abs() < 1e-6 * exact, "{stretch} vs {exact}");
    for c in ["xx", "yy", "zz", "xy", "yz", "zx"] {
        let s = final_value(&out, &format!("b.stress.{c}"));
        assert!(s.abs() < 1e-3, "residual stress {c} = {s} Pa");
    }
}

#[test]
fn lithostatic_column_is_in_equilibrium_at_the_start() {
    let rho_g = 2500.0 * 10.0;
    let tail = format!(
        r#"
[in_situ_stress]
stress = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
gradient = [0.0, 0.0, {rho_g}, 0.0, 0.0, 0.0]
reference_z = 4.0

[[constraint]]
select = {{ box = {{ min = [-0.01, -0.01, -0.01], max = [1.01, 1.01, 0.01] }} }}
directions = ["z"]

[[fixed_point]]
point = [0.0, 0.0, 0.0]
directions = ["x", "y"]

[[fixed_point]]
point = [1.0, 0.0, 0.0]
directions = ["y"]

[[monitor]]
name = "top"
select = {{ point = [0.5, 0.5, 4.0] }}
quantities = ["displacement"]
location = "point"

[[monitor]]
name = "column"
select = {{ body = "block" }}
quantities = ["stress"]
"#
    );
    let text = format!("{BASE}shape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 4.0] }} }}\n{tail}")
        .replace("output_interval = 0.0", "output_interval = 0.0\ngravity = [0.0, 0.0, -10.0]");
    let out = run_ok(&text, "in_situ_lithostatic");
    // Elastic settlement without the initial stress would be ρgL²/(2E) = 2e-5 m.
    let uz = final_value(&out, "top.displacement.z");
    assert!(uz.abs() < 1e-9, "the column moved {uz} m");
    // Mean vertical stress = −ρg L/2 (compression negative). The base penalty springs carry the
    // 100 kN weight and yield by ~1e-10 m, a strain of ~1e-10, i.e. a few Pa: tolerance 1e-4.
    let szz = final_value(&out, "column.stress.zz");
    assert!((szz + rho_g * 2.0).abs() < 1e-4 * rho_g * 2.0, "{szz}");
}
