//! Contract: a frame written with the layout its model's first frame made is byte for byte the
//! frame written from scratch, after the blocks moved; a layout made for another model is not
//! used.

mod common;

use common::{example, out_dir, scenario, started, with};
use nmm3d_core::output::frame::write_frame;
use nmm3d_core::output::layout::FrameLayout;
use nmm3d_core::system::System;

#[test]
fn a_frame_on_the_kept_layout_is_the_frame_written_afresh() {
    let text = with(&example("dominos.toml"), "duration = 5.0", "duration = 0.1");
    let (sys, mut state, mut stepper) = started(&text, "dominos");
    let dir = out_dir("frame_layout");
    std::fs::create_dir_all(&dir).unwrap();
    let (first, kept, fresh) = (dir.join("0.vtu"), dir.join("1.vtu"), dir.join("2.vtu"));
    let mut layout = None;
    write_frame(&sys, &state.motion, &first, &mut layout).unwrap();
    while state.motion.step < 30 {
        let _ = stepper.step(&sys, &mut state, f64::INFINITY).unwrap_or_else(|e| panic!("{e}"));
    }
    write_frame(&sys, &state.motion, &kept, &mut layout).unwrap();
    write_frame(&sys, &state.motion, &fresh, &mut None).unwrap();
    let read = |p: &std::path::Path| std::fs::read(p).unwrap();
    assert_eq!(read(&kept), read(&fresh));
    assert_ne!(read(&first), read(&kept), "the blocks moved: the frames differ");

    // A layout of another model (fewer MEs) is replaced, not used.
    let small = System::build(scenario(&example("free_fall.toml")), "free_fall").unwrap_or_else(|e| panic!("{e}"));
    let mut foreign = Some(FrameLayout::of(&small));
    assert!(!foreign.as_ref().unwrap().fits(&sys));
    write_frame(&sys, &state.motion, &first, &mut foreign).unwrap();
    assert_eq!(read(&first), read(&fresh));
}
