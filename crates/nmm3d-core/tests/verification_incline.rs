//! Verification (b): a cube on a 30° incline (thesis Fig. 4-8..4-10).
//!
//! Closed form d(t) = ½ g (sin α − tan φ cos α) t² for φ < α, else d = 0 (no creep). 1 m cube,
//! ρ = 2500, E = 10 GPa, g = 10, α = 30°, t = 1 s; tolerance max(1 % of d, 1 mm), sliding
//! direction within 0.5° of down-dip; a stuck cube does not creep.
//!
//! The closed form is for a rigid block. The elastic cube starts from its initial equilibrium
//! (`initial_equilibrium`: gravity applied with the contacts locked — released from rest
//! under sudden gravity, the elastic settlement would turn into velocity), and ν = 0: with
//! ν > 0 the base corners held by friction lock in radial shear forces (the Poisson expansion
//! of the loaded cube), which tilt the friction of each corner away from down-dip for the first
//! millimetres of slip — a real effect of an elastic block that a rigid block does not have
//! (≈ 1.2 mm more slide at φ = 29°).

mod common;

use common::{final_value, history, run_ok};

/// ½ g (sin α − tan φ cos α) t², or 0 when friction holds.
fn slide_distance(alpha_deg: f64, phi_deg: f64, g: f64, t: f64) -> f64 {
    let (a, p) = (alpha_deg.to_radians(), phi_deg.to_radians());
    (0.5 * g * (a.sin() - p.tan() * a.cos()) * t * t).max(0.0)
}

fn incline(phi: f64, dip_direction: f64) -> String {
    let (base, cube) = common::incline_planes(30.0, dip_direction, 1.0);
    format!(
        r#"
[analysis]
duration = 1.0
dt = 0.002
max_displacement_ratio = 0.002
gravity = [0.0, 0.0, -10.0]
output_interval = 0.0
initial_equilibrium = true

[cover]
pattern = "tet6"
size = 0.5



[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.0

[[joint]]
name = "face"
friction_angle = {phi}

[[body]]
name = "base"
material = "rock"
fixed = true
shape = {{ convex = {{ planes = [{base}] }} }}

[[body]]
name = "cube"
material = "rock"
joint = "face"
shape = {{ convex = {{ planes = [{cube}] }} }}

[[monitor]]
name = "cube"
select = {{ body = "cube" }}
quantities = ["displacement"]
"#
    )
}

fn check(phi: f64, dd: f64) {
    let name = format!("incline_{phi}_{dd}");
    let out = run_ok(&incline(phi, dd), &name);
    let u = [0, 1, 2].map(|i| final_value(&out, &format!("cube.displacement.{}", ["x", "y", "z"][i])));
    let d = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let exact = slide_distance(30.0, phi, 10.0, 1.0);
    let tol = (0.01 * exact).max(1e-3);
    let pen = out.summary.max_penetration;
    assert!(pen > 0.0 && pen < 1e-4, "φ = {phi}: max penetration {pen} m");
    assert!(out.summary.max_contact_points >= 3);
    assert!((d - exact).abs() <= tol, "φ = {phi}, dd = {dd}: slid {d} m, exact {exact} m");
    if exact > 0.01 {
        let a = 30f64.to_radians();
        let ddr = dd.to_radians();
        let s = [a.cos() * ddr.sin(), a.cos() * ddr.cos(), -a.sin()];
        let cos = (u[0] * s[0] + u[1] * s[1] + u[2] * s[2]) / d;
        assert!(
            cos.clamp(-1.0, 1.0).acos().to_degrees() < 0.5,
            "φ = {phi}: direction off by {} deg",
            cos.acos().to_degrees()
        );
    }
}

#[test]
fn cube_on_incline_slides_as_the_closed_form() {
    for phi in [0.0, 5.0, 10.0, 15.0, 20.0, 24.0] {
        check(phi, 90.0);
    }
}

#[test]
fn cube_on_incline_near_critical_angle_slides_as_the_closed_form() {
    for phi in [25.0, 29.0] {
        check(phi, 90.0);
    }
}

#[test]
fn cube_on_incline_sticks_without_creep() {
    for phi in [31.0, 35.0] {
        check(phi, 90.0);
        // Not growing: the second half second adds less than a micrometre.
        let x = history(&format!("incline_{phi}_90"), "cube.displacement.x");
        let at = |t: f64| x.iter().find(|(s, _)| *s >= t - 1e-9).expect("time").1;
        let creep = (at(1.0) - at(0.5)).abs();
        assert!(creep < 1e-6, "φ = {phi}: crept {creep} m in the last 0.5 s");
    }
}

#[test]
fn incline_not_aligned_with_an_axis() {
    check(10.0, 57.0);
    check(33.0, 57.0);
}
