"""Anchored rock bolts ([[bolt]]): a block hung by one bolt (static extension W / k), pretension,
yield (the block then comes down at (W − F_y) / m) and rupture (free fall), against closed forms.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import nmm3d
from nmm3d import analytic

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "bolted_block.toml"
W = 2500.0 * 9.81 * 1.0  # the cube's weight [N]
K = 1.0e7                # the bolt's stiffness [N/m]
DYNAMIC = ['analysis.kind="dynamic"', "analysis.dt=0.001", "analysis.duration=0.3",
           "analysis.max_displacement_ratio=0.01"]


def run(tmp_path, *overrides) -> nmm3d.Result:
    return nmm3d.load(EXAMPLE, overrides).run(out=tmp_path / "run")


def test_a_hanging_block_stretches_its_bolt_by_w_over_k(tmp_path):
    r = run(tmp_path)
    assert r.status == "completed"
    assert r.history["b1.elongation.value"][-1] == pytest.approx(W / K, rel=1e-6)
    assert r.history["b1.axial_force.value"][-1] == pytest.approx(W, rel=1e-6)


def test_pretension_is_taken_off_the_stretch(tmp_path):
    """Tension P₀ + k δ carries W: δ = (W − P₀) / k."""
    r = run(tmp_path, "bolt.b1.pretension=1e4")
    assert r.history["b1.elongation.value"][-1] == pytest.approx((W - 1e4) / K, rel=1e-6)
    assert r.history["b1.axial_force.value"][-1] == pytest.approx(W, rel=1e-6)


def test_a_bolt_that_yields_lets_the_block_down_at_the_closed_form_rate(tmp_path):
    fy = 2.0e4
    r = run(tmp_path, *DYNAMIC, f"bolt.b1.yield_force={fy}")
    t, v = r.history["time"], r.history["block.velocity.z"]
    late = t > 0.05  # yielded within the first millimetres
    slope = np.polyfit(t[late], v[late], 1)[0]
    assert slope == pytest.approx(-(W - fy) / 2500.0, rel=0.01)
    assert np.allclose(r.history["b1.axial_force.value"][late], fy, rtol=1e-9)


def test_a_bolt_that_breaks_lets_the_block_fall_freely(tmp_path):
    r = run(tmp_path, *DYNAMIC, "bolt.b1.rupture_elongation=1e-3")
    t, v = r.history["time"], r.history["block.velocity.z"]
    broken = r.history["b1.axial_force.value"] == 0.0
    assert broken[-1] and r.history["b1.elongation.value"][-1] > 0.1
    late = t > 0.05
    assert np.polyfit(t[late], v[late], 1)[0] == pytest.approx(-9.81, rel=1e-3)


def test_a_bolt_outside_the_rock_is_named(tmp_path):
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1.anchor"):
        run(tmp_path, "bolt.b1.anchor=[0.5, 0.5, 5.0]")


def test_bolt_inputs_are_checked():
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1.stiffness"):
        nmm3d.load(EXAMPLE, ["bolt.b1.stiffness=0"])
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1.pretension"):
        nmm3d.load(EXAMPLE, ["bolt.b1.yield_force=1e3", "bolt.b1.pretension=2e3"])


@pytest.mark.parametrize("fy", [2e3, 1e4])
def test_key_block_held_by_a_bolt_on_a_plane_is_the_passive_support_closed_form(fy):
    """The incline's cube (W = 25 kN, ψ = 30°, φ = 24°) with a bolt from its centre, pointing
    upslope and into the rock at 45°: its yield force F_y adds F_y/√2 to the normal force and
    F_y/√2 against the sliding: FS = ((W cos ψ + F_y/√2) tan φ + F_y/√2) / (W sin ψ)."""
    import math

    incline = EXAMPLE.parent / "incline.toml"
    d = nmm3d.load(incline).to_dict()
    psi, phi, w = math.radians(30.0), math.radians(24.0), 2500.0 * 10.0
    n, s = np.array([math.sin(psi), 0.0, math.cos(psi)]), np.array([math.cos(psi), 0.0, -math.sin(psi)])
    head = 0.5 * n  # the cube's centre
    axis = -(s + n) / math.sqrt(2.0)
    d["bolt"] = [{"name": "b", "head": head.tolist(), "anchor": (head + 2.0 * axis).tolist(), "stiffness": 1e8,
                  "yield_force": fy}]
    [b] = nmm3d.keyblocks(nmm3d.Scenario.from_dict(d)).key_blocks()
    exact = ((w * math.cos(psi) + fy / math.sqrt(2)) * math.tan(phi) + fy / math.sqrt(2)) / (w * math.sin(psi))
    assert b.mode.mode == "sliding_one_plane"
    assert b.mode.factor_of_safety == pytest.approx(exact, abs=1e-9)


def test_key_block_falling_on_its_bolt_has_the_support_over_the_weight():
    for fy in (1e4, 5e4):
        [b] = nmm3d.keyblocks(nmm3d.load(EXAMPLE, [f"bolt.b1.yield_force={fy}"])).blocks
        assert b.mode.mode == "falling" and b.mode.factor_of_safety == pytest.approx(fy / W, rel=1e-12)


def goodman_bare() -> dict:
    """Goodman's tunnel as a plain run (no study, no expectations)."""
    d = nmm3d.load(EXAMPLE.parent / "goodman_tunnel.toml").to_dict()
    d.pop("study", None)
    d["expect"] = []
    return d


def goodman_bolted(yield_force: float) -> nmm3d.Scenario:
    """Goodman's tunnel with a 1 m × 1 m pattern of 3 m roof bolts (5 along x, 5 across y)."""
    d = goodman_bare()
    d["bolt_pattern"] = [{"name": "roof", "start": [-2.0, -2.0, 0.0], "along": [1.0, 0.0, 0.0],
                          "across": [0.0, 1.0, 0.0], "count": [5, 5], "direction": [0.0, 0.0, 1.0],
                          "length": 3.0, "stiffness": 5e7, "yield_force": yield_force}]
    return nmm3d.Scenario.from_dict(d)


def test_a_bolt_pattern_is_spelled_out_as_bolts():
    d = goodman_bolted(2e4).to_dict()
    assert "bolt_pattern" not in d and len(d["bolt"]) == 25
    b = next(b for b in d["bolt"] if b["name"] == "roof_4_2")
    assert b["head"] == pytest.approx([2.0, 0.0, 0.05]) and b["anchor"] == pytest.approx([2.0, 0.0, 3.0])


def test_the_goodman_roof_key_block_held_by_its_bolt_pattern(tmp_path):
    """Block theory designs it: the roof block (FS 0.33 bare) reaches FS ≥ 1.5 with the bolts
    whose heads it holds; the run agrees: bare it slides out, bolted it stays."""
    bare = next(b for b in nmm3d.keyblocks(EXAMPLE.parent / "goodman_tunnel.toml").blocks if b.joint_pyramid == "101xxx")
    bolted = next(b for b in nmm3d.keyblocks(goodman_bolted(3e4)).blocks if b.joint_pyramid == "101xxx")
    assert bare.mode.factor_of_safety < 0.5 and bolted.mode.factor_of_safety >= 1.5
    run = goodman_bolted(3e4).with_overrides("analysis.duration=0.06").run(out=tmp_path / "bolted")
    free = nmm3d.Scenario.from_dict(goodman_bare()).with_overrides("analysis.duration=0.06").run(out=tmp_path / "bare")
    # Bare it slides out (8.6 mm in 0.06 s); bolted it hangs on the bolts' elastic stretch
    # (≈ 0.5 mm, about which it swings as a suddenly loaded spring does).
    moved = [abs(r.history["roof_block.displacement.z"][-1]) for r in (free, run)]
    assert moved[1] < 0.1 * moved[0], moved
    forces = [run.history[f"roof_{i}_{j}.axial_force.value"][-1] for i in range(5) for j in range(5)]
    assert 0.0 < max(forces) < 3e4  # the bolts in the block carry it, none at yield


# Fully grouted bolts (grouted = true): reinforcement across each joint they cross.
GROUTED = EXAMPLE.parent / "grouted_bolt.toml"
DOWEL = EXAMPLE.parent / "grouted_dowel.toml"
EA, KB = 9.82e7, 1.0e9  # the examples' bar [N] and grout [Pa]


def bonded_side(length: float) -> float:
    """A bar on an elastic shear foundation pulled at its end (Farmer 1975)."""
    return analytic.grouted_side_stiffness(EA, KB, length)


def test_a_grouted_bolt_across_a_joint_stretches_by_w_over_its_two_bonded_sides(tmp_path):
    r = nmm3d.load(GROUTED).run(out=tmp_path / "run")
    k1, k2 = bonded_side(0.95), bonded_side(0.5)
    assert r.history["rebar.axial_force.value"][-1] == pytest.approx(W, rel=1e-6)
    assert r.history["rebar.elongation.value"][-1] == pytest.approx(W * (1 / k1 + 1 / k2), rel=1e-6)
    # Deeper in the roof it is stiffer: the semi-infinite bar's sqrt(EA k_b) is the bound.
    deep = nmm3d.load(GROUTED, ["bolt.rebar.anchor=[0.5, 0.5, 0.999]"]).run(out=tmp_path / "deep")
    assert deep.history["rebar.elongation.value"][-1] == pytest.approx(W * (1 / k1 + 1 / bonded_side(0.999)), rel=1e-6)


def test_a_grouted_bolt_pulls_out_at_its_bond_strength_times_its_shorter_side(tmp_path):
    """Bond strength 2e4 N/m over the 0.5 m in the roof: 1e4 N < W, so the cube comes down at
    (W − 1e4) / m; over 0.95 m at 3e4 N/m (the cube's side is shorter then: 28.5 kN > W) it holds."""
    r = nmm3d.load(GROUTED, [*DYNAMIC, "bolt.rebar.bond_strength=2e4"]).run(out=tmp_path / "out")
    t, v = r.history["time"], r.history["block.velocity.z"]
    late = t > 0.05
    assert np.polyfit(t[late], v[late], 1)[0] == pytest.approx(-(W - 1e4) / 2500.0, rel=0.01)
    assert np.allclose(r.history["rebar.axial_force.value"][late], 1e4, rtol=1e-9)
    held = nmm3d.load(GROUTED, [*DYNAMIC, "bolt.rebar.bond_strength=3e4", "bolt.rebar.anchor=[0.5, 0.5, 0.999]"]
                      ).run(out=tmp_path / "held")
    assert abs(held.history["block.displacement.z"][-1]) < 1e-3


def dowel_stiffness(kf: float = 1e9, d: float = 0.025) -> float:
    """The examples' rebar (EI = EA d² / 16) in a foundation k_f: Hetényi's k_f / (4λ)."""
    return analytic.dowel_stiffness(kf, EA * d * d / 16.0)


def test_a_grouted_bolt_holds_a_block_on_a_smooth_joint_by_dowel_action(tmp_path):
    import math

    r = nmm3d.load(DOWEL).run(out=tmp_path / "run")
    drive = 2500.0 * 9.81 * math.sin(math.radians(20.0))
    assert r.history["dowel.shear_force.value"][-1] == pytest.approx(drive, rel=1e-4)
    assert r.history["block.displacement.x"][-1] == pytest.approx(drive / dowel_stiffness(), rel=0.01)
    # A cable (no foundation modulus, no dowel) does not hold it.
    cable = nmm3d.load(DOWEL, [*DYNAMIC]).to_dict()
    for key in ("foundation_modulus", "diameter"):
        cable["bolt"][0].pop(key)
    c = nmm3d.Scenario.from_dict(cable).run(out=tmp_path / "cable")
    assert c.history["block.displacement.x"][-1] > 0.05


def test_a_dowel_past_its_shear_capacity_lets_the_block_slide(tmp_path):
    import math

    cap = 5e3
    r = nmm3d.load(DOWEL, [*DYNAMIC, f"bolt.dowel.shear_capacity={cap}"]).run(out=tmp_path / "run")
    t, v = r.history["time"], r.history["block.velocity.x"]
    late = t > 0.05
    drive = 2500.0 * 9.81 * math.sin(math.radians(20.0))
    assert np.polyfit(t[late], v[late], 1)[0] == pytest.approx((drive - cap) / 2500.0, rel=0.02)
    assert np.allclose(r.history["dowel.shear_force.value"][late], cap, rtol=1e-6)


def test_bolt_frames_draw_each_bolt_with_its_forces(tmp_path):
    """A grouted bolt is drawn through its ends and the joint it crosses; VTK, PyVista and meshio
    read the frame."""
    import meshio
    import pyvista as pv

    r = nmm3d.load(GROUTED).run(out=tmp_path / "run")
    frames = sorted((tmp_path / "run" / "frames").glob("bolts_*.vtu"))
    assert frames and "bolts_" in (tmp_path / "run" / "result.pvd").read_text()
    m = pv.read(frames[-1])
    assert m.n_points == 3 and m.n_cells == 2
    assert m.point_data["axial_force"][1] == pytest.approx(W, rel=1e-6)
    assert m.points[1] == pytest.approx([0.5, 0.5, -r.history["rebar.elongation.value"][-1]], abs=1e-6)
    mesh = meshio.read(frames[-1])
    assert mesh.cells[0].type == "line" and len(mesh.point_data["shear_force"]) == 3


def test_grouted_bolt_inputs_are_checked():
    with pytest.raises(nmm3d.ScenarioError, match="bolt.rebar.axial_rigidity"):
        nmm3d.load(GROUTED, ["bolt.rebar.axial_rigidity=0"])
    with pytest.raises(nmm3d.ScenarioError, match="bolt.rebar.stiffness"):
        nmm3d.load(GROUTED, ["bolt.rebar.stiffness=1e7"])
    with pytest.raises(nmm3d.ScenarioError, match="bolt.rebar.diameter"):
        nmm3d.load(GROUTED, ["bolt.rebar.foundation_modulus=1e9"])
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1.bond_stiffness"):
        nmm3d.load(EXAMPLE, ["bolt.b1.bond_stiffness=1e9"])
    with pytest.raises(nmm3d.ScenarioError, match="unknown field"):
        nmm3d.load(GROUTED, ["bolt.rebar.bond_strenght=1e4"])


def test_key_block_held_by_a_grouted_bolt_counts_its_pull_out_capacity():
    """The hanging cube: its grouted bar holds it with min(F_y, τ × shorter side) = 2e4 × 0.5
    (the joint is found to the blocks' containment tolerance, 1e-9 of the model's diagonal)."""
    [b] = nmm3d.keyblocks(nmm3d.load(GROUTED, ["bolt.rebar.bond_strength=2e4"])).blocks
    assert b.mode.mode == "falling" and b.mode.factor_of_safety == pytest.approx(1e4 / W, rel=1e-7)
    [b] = nmm3d.keyblocks(GROUTED).blocks
    assert b.mode.factor_of_safety == pytest.approx(2.45e5 / W, rel=1e-9)


def test_the_thesis_tunnel_bolt_pattern_is_the_one_the_key_block_module_designs():
    """examples/tunnel_key_blocks_bolted.toml carries what design_bolt_pattern gives for its two
    faces: the widest spacing at which both key blocks (FS 0.34 and 0.26 bare at φ = 8°) reach 1.5."""
    bolted = nmm3d.load(EXAMPLE.parent / "tunnel_key_blocks_bolted.toml")
    d = bolted.to_dict()
    bars = {k: v for k, v in d["bolt"][0].items() if k not in ("name", "head", "anchor")}
    bars.update(length=2.5)
    faces = [dict(name="roof", start=[0.2, -0.8, 0.6], along=[7.6, 0.0, 0.0], across=[0.0, 1.6, 0.0],
                  direction=[0.0, 0.0, 1.0], **bars),
             dict(name="wall", start=[0.2, -0.5, -0.55], along=[7.6, 0.0, 0.0], across=[0.0, 0.0, 1.0],
                  direction=[0.0, -1.0, 0.0], **bars)]
    bare = dict(d, bolt=[])
    design = nmm3d.design_bolt_pattern(nmm3d.Scenario.from_dict(bare), faces, target=1.5)
    assert max(design.bare.values()) < 0.5 and min(design.supported.values()) >= 1.5
    assert all(fs < 1.5 for s, fs in design.tried[:-1])  # the widest spacing that works
    spelled = nmm3d.Scenario.from_dict(dict(bare, bolt_pattern=design.patterns)).to_dict()["bolt"]
    assert len(spelled) == len(d["bolt"])
    for got, want in zip(spelled, d["bolt"]):
        assert got["name"] == want["name"]
        assert got["head"] == pytest.approx(want["head"], abs=1e-9)
        assert got["anchor"] == pytest.approx(want["anchor"], abs=1e-9)


def test_a_bolt_design_that_cannot_reach_the_target_names_the_blocks():
    """Bolts of 1 N cannot hold the hanging cube (W = 24.5 kN) at any spacing."""
    d = nmm3d.load(EXAMPLE).to_dict()
    d["bolt"], d["expect"] = [], []
    face = dict(name="weak", start=[0.1, 0.1, -1.2], along=[0.8, 0.0, 0.0], across=[0.0, 0.8, 0.0],
                direction=[0.0, 0.0, 1.0], length=2.0, head_depth=0.5, stiffness=1e7, yield_force=1.0)
    with pytest.raises(ValueError, match=r"block \d+ \(FS 0\.00\)"):
        nmm3d.design_bolt_pattern(nmm3d.Scenario.from_dict(d), [face], target=1.5, spacings=(1.0, 0.5))
