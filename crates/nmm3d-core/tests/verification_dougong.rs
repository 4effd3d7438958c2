//! Thesis dougong collapse (`examples/dougong.toml`): a bracket set of crossing timber beams on
//! one corner post tips over and falls apart. Crossing beams meet in crossing-lines
//! (edge-to-edge) contacts as they tumble; the overlap stays below 1 % of the smallest block
//! dimension (0.15 m) at every step.

mod common;

use common::{example, started, with};
use nmm3d_core::simulation::Status;
use nmm3d_geom::contact::Mode;

#[test]
fn dougong_collapses_with_crossing_contacts_and_no_deep_overlap() {
    let text = with(&example("dougong.toml"), "duration = 1.0", "duration = 0.5");
    let (sys, mut state, mut stepper) = started(&text, "dougong");
    let (mut deepest, mut edge_edge) = (0.0f64, 0usize);
    while state.motion.time < 0.5 - 1e-12 {
        let cap = 0.5 - state.motion.time;
        let r = stepper.step(&sys, &mut state, cap).unwrap_or_else(|e| panic!("{e}"));
        deepest = deepest.max(r.max_penetration);
        let c = state.contact.as_ref().expect("contacts");
        edge_edge = edge_edge.max(
            c.records
                .iter()
                .filter(|p| p.mode == Mode::EdgeEdge && p.state != nmm3d_core::contact::ContactState::Open)
                .count(),
        );
    }
    assert!(deepest < 0.01 * 0.15, "overlap {deepest} m");
    assert!(edge_edge > 0, "no closed crossing-lines contact during the collapse");
    // It collapsed: the cap fell (mean displacement of its covers).
    let body = sys.scenario.body.iter().position(|b| b.name == "cap").unwrap();
    let cap = sys.geometry.blocks.iter().position(|b| b.body == body).unwrap();
    let z: Vec<f64> = sys
        .covers
        .covers
        .iter()
        .enumerate()
        .filter(|(_, c)| c.block == cap)
        .map(|(i, _)| state.motion.u[i].z)
        .collect();
    let fall = -z.iter().sum::<f64>() / z.len() as f64;
    assert!(fall > 0.2, "the cap fell only {fall} m");
}

#[test]
fn dougong_on_hex8_covers_keeps_its_crossing_contacts_shallow() {
    // The same collapse on hex8 covers, whose beams bend between their corners: a crossing-lines
    // point's gap measured on the beam's straight edges did not close when its spring pushed the
    // material points apart, and the beams passed into each other (the run failed at 0.14 s).
    let text = with(
        &with(&example("dougong.toml"), "duration = 1.0", "duration = 0.3"),
        "pattern = \"tet6\"",
        "pattern = \"hex8\"",
    );
    let out = common::run_ok(&text, "dougong_hex8");
    assert_eq!(out.summary.status, Status::Completed);
    let pen = out.summary.max_penetration;
    assert!(pen < 0.01 * 0.15, "overlap {pen} m");
    assert_eq!(out.summary.penalty_raises, 0, "no overlap deep enough to raise the penalties");
}
