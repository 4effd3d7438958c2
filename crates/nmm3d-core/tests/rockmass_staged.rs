//! Staged excavation's rock mass (`Geometry::staged`): the thesis tunnel cut with its opening's
//! rock kept as plug blocks. The rock blocks are the unstaged model's, numbered alike; the
//! plugs fill the opening exactly (Σ plug volumes = the unstaged excavated volume, 1e-9) and
//! come after the rock; `without` removes them and maps the kept blocks' indices.

use nmm3d_core::model::Geometry;

fn tunnel() -> nmm3d_core::scenario::Scenario {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/tunnel_key_blocks_staged.toml");
    nmm3d_core::input::load_file(&path, &[]).expect("the example loads")
}

#[test]
fn the_plug_fills_the_opening_and_the_rock_is_the_unstaged_models() {
    let s = tunnel();
    let open = Geometry::from_scenario(&s);
    let staged = Geometry::staged(&s);
    let rock: Vec<_> = staged.blocks.iter().filter(|b| b.excavation.is_none()).collect();
    assert_eq!(rock.len(), open.blocks.len());
    for (a, b) in rock.iter().zip(&open.blocks) {
        assert!((a.volume - b.volume).abs() <= 1e-12 * b.volume, "{} {}", a.volume, b.volume);
        assert!((a.centroid - b.centroid).norm() <= 1e-12);
    }
    let plug: f64 = staged.blocks.iter().filter(|b| b.excavation == Some(0)).map(|b| b.volume).sum();
    let excavated = open.report.excavated_volume;
    assert!(excavated > 20.0 && (plug - excavated).abs() <= 1e-9 * excavated, "{plug} {excavated}");
    // Plugs after the rock: the first rock.len() blocks are the rock.
    assert!(staged.blocks[..rock.len()].iter().all(|b| b.excavation.is_none()));
    let (after, map) = staged.without(&[true]);
    assert_eq!(after.blocks.len(), rock.len());
    assert!(map[..rock.len()].iter().enumerate().all(|(i, m)| *m == Some(i)));
    assert!(map[rock.len()..].iter().all(Option::is_none));
}

#[test]
fn a_scenario_without_stages_keeps_no_plug() {
    let mut s = tunnel();
    s.stage.clear();
    assert!(Geometry::staged(&s).blocks.iter().all(|b| b.excavation.is_none()));
}
