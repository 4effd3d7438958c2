//! Contract: every rejected trial is in `cuts.csv` with its reason and the blocks responsible,
//! and `summary.json` → `step_diagnostics` counts them and bins the accepted steps.

mod common;

use common::{example, run_ok, with};

/// A cube thrown down past a fixed one far away: its first steps are cut for moving too far,
/// and only it is named.
#[test]
fn a_falling_cube_is_named_in_every_displacement_cut() {
    let fixed = "[[body]]\nname = \"pillar\"\nmaterial = \"rock\"\nfixed = true\n\
                 shape = { box = { min = [5.0, 0.0, -20.0], max = [6.0, 1.0, 1.0] } }\n\n[[body]]\nname = \"cube\"";
    let text = with(&example("free_fall.toml"), "[[body]]\nname = \"cube\"", fixed);
    let text = with(&text, "velocity = [0.0, 0.0, 0.0]", "velocity = [0.0, 0.0, -20.0]");
    let out = run_ok(&text, "step_diagnostics_fall");
    let s = &out.summary;
    let cuts = s.step_cuts;
    assert!(cuts >= 1, "the throw must cut a step: {s:?}");
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("step_diagnostics_fall");
    let csv = std::fs::read_to_string(dir.join("cuts.csv")).unwrap();
    // The cube's id in blocks.csv (moving blocks are numbered first).
    let blocks = std::fs::read_to_string(dir.join("blocks.csv")).unwrap();
    let cube: usize = blocks
        .lines()
        .find(|l| l.split(',').nth(1) == Some("cube"))
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("step,time,dt,reason,value,blocks"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len() as u64, cuts);
    for r in &rows {
        assert_eq!(r[3], "displacement_ratio", "{r:?}");
        assert!(r[4].parse::<f64>().unwrap() > 1.0, "a ratio beyond 1 was cut: {r:?}");
        assert_eq!(r[5], cube.to_string(), "only the falling cube is responsible: {r:?}");
    }

    let d = &s.step_diagnostics;
    assert_eq!(d.cuts_by_reason.get("displacement_ratio"), Some(&cuts));
    assert_eq!(d.blocks_most_cut[0].block, cube);
    assert_eq!(d.blocks_most_cut[0].body, "cube");
    assert_eq!(d.blocks_most_cut[0].cuts, cuts);
    let bins = &d.dt_histogram;
    let steps: u64 = bins.iter().map(|b| b.steps).sum();
    assert_eq!(steps, s.steps, "every accepted step in one bin");
    assert!(bins[..bins.len() - 1].iter().any(|b| b.steps > 0), "some steps below the requested Δt");
}

/// Dominos allowed two open–close iterations a step: their first trials are cut unsettled
/// because a sliding point's friction still turns while no point changes state (until the
/// turn named its point, such cuts had value 0 and no block). Every such cut names a block.
#[test]
fn an_unsettled_cut_names_the_blocks_even_when_only_friction_turned() {
    let text = with(&example("dominos.toml"), "duration = 5.0", "duration = 0.00203\nmax_open_close = 2");
    let out = run_ok(&text, "step_diagnostics_unsettled");
    assert!(out.summary.step_cuts >= 2, "{:?}", out.summary);
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("step_diagnostics_unsettled");
    let csv = std::fs::read_to_string(dir.join("cuts.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert!(rows.iter().filter(|r| r[3] == "open_close_unsettled").count() >= 2, "{csv}");
    for r in rows.iter().filter(|r| r[3] == "open_close_unsettled") {
        assert!(r[4].parse::<f64>().unwrap() >= 1.0, "an unsettled iteration changed something: {r:?}");
        assert!(!r[5].is_empty(), "no block named: {r:?}");
    }
}
