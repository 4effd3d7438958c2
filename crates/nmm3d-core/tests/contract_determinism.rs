//! Contract: the same input gives bit-identical outputs, whatever the thread count.
//! History and frames are compared byte for byte (numbers are written round-trip exact).

mod common;

use common::{out_dir, scenario};
use nmm3d_core::simulation::{run, RunOptions};

const TEXT: &str = r#"
[analysis]
duration = 0.05
dt = 0.005
max_displacement_ratio = 0.01
gravity = [0.0, 0.0, -10.0]
output_interval = 0.025

[cover]
pattern = "tet5"
size = 0.3
rotation = [5.0, 10.0, 15.0]

[[material]]
name = "rock"
density = 2500.0
young = 1.0e8
poisson = 0.25

[[body]]
name = "cube"
material = "rock"
angular_velocity = [1.0, 2.0, 3.0]
shape = { convex = { planes = [[1, 0, 0, 1], [-1, 0, 0, 0], [0, 1, 0, 1], [0, -1, 0, 0], [0, 0, 1, 1], [0, 0, -1, 0], [1, 1, 1, 2.5]] } }

[[fixed_point]]
point = [0.0, 0.0, 0.0]
directions = ["z"]

[[monitor]]
name = "cube"
select = { body = "cube" }
quantities = ["displacement", "velocity", "rotation", "volume", "stress"]
"#;

fn run_with_threads(threads: usize) -> (Vec<u8>, Vec<u8>) {
    let dir = out_dir(&format!("determinism_{threads}"));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        run(scenario(TEXT), "<test>", &RunOptions { out: dir.clone(), progress: false, ..Default::default() }).unwrap()
    });
    let read = |p: &str| std::fs::read(dir.join(p)).unwrap();
    (read("history.csv"), read("frames/blocks_00002.vtu"))
}

#[test]
fn same_input_same_output_for_any_thread_count() {
    let one = run_with_threads(1);
    assert_eq!(one, run_with_threads(1), "two runs differ");
    assert_eq!(one, run_with_threads(2), "thread count changes the result");
}

/// With contact (parallel detection, facet overlay, open–close iteration): the dominos' first
/// tenth of a second, history and contact frames byte for byte.
fn contact_run_with_threads(threads: usize) -> (Vec<u8>, Vec<u8>) {
    let dir = out_dir(&format!("determinism_contact_{threads}"));
    let text = common::with(&common::example("dominos.toml"), "duration = 5.0", "duration = 0.1");
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| {
        run(scenario(&text), "<test>", &RunOptions { out: dir.clone(), progress: false, ..Default::default() }).unwrap()
    });
    let read = |p: &str| std::fs::read(dir.join(p)).unwrap();
    (read("history.csv"), read("frames/contacts_00001.vtu"))
}

#[test]
fn contact_runs_are_identical_for_any_thread_count() {
    let one = contact_run_with_threads(1);
    assert_eq!(one, contact_run_with_threads(2), "thread count changes a contact run");
}
