"""Every example scenario runs; one key number each is checked against its reference.

Heavy examples run coarsened through overrides (the full-size figures are in
docs/verification.md, produced by bench/verification.py).
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES, ROOT
from nmm3d import analytic, roof_wedge
from nmm3d.wedge import wedge

CASES = {
    "free_fall.toml": [],
    "spinning_block.toml": ["analysis.duration=0.25"],
    "bar_patch.toml": [],
    "hanging_bar.toml": [],
    "cantilever.toml": [],
    "cantilever_self_weight.toml": [],
    "plate_self_weight.toml": ["cover.size=0.1"],
    "plate_large_deflection.toml": ["cover.size=0.1"],
    "large_block.toml": [],
    # Rock masses: the blocks are checked below; a short run with contact proves the scenario
    # runs end to end (the full runs take minutes).
    "tunnel_key_blocks.toml": ["analysis.duration=0.002"],
    "tunnel_key_blocks_bolted.toml": ["analysis.duration=0.002"],
    "rock_slope.toml": ["analysis.duration=0.002"],
    "rock_slope_confined.toml": ["analysis.duration=0.002"],
    "rock_slope_bollards.toml": ["analysis.duration=0.002"],
    # Contact: short runs (the full ones are in docs/verification.md).
    "incline.toml": ["analysis.duration=0.3"],
    "roof_wedge.toml": ["analysis.duration=0.1"],
    "roof_wedge_prism.toml": ["analysis.duration=0.1"],
    "roof_wedge_pyramid.toml": ["analysis.duration=0.1"],
    "drop_test.toml": [],
    "damped_drop.toml": [],
    "block_on_joint.toml": [],
    "eccentric_footing.toml": [],
    "tetrahedral_wedge.toml": ["analysis.duration=0.2"],
    "block_tower.toml": ["analysis.max_steps=1000"],
    "dominos.toml": ["analysis.duration=0.3"],
    "dougong.toml": ["analysis.duration=0.05"],
    "two_wedges.toml": ["analysis.duration=0.05"],
    "goodman_tunnel.toml": ["analysis.duration=0.06"],
    "newmark_sliding_block.toml": [],
    "incline_water.toml": [],
    "bolted_block.toml": [],
    "grouted_bolt.toml": [],
    "grouted_dowel.toml": [],
    "sliding_wedge.toml": [],
    # Staged analyses (tests/test_stages.py checks them against closed forms).
    "staged_incline.toml": ["stage.bolt.duration=0.1"],
    "staged_tunnel_lame.toml": ["cover.size=0.2"],
    "tunnel_key_blocks_staged.toml": ["stage.in-situ.duration=0.002", "stage.excavate.duration=0.002"],
}


def test_every_example_is_covered():
    assert sorted(p.name for p in EXAMPLES.glob("*.toml")) == sorted(CASES)


@pytest.mark.parametrize("path", sorted([*EXAMPLES.glob("*.toml"), *(ROOT / "bench" / "peers").glob("*.toml")]),
                         ids=lambda p: p.name)
def test_scenario_files_are_toml_1_0(path):
    # nmm3d's parser also takes TOML 1.1 (an inline table over several lines); Python's
    # tomllib, editors and other tools a user copies an example into take 1.0 only.
    tomllib.loads(path.read_text())


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = {}
    base = tmp_path_factory.mktemp("examples")
    for name, overrides in CASES.items():
        out[name] = nmm3d.load(EXAMPLES / name, overrides).run(out=base / name.removesuffix(".toml"))
    return out


def final(results, name, key):
    r = results[name]
    assert r.completed, r.summary["message"]
    return r.summary["final"][key]


def test_free_fall(results):
    u, _ = analytic.ballistic([0, 0, 0], [0, 0, -10.0], 1.0)
    assert final(results, "free_fall.toml", "cube.displacement.z") == pytest.approx(u[2], rel=1e-6)


def test_spinning_block_keeps_volume(results):
    assert final(results, "spinning_block.toml", "cube.volume.value") == pytest.approx(1.0, abs=1e-3)


def test_bar_patch(results):
    stretch = final(results, "bar_patch.toml", "end.displacement.x") - final(results, "bar_patch.toml", "start.displacement.x")
    assert stretch == pytest.approx(analytic.bar_end_load(1e6, 10.0, 10e9), rel=1e-6)
    assert final(results, "bar_patch.toml", "bar.stress.xx") == pytest.approx(1e6, rel=1e-6)


def test_hanging_bar(results):
    stretch = final(results, "hanging_bar.toml", "top.displacement.z") - final(results, "hanging_bar.toml", "bottom.displacement.z")
    assert stretch == pytest.approx(analytic.hanging_bar(2500.0, 10.0, 10.0, 10e9), rel=0.01)


def test_full_size_examples_meet_their_expectations(results):
    # Each example's [[expect]] tables state its answer; the ones run here unchanged must meet them.
    for name, overrides in CASES.items():
        if overrides or not results[name].summary["checks"]:
            continue
        for c in results[name].summary["checks"]:
            assert c["passed"], (name, c)


def test_the_large_block_is_solved_by_multigrid(results):
    summary = results["large_block.toml"].summary
    assert (summary["linear_solver"], summary["factorizations"]) == ("amg", 1)
    assert 0 < summary["multigrid_iterations"] <= 40 * summary["steps"]


def test_examples_with_a_closed_form_state_it():
    for name in ("free_fall.toml", "bar_patch.toml", "hanging_bar.toml", "cantilever.toml",
                 "cantilever_self_weight.toml", "incline.toml", "roof_wedge.toml", "drop_test.toml", "damped_drop.toml",
                 "block_on_joint.toml", "tetrahedral_wedge.toml", "newmark_sliding_block.toml",
                 "incline_water.toml", "bolted_block.toml", "grouted_bolt.toml", "grouted_dowel.toml",
                 "two_wedges.toml", "sliding_wedge.toml", "eccentric_footing.toml"):
        assert nmm3d.load(EXAMPLES / name).to_dict().get("expect"), name


def test_flagship_cantilever_is_within_one_percent(results):
    tip = final(results, "cantilever.toml", "tip.displacement.z")
    assert tip == pytest.approx(-0.04009, rel=0.01)
    assert abs(final(results, "cantilever.toml", "tip.displacement.y")) < 1e-9
    tip = final(results, "cantilever_self_weight.toml", "tip.displacement.z")
    assert tip == pytest.approx(-0.03762, rel=0.01)


def test_tet6_cantilever_locks_and_drifts_within_a_bound(tmp_path):
    # tet6 splits every cell along one diagonal: stiff in bending and not mirror-symmetric about
    # the beam's mid-plane, so a vertical load bends it a little sideways (documented in the
    # example's header); hex8 (the example's pattern) is symmetric and does not drift.
    r = nmm3d.load(EXAMPLES / "cantilever.toml", ["cover.pattern=tet6", "cover.size=0.25"]).run(out=tmp_path / "t")
    z, y = r.summary["final"]["tip.displacement.z"], r.summary["final"]["tip.displacement.y"]
    assert 0.75 * 0.04009 < -z < 0.85 * 0.04009
    assert 1e-4 < abs(y) < 0.1 * abs(z)


def test_plates(results):
    w = -final(results, "plate_self_weight.toml", "centre.displacement.z")
    assert 0.6 * 5.61e-3 < w < 5.61e-3
    w = -final(results, "plate_large_deflection.toml", "centre.displacement.z")
    assert 0.25 < w < 0.42


def test_rock_mass_examples_match_the_thesis_description(tmp_path):
    tunnel = nmm3d.load(EXAMPLES / "tunnel_key_blocks.toml").write_blocks(tmp_path / "t")
    # Thesis: 277.45 m³ of rock and 25.65 m³ excavated.
    assert tunnel["total_volume"] == pytest.approx(277.45, rel=0.01)
    assert tunnel["excavated_volume"] == pytest.approx(25.65, rel=0.02)
    assert tunnel["non_convex_blocks"] > 0
    b = nmm3d.load(EXAMPLES / "rock_slope.toml").blocks()
    v = b["volume"][b["body"] == "layer"]
    # Thesis: 45 potentially sliding blocks, mean 1.22995 m³, smallest 0.4155 m³, largest 2.7687 m³.
    assert len(v) == 45
    assert v.mean() == pytest.approx(1.22995, rel=0.01)
    assert 0.4 <= v.min() <= 0.4155
    assert v.max() == pytest.approx(2.7687, rel=0.03)


def test_thesis_tunnel_has_a_roof_and_a_side_wall_key_block():
    # Thesis Part 5: two key blocks, #11 in the roof and #12 in the side wall; both held at the
    # thesis's φ = 59°, and the wall block the less stable one (critical angles 17.6° > 11.1°).
    kb = nmm3d.keyblocks(EXAMPLES / "tunnel_key_blocks.toml")
    key = kb.key_blocks()
    assert len(key) == 2, [(b.id, b.mode.mode) for b in key]
    half_width, springline = 0.9, 0.1  # the horseshoe: 1.8 m wide, crown arc from z = 0.1 m
    roof = [b for b in key if abs(b.centroid[1]) < half_width and b.centroid[2] > springline]
    wall = [b for b in key if b.centroid[2] < springline]
    assert len(roof) == 1 and len(wall) == 1, [(b.id, b.centroid) for b in key]
    assert wall[0].mode.critical_friction_angle > roof[0].mode.critical_friction_angle > 5.0
    assert wall[0].mode.critical_friction_angle < 59.0
    assert 0.01 < wall[0].volume < roof[0].volume < 0.5


def test_case_b_confines_the_case_a_layer_without_cutting_the_walls():
    """Case B is case A's layer (the same blocks) between two fixed walls the joints do not cut."""
    a, b = (nmm3d.load(EXAMPLES / f).blocks() for f in ("rock_slope.toml", "rock_slope_confined.toml"))
    la, lb = a["body"] == "layer", b["body"] == "layer"
    assert la.sum() == lb.sum() and sorted(a["volume"][la]) == pytest.approx(sorted(b["volume"][lb]), rel=1e-9)
    walls = np.isin(b["body"], ["wall_south", "wall_north"])
    assert walls.sum() == 2 and b["fixed"][walls].all()
    assert nmm3d.load(EXAMPLES / "rock_slope_confined.toml").to_dict()["joint"][0]["friction_angle"] == 10.0


def test_rock_mass_examples_run(results):
    for name in ("tunnel_key_blocks.toml", "rock_slope.toml", "rock_slope_confined.toml"):
        assert results[name].completed, results[name].summary["message"]
        assert results[name].summary["blocks"] > 20


def test_incline_slides_as_the_closed_form(results):
    u = [final(results, "incline.toml", f"cube.displacement.{c}") for c in "xyz"]
    a = math.radians(30.0)
    exact = 0.5 * 10.0 * (math.sin(a) - math.tan(math.radians(24.0)) * math.cos(a)) * 0.3**2
    assert math.hypot(*u) == pytest.approx(exact, rel=0.02)


def test_roof_wedge_settles_and_stays(results):
    # W / (k ΣA): weight 11.547 kN, k = 10 MPa/m, three faces of 1.1547 m².
    settle = 2000.0 * 10.0 * math.sqrt(3.0) / 3.0 / (10.0e6 * 3.0 * 2.0 / math.sqrt(3.0))
    assert -final(results, "roof_wedge.toml", "wedge.displacement.z") == pytest.approx(settle, rel=0.05)


@pytest.mark.parametrize("name, shape", [("roof_wedge_prism.toml", "prism"), ("roof_wedge_pyramid.toml", "pyramid")])
def test_multi_face_roof_wedges_settle_as_the_relaxation_closed_form(results, name, shape):
    # Rigid wedge on springs k_n = k_s = 10 MPa/m: δ = W / (k ΣA) (nmm3d.roof_wedge).
    wedge = roof_wedge.prism(1.0, math.sqrt(3.0), 4.0, 2000.0, 10.0, 5e4) if shape == "prism" else \
        roof_wedge.pyramid(1.0, math.sqrt(3.0), 2000.0, 10.0, 5e4)
    assert -final(results, name, "wedge.displacement.z") == pytest.approx(wedge.settlement(1e7, 1e7), rel=0.03)


def test_drop_test_penetration(results):
    z = results["drop_test.toml"].history["cube.displacement.z"]
    assert float(-z.min() - 1e-3) == pytest.approx(7.096e-3, rel=0.05)


def test_tetrahedral_wedge_accelerates_as_the_vector_method(results):
    u = [final(results, "tetrahedral_wedge.toml", f"wedge.displacement.{c}") for c in "xyz"]
    ref = wedge((50.0, 130.0), (50.0, 230.0), 20.0, g=9.81)
    assert 2.0 * math.hypot(*u) / 0.2**2 == pytest.approx(ref.acceleration, rel=0.03)


def test_block_tower_does_not_drift(results):
    drift = max(abs(final(results, "block_tower.toml", f"cube{k}.displacement.{c}")) for k in range(3) for c in "xy")
    assert drift < 1e-4


def test_dominos_start_to_topple(results):
    # The end dominos tip towards the others (the full run is a Rust verification test).
    assert final(results, "dominos.toml", "d0.rotation.y") > 0.1
    assert final(results, "dominos.toml", "d7.rotation.y") < -0.1


def test_dougong_starts_to_tip(results):
    # Unsupported but for one corner post, the set starts falling (full run: Rust verification).
    assert final(results, "dougong.toml", "cap.displacement.z") < -1e-3


def test_goodman_tunnel_roof_key_block_leaves_and_the_wall_block_stays(results):
    # Block theory: the roof block slides at FS 0.33, the wall block holds at FS 1.59 (the full
    # 0.3 s run meets the example's [[expect]]: roof block 0.18 m down, wall block 6 µm).
    assert final(results, "goodman_tunnel.toml", "roof_block.displacement.z") < -3e-3
    assert max(abs(final(results, "goodman_tunnel.toml", f"wall_block.displacement.{c}")) for c in "xyz") < 1e-4


def test_block_on_joint_closes_and_shears_as_the_closed_form(results):
    assert -final(results, "block_on_joint.toml", "base.displacement.z") == pytest.approx(25_000.0 / 1.0e8, rel=0.002)
    assert final(results, "block_on_joint.toml", "base.displacement.x") == pytest.approx(2_500.0 / 5.0e7, rel=0.02)
