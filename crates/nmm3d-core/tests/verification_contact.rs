//! Verification of the contact algorithm beyond the incline: joint strength (cohesion, tensile
//! strength), in-situ stress as joint traction (roof wedge, case C1), stacked blocks at rest,
//! impact (i) and collision, overlapping input, and the detection margin of a moving step.

mod common;

use common::{example, final_value, history, run_ok, scenario};
use nmm3d_core::error::Error;
use nmm3d_core::simulation::{RunOutcome, Status};
use nmm3d_core::system::System;
use nmm3d_core::time::{State, Stepper};

/// Materials, joint, base slab and analysis shared by the cube cases; `extra` adds bodies etc.
fn cube_case(analysis: &str, joint: &str, extra: &str) -> String {
    format!(
        r#"
[analysis]
{analysis}
output_interval = 0.0

[cover]
pattern = "tet6"
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.0

[[joint]]
name = "j"
{joint}

{extra}
"#
    )
}

/// A 1 × 1 × 0.5 m slab on a frictionless 30° incline glued by cohesion c [Pa]; returns the
/// slide [m]. (Squat, so the whole base stays in compression: a 1 m cube's uphill third would
/// lift off and break its bond in tension.)
fn glued_cube_slide(cohesion: f64, name: &str) -> f64 {
    let (base, cube) = common::incline_planes(30.0, 0.0, 0.5);
    let text = cube_case(
        "duration = 0.5\ndt = 0.002\nmax_displacement_ratio = 0.002\ngravity = [0.0, 0.0, -10.0]\ninitial_equilibrium = true",
        &format!("friction_angle = 0.0\ncohesion = {cohesion}"),
        &format!(
            r#"
[[body]]
name = "base"
material = "rock"
fixed = true
shape = {{ convex = {{ planes = [{base}] }} }}

[[body]]
name = "cube"
material = "rock"
joint = "j"
shape = {{ convex = {{ planes = [{cube}] }} }}

[[monitor]]
name = "cube"
select = {{ body = "cube" }}
quantities = ["displacement"]
"#
        ),
    );
    let out = run_ok(&text, name);
    // Down-dip is (0, cos α, −sin α).
    let a = 30f64.to_radians();
    final_value(&out, "cube.displacement.y") * a.cos() - final_value(&out, "cube.displacement.z") * a.sin()
}

#[test]
fn cohesion_holds_a_cube_until_the_shear_exceeds_c_times_area() {
    // Driving force W sin α = 2500 × 10 × 0.5 × ½ = 6.25 kN on 1 m².
    let driving = 6_250.0;
    let held = glued_cube_slide(1.3 * driving, "cohesion_holds");
    assert!(held.abs() < 1e-5, "c A = 1.3 W sin α: slid {held} m");
    // Broken bond, no friction: slides as ½ g sin α t² = 0.625 m at t = 0.5 s.
    let slid = glued_cube_slide(0.7 * driving, "cohesion_breaks");
    assert!((slid - 0.625).abs() < 0.01 * 0.625, "c A = 0.7 W sin α: slid {slid} m, frictionless 0.625 m");
}

/// A 1 m cube hanging under a fixed slab, bonded by tensile strength T and cohesion T [Pa]
/// (with c = 0 a joint in tension has no shear strength at all); returns its fall [m].
fn hanging_cube_fall(tensile: f64, name: &str) -> f64 {
    let text = cube_case(
        "duration = 0.5\ndt = 0.002\nmax_displacement_ratio = 0.01\ngravity = [0.0, 0.0, -10.0]\ninitial_equilibrium = true",
        &format!("friction_angle = 30.0\ntensile_strength = {tensile}\ncohesion = {tensile}"),
        r#"
[[body]]
name = "roof"
material = "rock"
fixed = true
shape = { box = { min = [-2.0, -2.0, 1.0], max = [2.0, 2.0, 2.0] } }

[[body]]
name = "cube"
material = "rock"
joint = "j"
shape = { box = { min = [-0.5, -0.5, 0.0], max = [0.5, 0.5, 1.0] } }

[[monitor]]
name = "cube"
select = { body = "cube" }
quantities = ["displacement"]
"#,
    );
    let out = run_ok(&text, name);
    -final_value(&out, "cube.displacement.z")
}

#[test]
fn tensile_strength_holds_a_hanging_cube_until_the_weight_exceeds_t_times_area() {
    let weight = 25_000.0; // N on 1 m²
    let held = hanging_cube_fall(1.3 * weight, "tension_holds");
    assert!(held.abs() < 1e-5, "T A = 1.3 W: fell {held} m");
    let fell = hanging_cube_fall(0.7 * weight, "tension_breaks");
    assert!((fell - 1.25).abs() < 0.01 * 1.25, "T A = 0.7 W: fell {fell} m, free fall 1.25 m");
}

/// Roof wedge C1 (verification case (c)): three joints dipping 60° (dip directions 30°, 150°,
/// 270°), apex 1 m above the roof z = 0; σ_xx = σ_yy = −0.05 MPa; ρ = 2000, g = 10;
/// k_n = k_s = 10 MPa/m. Returns the wedge's vertical displacement after 0.5 s [m].
fn roof_wedge(phi: f64, name: &str) -> f64 {
    let r = 2.0 / 3f64.sqrt(); // circumradius of the base triangle (side 2 m)
    let base = [[r, 0.0], [-0.5 * r, 1.0], [-0.5 * r, -1.0]];
    let apex = [0.0, 0.0, 1.0];
    let v = |p: [f64; 2]| format!("[{}, {}, 0.0]", p[0], p[1]);
    let wedge = format!(
        "{{ polyhedron = {{ vertices = [{}, {}, {}, [0.0, 0.0, 1.0]], faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]] }} }}",
        v(base[0]),
        v(base[1]),
        v(base[2])
    );
    // Rock beyond each face: the half-space outside the face within a box above the roof.
    let mut rock = String::new();
    for (i, (p, q)) in [(base[0], base[1]), (base[1], base[2]), (base[2], base[0])].into_iter().enumerate() {
        let e1 = [q[0] - p[0], q[1] - p[1], 0.0];
        let e2 = [apex[0] - p[0], apex[1] - p[1], apex[2]];
        // Outward normal of the wedge face (p, q, apex) = e1 × e2.
        let n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
        let d = n[0] * p[0] + n[1] * p[1];
        rock += &format!(
            r#"
[[body]]
name = "rock{i}"
material = "rock"
fixed = true
shape = {{ convex = {{ planes = [[{}, {}, {}, {}], [1, 0, 0, 3], [-1, 0, 0, 3], [0, 1, 0, 3], [0, -1, 0, 3], [0, 0, 1, 3], [0, 0, -1, 0]] }} }}
"#,
            -n[0], -n[1], -n[2], -d
        );
    }
    let k = 10.0e6 * 0.5 * 0.5; // 10 MPa/m over one cover cell's face (size²)
    let text = format!(
        r#"
[analysis]
duration = 0.5
dt = 0.002
max_displacement_ratio = 0.01
gravity = [0.0, 0.0, -10.0]
output_interval = 0.0
initial_equilibrium = true

[cover]
pattern = "tet6"
size = 0.5

[contact]
normal_stiffness = {k}
shear_stiffness = {k}

[in_situ_stress]
stress = [-5.0e4, -5.0e4, 0.0, 0.0, 0.0, 0.0]

[[material]]
name = "rock"
density = 2000.0
young = 10.0e9
poisson = 0.0

[[joint]]
name = "j"
friction_angle = {phi}
{rock}
[[body]]
name = "wedge"
material = "rock"
joint = "j"
shape = {wedge}

[[monitor]]
name = "wedge"
select = {{ body = "wedge" }}
quantities = ["displacement"]
"#
    );
    let out = run_ok(&text, name);
    final_value(&out, "wedge.displacement.z")
}

/// φ_c of the roof wedge with k_s = k_n: tan(φ_c − α) = W cos α / (σ_n ΣA).
fn roof_wedge_critical_angle() -> f64 {
    let alpha = 30f64.to_radians(); // semi-apical angle = 90° − dip
    let sigma_n = 0.05e6 * alpha.cos().powi(2);
    let r: f64 = 2.0 / 3f64.sqrt();
    let area = 3.0 * 2.0 * (1.0 + 0.25 * r * r).sqrt() / 2.0;
    let weight = 2000.0 * 10.0 * (3f64.sqrt() / 4.0 * 4.0) / 3.0;
    ((weight * alpha.cos() / (sigma_n * area)).atan() + alpha).to_degrees()
}

#[test]
fn roof_wedge_held_by_in_situ_stress_stays_above_and_falls_below_the_critical_angle() {
    let phi_c = roof_wedge_critical_angle();
    assert!((phi_c - 34.40).abs() < 0.01, "closed form {phi_c}");
    // Stable: settles W / (k ΣA) = 0.333 mm (with k_s = k_n every spring pushes straight up).
    let settled = -roof_wedge(phi_c + 1.0, "roof_wedge_stays");
    assert!((settled - 0.333e-3).abs() < 0.05 * 0.333e-3, "φ_c + 1°: settled {settled} m, expected 0.333 mm");
    let z = history("roof_wedge_stays", "wedge.displacement.z");
    let growth = (z.last().unwrap().1 - z[z.len() / 2].1).abs();
    assert!(growth < 1e-6, "φ_c + 1°: still moving ({growth} m over the last 0.25 s)");
    let fallen = -roof_wedge(phi_c - 1.0, "roof_wedge_falls");
    assert!(fallen > 0.01, "φ_c − 1°: moved only {fallen} m");
}

/// A tower of `n` 1 m cubes on a fixed slab; dynamic with gravity for `steps` steps.
fn tower(n: usize, steps: u64, name: &str) -> RunOutcome {
    let mut bodies = String::from(
        r#"
[[body]]
name = "base"
material = "rock"
fixed = true
shape = { box = { min = [-2.0, -2.0, -1.0], max = [2.0, 2.0, 0.0] } }
"#,
    );
    for k in 0..n {
        bodies += &format!(
            r#"
[[body]]
name = "cube{k}"
material = "rock"
joint = "j"
shape = {{ box = {{ min = [-0.5, -0.5, {k}.0], max = [0.5, 0.5, {}.0] }} }}

[[monitor]]
name = "cube{k}"
select = {{ body = "cube{k}" }}
quantities = ["displacement"]
"#,
            k + 1
        );
    }
    let text = cube_case(
        &format!("duration = 1.0e3\ndt = 0.001\nmax_steps = {steps}\nmax_displacement_ratio = 0.001\ngravity = [0.0, 0.0, -10.0]"),
        "friction_angle = 30.0",
        &bodies,
    );
    run_ok(&text, name)
}

#[test]
fn block_on_block_and_a_three_block_tower_rest_without_drift() {
    let (rho, g, e, h) = (2500.0, 10.0, 10.0e9, 1.0);
    let weight = rho * g * h;
    // "auto": the default factor × E × cover size, per point; four points per face.
    let kn = nmm3d_core::scenario::ContactSpec::default().auto_penalty_factor * e * 0.5;
    for n in [2usize, 3] {
        let name = format!("tower_{n}");
        let out = tower(n, 4000, &name);
        let pen = out.summary.max_penetration;
        assert!(pen < 1e-3 * 0.5, "{n} blocks: penetration {pen} m");
        // Centroid settlement of the top cube: penalty compression of every interface
        // (load of the cubes above / 4 k_n) + elastic shortening of the cubes below (uniaxial,
        // ν = 0) + the top cube's own shortening below its centroid (3/8 ρ g h² / E).
        let mut expected = 0.0;
        for k in 0..n {
            let above = (n - k) as f64 * weight;
            expected += above / (4.0 * kn);
            if k + 1 < n {
                expected += (above - weight) * h / e + rho * g * h * h / (2.0 * e);
            }
        }
        expected += 3.0 / 8.0 * rho * g * h * h / e;
        let top = format!("cube{}", n - 1);
        let settled = -final_value(&out, &format!("{top}.displacement.z"));
        assert!((settled - expected).abs() < 0.1 * expected, "{n} blocks: settled {settled} m, expected {expected} m");
        for k in 0..n {
            for c in ["x", "y"] {
                let drift = final_value(&out, &format!("cube{k}.displacement.{c}")).abs();
                assert!(drift < 1e-4, "{n} blocks: cube {k} drifted {drift} m along {c}");
            }
        }
    }
}

/// A 1 m cube (2500 kg) reaching a fixed base at the speed of a 1 m drop (g = 10), total normal
/// stiffness 1e9 N/m (examples/drop_test.toml), Newmark γ = ½. Returns (contact time, penetration).
fn drop_test() -> (f64, f64) {
    let gap: f64 = 1e-3; // the cube starts this far above the base (examples/drop_test.toml)
    run_ok(&example("drop_test.toml"), "drop_test");
    let z = history("drop_test", "cube.displacement.z");
    // In contact while the cube is below its touching level.
    let inside: Vec<f64> = z.iter().filter(|(_, u)| *u < -gap).map(|(t, _)| *t).collect();
    let (first, last) = (inside[0], *inside.last().unwrap());
    let deepest = z.iter().map(|(_, u)| -u - gap).fold(0.0, f64::max);
    (last - first, deepest)
}

/// The exact piecewise-linear ODE: p'' = g − (k/m) p from p = 0, p' = v.
fn drop_exact() -> (f64, f64) {
    let (g, k, m, v) = (10.0f64, 1e9f64, 2500.0f64, (2.0f64 * 10.0).sqrt());
    let w = (k / m).sqrt();
    let r = ((g / (w * w)).powi(2) + (v / w).powi(2)).sqrt();
    let delta = (g / (w * w) / r).asin();
    ((std::f64::consts::PI + 2.0 * delta) / w, g / (w * w) + r)
}

#[test]
fn drop_test_contact_time_and_penetration_match_the_exact_impact() {
    let (t_exact, p_exact) = drop_exact();
    assert!((t_exact - 4.978e-3).abs() < 1e-6 && (p_exact - 7.096e-3).abs() < 1e-6);
    let (t, p) = drop_test();
    assert!((t - t_exact).abs() < 0.05 * t_exact, "contact time {t} s, exact {t_exact} s");
    assert!((p - p_exact).abs() < 0.05 * p_exact, "penetration {p} m, exact {p_exact} m");
}

#[test]
fn two_block_collision_conserves_momentum() {
    for integrator in ["dda", "newmark"] {
        let text = format!(
            r#"
[analysis]
duration = 0.02
dt = 1.0e-4
max_displacement_ratio = 0.05
gravity = [0.0, 0.0, 0.0]
output_interval = 0.0
integrator = "{integrator}"

[cover]
pattern = "tet6"
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 10.0e9
poisson = 0.25

[[body]]
name = "moving"
material = "rock"
velocity = [2.0, 0.0, 0.0]
shape = {{ box = {{ min = [-1.001, 0.0, 0.0], max = [-0.001, 1.0, 1.0] }} }}

[[body]]
name = "resting"
material = "rock"
shape = {{ box = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }} }}
"#
        );
        let sys = System::build(scenario(&text), "<test>").unwrap_or_else(|e| panic!("{e}"));
        let mut whole = State::initial(&sys);
        let mut stepper = Stepper::new(&sys, &mut whole, "<test>").unwrap_or_else(|e| panic!("{e}"));
        stepper.initialize(&sys, &mut whole).unwrap();
        let p0 = sys.momentum(&whole.motion.v);
        assert!((p0.x - 5000.0).abs() < 1e-6, "{integrator}: initial momentum {p0}");
        let mut touched = false;
        while whole.motion.time < 0.02 {
            let cap = 0.02 - whole.motion.time;
            let r = stepper.step(&sys, &mut whole, cap).unwrap_or_else(|e| panic!("{e}"));
            touched |= r.contacts > 0 && r.max_penetration > 0.0;
        }
        let state = &whole.motion;
        assert!(touched, "{integrator}: the blocks never touched");
        let p = sys.momentum(&state.v);
        assert!((p - p0).norm() < 1e-9 * p0.norm(), "{integrator}: momentum {p} vs {p0}");
        // The struck block moves off: momentum really was exchanged.
        let b1: Vec<usize> = (0..sys.covers.covers.len()).filter(|&c| sys.covers.covers[c].block == 1).collect();
        let v1 = b1.iter().map(|&c| state.v[c].x).sum::<f64>() / b1.len() as f64;
        assert!(v1 > 1.0, "{integrator}: struck block moves at {v1} m/s");
    }
}

#[test]
fn blocks_overlapping_at_the_start_are_invalid_input_naming_both() {
    let text = cube_case(
        "duration = 0.1\ndt = 0.01",
        "friction_angle = 30.0",
        r#"
[[body]]
name = "left"
material = "rock"
shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] } }

[[body]]
name = "right"
material = "rock"
shape = { box = { min = [0.9, 0.0, 0.0], max = [1.9, 1.0, 1.0] } }
"#,
    );
    let sys = System::build(scenario(&text), "case.toml").unwrap();
    let mut state = State::initial(&sys);
    match Stepper::new(&sys, &mut state, "case.toml") {
        Err(e @ Error::Scenario { .. }) => {
            let m = e.to_string();
            assert!(
                m.contains("case.toml") && m.contains("'left'") && m.contains("'right'") && m.contains("overlaps"),
                "{m}"
            );
            assert_eq!(e.exit_code(), 2);
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("overlapping blocks accepted"),
    }
}

#[test]
fn a_soft_penalty_is_raised_until_the_overlap_is_allowed() {
    // The drop test with a hundredth of its stiffness would overlap by 2.2 cm (4.5 % of the
    // 0.5 m cover): the penalty must be raised until the overlap stays below 1 %.
    let text = common::with_each(
        &common::example("drop_test.toml"),
        &[
            ("normal_stiffness = 2.5e8", "normal_stiffness = 2.5e6"),
            ("shear_stiffness = 2.5e8", "shear_stiffness = 2.5e6"),
            ("dt = 1.0e-5", "dt = 0.002"),
            ("duration = 0.0062", "duration = 0.05"),
            ("max_penetration_ratio = 0.05", "max_penetration_ratio = 0.01"),
        ],
    );
    let out = run_ok(&text, "soft_penalty");
    let raises = out.summary.penalty_raises;
    let pen = out.summary.max_penetration;
    assert!(raises >= 1, "no raise (penetration {pen} m)");
    assert!(pen <= 0.01 * 0.5, "overlap {pen} m beyond 1 % of the cover size");
}

#[test]
fn dda_scheme_restitution_matches_the_table() {
    // Verification case (i): the DDA scheme (γ = 1) dissipates a bounce; restitution at
    // ω Δt = 0.05 / 0.1 / 0.2 / 0.5 is 0.962 / 0.925 / 0.855 / 0.684 (ω² = k / m, no gravity).
    let omega = (1e9f64 / 2500.0).sqrt();
    for (wdt, table) in [(0.05, 0.962), (0.1, 0.925), (0.2, 0.855), (0.5, 0.684)] {
        let text = common::with_each(
            &common::example("drop_test.toml"),
            &[
                ("dt = 1.0e-5", format!("dt = {}", wdt / omega)),
                ("integrator = \"newmark\"", "integrator = \"dda\"".into()),
                ("gravity = [0.0, 0.0, -10.0]", "gravity = [0.0, 0.0, 0.0]".into()),
                ("duration = 0.0062", "duration = 0.012".into()),
                ("max_displacement_ratio = 0.05", "max_displacement_ratio = 1.0".into()),
            ],
        );
        let name = format!("restitution_{wdt}");
        run_ok(&text, &name);
        let v = history(&name, "cube.velocity.z");
        let e = -v.last().unwrap().1 / v[0].1;
        assert!((e - table).abs() < 0.005, "ω Δt = {wdt}: restitution {e}, table {table}");
    }
}

#[test]
fn an_open_close_iteration_that_cannot_settle_fails_the_run_with_its_reason() {
    // One iteration allowed and no step cuts possible: the cube's points must go from stick to
    // slide in the first step, which needs a second iteration.
    let mut text = common::example("incline.toml");
    text = common::with(
        &text,
        "initial_equilibrium = true",
        "initial_equilibrium = true\nmax_open_close = 1\nmin_dt_ratio = 1.0",
    );
    let dir = common::out_dir("unsettled");
    let out = nmm3d_core::simulation::run(
        scenario(&text),
        "<test>",
        &nmm3d_core::simulation::RunOptions { out: dir.clone(), progress: false, ..Default::default() },
    )
    .unwrap();
    assert!(!out.completed);
    let message = out.summary.message.as_str();
    assert!(message.contains("open–close iteration did not settle"), "{message}");
    assert_eq!(out.summary.status, Status::Failed);
    assert!(dir.join("summary.json").exists() && dir.join("history.csv").exists() && dir.join("result.pvd").exists());
}

/// A fixed base and two 1 m cubes on it, "left" and "right", their facing sides `gap` apart;
/// `left` adds keys to the left cube (e.g. its velocity).
fn two_cubes(gap: f64, left: &str) -> String {
    format!(
        r#"
[[body]]
name = "base"
material = "rock"
fixed = true
shape = {{ box = {{ min = [-2.0, -2.0, -1.0], max = [4.0, 2.0, 0.0] }} }}

[[body]]
name = "left"
material = "rock"
joint = "j"
{left}
shape = {{ box = {{ min = [-1.0, -0.5, 0.0], max = [0.0, 0.5, 1.0] }} }}

[[body]]
name = "right"
material = "rock"
joint = "j"
shape = {{ box = {{ min = [{gap}, -0.5, 0.0], max = [{}, 0.5, 1.0] }} }}
"#,
        gap + 1.0
    )
}

/// Two 1 m cubes resting on a fixed base, their facing sides `gap` apart; `steps` steps.
fn side_by_side(gap: f64, name: &str) -> RunOutcome {
    let bodies = two_cubes(gap, "");
    let text = cube_case(
        "duration = 1.0\ndt = 0.001\nmax_steps = 20\ngravity = [0.0, 0.0, -10.0]",
        "friction_angle = 30.0",
        &bodies,
    );
    run_ok(&text, name)
}

#[test]
fn open_contacts_add_no_fill_to_the_system_matrix() {
    // Side faces 2 mm apart are within the detection margin: their points are detected, open.
    // Only pairs of MEs with a closed point are coupled in the matrix, so its factor is the same
    // as with the cubes far apart, and grew as often.
    // (Tested on the factor's size: the contact pattern as it was first built coupled every
    // detected pair, open or not.)
    let near = side_by_side(0.002, "side_by_side_near");
    let far = side_by_side(1.002, "side_by_side_far"); // shifted by two cover cells: the same MEs
    let points = |o: &RunOutcome| o.summary.max_contact_points;
    assert!(points(&near) > points(&far), "the near sides are detected: {} vs {}", points(&near), points(&far));
    assert_eq!(near.summary.factor_nonzeros, far.summary.factor_nonzeros);
    assert_eq!(
        near.summary.pattern_rebuilds, far.summary.pattern_rebuilds,
        "the pattern grew for the base contacts only"
    );
}

/// A 1 m cube sliding at 1 m/s on a frictionless fixed base past a cube at rest, their facing
/// sides `gap` apart; the side pair's contact points after the first detection and after
/// `steps` steps of 1 ms.
fn side_points(gap: f64, steps: usize) -> (usize, usize) {
    let bodies = two_cubes(gap, "velocity = [0.0, 1.0, 0.0]");
    let analysis = "duration = 1.0\ndt = 0.001\nmax_displacement_ratio = 0.05\ngravity = [0.0, 0.0, -10.0]";
    let text = cube_case(analysis, "friction_angle = 0.0", &bodies);
    let sys = System::build(scenario(&text), "<test>").unwrap_or_else(|e| panic!("{e}"));
    let mut whole = State::initial(&sys);
    let mut stepper = Stepper::new(&sys, &mut whole, "<test>").unwrap_or_else(|e| panic!("{e}"));
    stepper.initialize(&sys, &mut whole).unwrap();
    let block = |name: &str| {
        let named = |b: &usize| sys.scenario.body[sys.geometry.blocks[*b].body].name == name;
        (0..sys.geometry.blocks.len()).find(named).expect("a block of that body")
    };
    let (a, b) = (block("left"), block("right"));
    let pair = (a.max(b), a.min(b));
    let sides = |w: &State| w.contact.as_ref().unwrap().records.iter().filter(|r| r.blocks == pair).count();
    let first = sides(&whole);
    for _ in 0..steps {
        stepper.step(&sys, &mut whole, 1.0).unwrap_or_else(|e| panic!("{e}"));
    }
    (first, sides(&whole))
}

#[test]
fn a_moving_step_detects_within_twice_its_reach_not_the_step_controls_bound() {
    // The step control allows 0.05 × 3 m = 0.15 m per step, so the first detection (no motion
    // known yet) takes the sides 50 mm apart as open points. Sliding at 1 m/s a step moves
    // 1 mm, and later detections look 0.5 mm + 2 × 4 (`reach_safety`) × 1 mm far: they leave
    // the sides 50 mm apart out and keep those 2 mm apart.
    let (first, later) = side_points(0.05, 20);
    assert!(first > 0, "the first detection takes the sides within the step control's margin");
    assert_eq!(later, 0, "sides 50 mm apart are beyond the step's margin");
    let (first, later) = side_points(0.002, 20);
    assert!(first > 0 && later > 0, "sides 2 mm apart are within it: {first}, {later}");
}
