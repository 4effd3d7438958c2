//! Contract: a run stopped mid-way (with contacts) and resumed from its checkpoint continues
//! bit for bit as the run that never stopped; the whole state round-trips through the file.

mod common;

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use common::{out_dir, scenario};
use nmm3d_core::assembly::SparsityPattern;
use nmm3d_core::checkpoint::{self, Checkpoint};
use nmm3d_core::simulation::{run, RunOptions, Status, StopRequest};
use nmm3d_core::solver::ordering::amd;
use nmm3d_core::Error;

/// Stops the run after `steps` accepted steps.
fn stop_after(steps: u64) -> StopRequest {
    let seen = Arc::new(AtomicU64::new(0));
    StopRequest(Arc::new(move || seen.fetch_add(1, Ordering::SeqCst) + 1 >= steps))
}

fn read(dir: &std::path::Path, file: &str) -> Vec<u8> {
    std::fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn checkpoint_of(dir: &std::path::Path) -> Checkpoint {
    serde_json::from_slice(&read(dir, checkpoint::FILE)).expect("a checkpoint")
}

/// Run `text` stopped after `at` steps into the directory `name`; its checkpoint. It also
/// writes a checkpoint after every step: writing one changes nothing.
fn stopped(name: &str, text: &str, at: u64) -> (std::path::PathBuf, Checkpoint) {
    let parts = out_dir(name);
    let every_step = common::with(text, "[analysis]", "[analysis]\ncheckpoint_interval = 1e-9");
    let b = run(
        scenario(&every_step),
        "<test>",
        &RunOptions { out: parts.clone(), stop: Some(stop_after(at)), ..Default::default() },
    )
    .unwrap();
    assert_eq!(b.summary.status, Status::Interrupted);
    assert_eq!(b.summary.steps, at);
    let mid = checkpoint_of(&parts);
    (parts, mid)
}

/// Run `text` whole, and again stopped after `at` steps then resumed; compare.
fn stopped_and_resumed_equals_whole(name: &str, text: &str, at: u64) -> Checkpoint {
    let whole = out_dir(&format!("{name}_whole"));
    let a = run(scenario(text), "<test>", &RunOptions { out: whole.clone(), ..Default::default() }).unwrap();
    assert!(a.completed, "{}", a.summary.message);

    let (parts, mid) = stopped(&format!("{name}_parts"), text, at);
    let again: Checkpoint = serde_json::from_str(&serde_json::to_string(&mid).unwrap()).unwrap();
    assert_eq!(again, mid, "the state round-trips exactly");

    let c =
        run(scenario(text), "<test>", &RunOptions { out: parts.clone(), resume: true, ..Default::default() }).unwrap();
    assert!(c.completed, "{}", c.summary.message);
    assert_eq!(c.summary.resumed_from.as_ref().map(|r| r.step), Some(at));
    for file in ["history.csv", "diagnostics.csv"] {
        assert!(read(&whole, file) == read(&parts, file), "{name}: {file} differs after the resume");
    }
    assert_eq!(a.summary.final_values, c.summary.final_values);
    let (end_a, end_c) = (checkpoint_of(&whole), checkpoint_of(&parts));
    assert_eq!(end_a.state, end_c.state);
    assert_eq!(end_a.stepper, end_c.stepper);
    mid
}

fn holds_contact_points(c: &Checkpoint) -> bool {
    c.state.contact.as_ref().is_some_and(|c| !c.records.is_empty())
}

#[test]
fn dominos_resume_bit_identically() {
    let text = common::with(&common::example("dominos.toml"), "duration = 5.0", "duration = 0.1");
    let mid = stopped_and_resumed_equals_whole("checkpoint_dominos", &text, 37);
    assert!(holds_contact_points(&mid), "the checkpoint holds contact points");
    // Standing dominos keep their tangent: shares made at poses of earlier steps are restored
    // from them (`time::kept_tangent`), and the resume still continues bit for bit.
    let t = &mid.stepper.tangent;
    assert!(!t.elements.is_empty(), "the dominos' MEs have shares (the fixed floor's none)");
    let earlier = t.elements.iter().zip(&t.rotations).filter(|(&e, r)| **r != mid.state.motion.rotations[e as usize]);
    assert!(earlier.count() > t.elements.len() / 2, "most shares were made at an earlier step");
}

/// The thesis slope on soft joints sliding (case A, 10 MPa/m): its pattern grows inside the
/// factor and is factorised on an earlier analysis, which the checkpoint carries
/// (`solver::reuse`), so the resumed run orders nothing afresh and continues bit for bit.
/// Stopped late in the run at a step after adoptions since the last analysis whose pattern AMD
/// orders otherwise than the factor's own (the first such of a few candidates): a restore that
/// analysed the factor's own pattern would factorise in another order (checked: it changes the
/// resumed run).
#[test]
fn a_sliding_slope_on_adopted_patterns_resumes_bit_identically() {
    let text = common::with_each(
        &common::example("rock_slope.toml"),
        &[
            ("friction_angle = 26.4", "friction_angle = 10.0\nnormal_stiffness = 1e7\nshear_stiffness = 1e7"),
            ("duration = 1.0", "duration = 0.1"),
        ],
    );
    let adopted = |at: &u64| {
        let f = stopped("checkpoint_slope_probe", &text, *at).1.stepper.factor;
        let order = |p: &SparsityPattern| amd(p).expect("an ordering").forward;
        f.analysed.zip(f.source).is_some_and(|(a, s)| order(&a) != order(&s.pattern))
    };
    let at = [90, 93, 96, 99, 85, 80].into_iter().find(adopted).expect("a checkpoint on an adopted pattern");
    let mid = stopped_and_resumed_equals_whole("checkpoint_slope", &text, at);
    let f = &mid.stepper.factor;
    assert!(f.counts.patterns_adopted > 0 && f.analysed.is_some(), "{:?}", f.counts);
}

#[test]
fn incline_from_its_initial_equilibrium_resumes_bit_identically() {
    let text = common::with(&common::example("incline.toml"), "duration = 1.0", "duration = 0.2");
    let mid = stopped_and_resumed_equals_whole("checkpoint_incline", &text, 23);
    assert!(holds_contact_points(&mid), "the checkpoint holds contact points");
}

/// The cantilever example made a dynamic run of 12 ms on covers of `size`, with `extra` keys.
fn vibrating_cantilever(size: &str, extra: &str) -> String {
    let dynamic = format!("kind = \"dynamic\"{extra}");
    common::with_each(
        &common::example("cantilever.toml"),
        &[
            ("kind = \"static\"", dynamic.as_str()),
            ("duration = 1000.0", "duration = 0.012"),
            ("dt = 1.0", "dt = 0.001"),
            ("size = 0.125", size),
        ],
    )
}

/// A continuum's steps are solved by PCG on an earlier factor: the checkpoint carries that
/// factor's matrix, and the resumed run re-makes it.
#[test]
fn a_vibrating_cantilever_solved_on_a_reused_factor_resumes_bit_identically() {
    let text = vibrating_cantilever("size = 0.5", "");
    let mid = stopped_and_resumed_equals_whole("checkpoint_cantilever", &text, 5);
    let solver = &mid.stepper.factor;
    assert!(solver.source.is_some(), "the checkpoint holds the reused factor's matrix");
    assert!(solver.counts.krylov_solves >= 3, "{:?}", solver.counts);
}

/// The same on multigrid PCG: the checkpoint carries the hierarchy's matrix, and the resumed
/// run rebuilds the same hierarchy.
#[test]
fn a_vibrating_cantilever_solved_by_multigrid_resumes_bit_identically() {
    let text = vibrating_cantilever("size = 0.2", "\nlinear_solver = \"amg\"");
    let mid = stopped_and_resumed_equals_whole("checkpoint_cantilever_amg", &text, 5);
    let solver = &mid.stepper.factor;
    assert!(solver.source.is_some(), "the checkpoint holds the hierarchy's matrix");
    assert!(solver.counts.krylov_solves >= 3, "{:?}", solver.counts);
}

/// A static equilibrium stopped between its Newton iterations: the next one keeps the
/// factor's matrix (modified Newton) after the resume as it does in the whole run.
#[test]
fn a_static_equilibrium_on_a_kept_matrix_resumes_bit_identically() {
    let text = common::example("hanging_bar.toml");
    let mid = stopped_and_resumed_equals_whole("checkpoint_hanging_bar", &text, 2);
    let newton = mid.state.stepper.newton;
    assert_eq!((newton.last.map(|r| r > 0.0), newton.iterations, newton.full), (Some(true), 2, false));
}

/// A checkpoint in version 1's layout: the motion alone in `state`, the contact points and the
/// counters in `stepper`.
fn as_version_1(current: &serde_json::Value) -> serde_json::Value {
    let mut v = current.clone();
    let mut state = v["state"].take();
    let mut stepper = v["stepper"].take();
    stepper["contacts"] = state["contact"].take();
    for (k, x) in state["stepper"].as_object().expect("the stepper's state") {
        stepper[k] = x.clone();
    }
    v["state"] = state["motion"].take();
    v["stepper"] = stepper;
    v["version"] = 1.into();
    v
}

/// Version 1 kept the contact points and counters beside the state; such a file is moved into
/// the current layout and resumes as the current file does.
#[test]
fn a_version_1_checkpoint_resumes_as_the_current_one() {
    let text = common::with(&common::example("incline.toml"), "duration = 1.0", "duration = 0.05");
    let now = out_dir("checkpoint_v2");
    let _ = run(scenario(&text), "<test>", &RunOptions { out: now.clone(), ..Default::default() }).unwrap();
    let current: serde_json::Value = serde_json::from_slice(&read(&now, checkpoint::FILE)).unwrap();
    assert!(current["state"]["contact"]["records"].as_array().is_some_and(|r| !r.is_empty()));
    let mut old = as_version_1(&current);
    let old_dir = out_dir("checkpoint_v1");
    std::fs::create_dir_all(&old_dir).unwrap();
    std::fs::write(old_dir.join(checkpoint::FILE), serde_json::to_vec(&old).unwrap()).unwrap();
    checkpoint::upgrade_v1(&mut old);
    assert_eq!(old, current, "version 1 moved over is the current checkpoint");

    let longer = common::with(&text, "duration = 0.05", "duration = 0.1");
    for dir in [&now, &old_dir] {
        let r = run(scenario(&longer), "<test>", &RunOptions { out: dir.clone(), resume: true, ..Default::default() });
        assert!(r.unwrap().completed);
    }
    assert!(read(&now, "diagnostics.csv") == read(&old_dir, "diagnostics.csv"), "the two resumed runs differ");
    assert_eq!(checkpoint_of(&now), checkpoint_of(&old_dir));
}

#[test]
fn a_changed_scenario_does_not_resume() {
    let text = common::with(&common::example("incline.toml"), "duration = 1.0", "duration = 0.05");
    let dir = out_dir("checkpoint_changed");
    let _ = run(scenario(&text), "<test>", &RunOptions { out: dir.clone(), ..Default::default() }).unwrap();
    // A longer duration may change; a friction angle may not.
    let longer = common::with(&text, "duration = 0.05", "duration = 0.06");
    assert!(
        run(scenario(&longer), "<test>", &RunOptions { out: dir.clone(), resume: true, ..Default::default() })
            .unwrap()
            .completed
    );
    let other = common::with(&longer, "friction_angle = 24.0", "friction_angle = 20.0");
    match run(scenario(&other), "<test>", &RunOptions { out: dir, resume: true, ..Default::default() }) {
        Err(Error::Scenario { problems, .. }) => {
            assert!(problems[0].reason.contains("joint[0].friction_angle"), "{}", problems[0].reason)
        }
        other => panic!("expected an input error, got {other:?}"),
    }
}

/// A checkpoint written before a key existed (here `analysis.settle_dt`) resumes under a
/// scenario that leaves the key at its default, and not under one that sets it otherwise.
#[test]
fn a_checkpoint_without_a_later_key_resumes_at_its_default() {
    let text = common::with(&common::example("incline.toml"), "duration = 1.0", "duration = 0.05");
    let dir = out_dir("checkpoint_older_key");
    let _ = run(scenario(&text), "<test>", &RunOptions { out: dir.clone(), ..Default::default() }).unwrap();
    let mut older: serde_json::Value = serde_json::from_slice(&read(&dir, checkpoint::FILE)).unwrap();
    let analysis = older["scenario"]["analysis"].as_object_mut().unwrap();
    assert!(analysis.remove("settle_dt").is_some(), "the checkpoint records the key");
    std::fs::write(dir.join(checkpoint::FILE), serde_json::to_vec(&older).unwrap()).unwrap();
    let set = common::with(&text, "duration = 0.05", "duration = 0.06\nsettle_dt = 0.5");
    match run(scenario(&set), "<test>", &RunOptions { out: dir.clone(), resume: true, ..Default::default() }) {
        Err(Error::Scenario { problems, .. }) => {
            assert!(problems[0].reason.contains("analysis.settle_dt"), "{}", problems[0].reason)
        }
        other => panic!("expected an input error, got {other:?}"),
    }
    let longer = common::with(&text, "duration = 0.05", "duration = 0.06");
    let r = run(scenario(&longer), "<test>", &RunOptions { out: dir, resume: true, ..Default::default() });
    assert!(r.unwrap().completed);
}

/// `--resume` reads a checkpoint's scenario back to fill the keys it lacks; that must change
/// nothing else: every example's scenario reads back as it was recorded.
#[test]
fn every_example_reads_back_as_recorded() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    names.retain(|n| n.to_string_lossy().ends_with(".toml"));
    assert!(names.len() >= 30, "{} examples", names.len());
    for name in names {
        let s = scenario(&common::example(&name.to_string_lossy()));
        let back: nmm3d_core::scenario::Scenario = serde_json::from_value(serde_json::to_value(&s).unwrap())
            .unwrap_or_else(|e| panic!("{name:?} does not read back: {e}"));
        assert_eq!(checkpoint::comparable(&back), checkpoint::comparable(&s), "{name:?}");
    }
}

/// The same on the block-preconditioned solver: its coarse space turns with the blocks (built
/// at the nodes' positions of the step that made it), so the checkpoint carries those
/// positions and the resumed run rebuilds the same preconditioner.
#[test]
fn dominos_on_the_block_solver_resume_bit_identically() {
    let text = common::with_each(
        &common::example("dominos.toml"),
        &[("duration = 5.0", "duration = 0.1"), ("[analysis]", "[analysis]\nlinear_solver = \"blocks\"")],
    );
    let mid = stopped_and_resumed_equals_whole("checkpoint_dominos_blocks", &text, 37);
    let solver = &mid.stepper.factor;
    assert!(solver.source.is_some() && !solver.geometry.is_empty(), "the preconditioner's positions are kept");
    assert!(holds_contact_points(&mid));
}
