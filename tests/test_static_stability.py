"""A static analysis as a stability check (`analysis.static_travel_limit`): the run stops once
the blocks that moved beyond the limit are the only ones out of equilibrium, names them in
`summary.json` (`not_held`), and a critical-friction study on such runs finds the wedge's
critical angle as block theory does — a verdict per run without following a failing block
down its slope (the static framework of joint-element NMM, issue 10 item 1).
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.wedge import critical_friction_angle
from test_wedge_nmm import PLANE_A, PLANE_B, scenario

LIMIT = 0.02  # m
PSEUDO_TIME = 20.0  # s: the static run's time limit (its steps are not physical time)


def static_scenario(phi: float) -> dict:
    data = scenario(phi)
    data["analysis"].update(kind="static", dt=1.0, duration=PSEUDO_TIME, static_travel_limit=LIMIT)
    return data


def static_tunnel(phi: float, limit: float) -> dict:
    """`examples/tunnel_key_blocks.toml` as a static stability check at φ with a travel limit [m]."""
    data = nmm3d.load(EXAMPLES / "tunnel_key_blocks.toml").to_dict()
    data.pop("expect", None)
    data["joint"][0]["friction_angle"] = phi
    data["analysis"].update(kind="static", dt=1.0, duration=PSEUDO_TIME, output_interval=0.0,
                            static_travel_limit=limit)
    return data


def wedge_block(out) -> int:
    with open(out / "blocks.csv", newline="") as f:
        return next(int(r["id"]) for r in csv.DictReader(f) if r["body"] == "wedge")


def run(phi: float, out) -> nmm3d.Result:
    return nmm3d.Scenario.from_dict(static_scenario(phi)).run(out=out)


def test_a_static_run_names_the_wedge_it_does_not_hold(tmp_path):
    phi = critical_friction_angle(PLANE_A, PLANE_B) - 2.0
    result = run(phi, tmp_path / "run")
    s = result.summary
    assert s["status"] == "not_converged", s["message"]
    assert s["not_held"] == [wedge_block(tmp_path / "run")], s
    assert "not held" in s["message"] and "static_travel_limit" in s["message"], s["message"]
    moved = np.linalg.norm([s["final"][f"wedge.displacement.{c}"] for c in "xyz"])
    assert moved > 0.5 * LIMIT


def test_a_static_run_holds_the_wedge_above_its_critical_angle(tmp_path):
    phi = critical_friction_angle(PLANE_A, PLANE_B) + 2.0
    result = run(phi, tmp_path / "run")
    s = result.summary
    assert result.completed, s["message"]
    assert "not_held" not in s
    assert np.linalg.norm([s["final"][f"wedge.displacement.{c}"] for c in "xyz"]) < 1e-3


def test_a_released_wedge_carries_no_contact_points(tmp_path):
    """Beyond the limit a block is released: its contact points go (a failed block neither holds
    nor drags its neighbours)."""
    run(critical_friction_angle(PLANE_A, PLANE_B) - 2.0, tmp_path / "run")
    with open(tmp_path / "run" / "diagnostics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert int(rows[0]["contact_points"]) > 0
    assert int(rows[-1]["contact_points"]) == 0, rows[-1]


def test_released_tunnel_key_blocks_stay_where_they_crossed_the_limit(tmp_path):
    """The tunnel's key blocks below their critical angles, on a limit of 2 mm: each is pinned
    where it crossed it (its displacement constant from then on, while the run goes on until the
    rest of the rock mass is in equilibrium), so a falling block neither cuts the step nor runs
    through the rock."""
    limit = 0.002
    s = nmm3d.Scenario.from_dict(static_tunnel(20.0, limit)).run(out=tmp_path / "run").summary
    assert s["status"] == "not_converged" and s["not_held"], s["message"]
    with open(tmp_path / "run" / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    blocks = {"roof_key_block": 21, "wall_key_block": 24}  # as the example's checks name them
    pinned = 0
    for name, block in blocks.items():
        assert block in s["not_held"], f"{name} held at 20°"
        u = np.array([[float(r[f"{name}.displacement.{c}"]) for c in "xyz"] for r in rows])
        # The limit bounds the block's farthest vertex; its centroid, monitored, moved less.
        since = len(u) - 1
        while since > 0 and np.array_equal(u[since - 1], u[-1]):
            since -= 1
        assert np.linalg.norm(u[-1]) > 0.5 * limit, f"{name} ended within the limit"
        pinned += len(u) - 1 - since
    assert pinned > 0, "the run ended as both crossed: nothing shows the pinning"


def test_without_a_limit_a_static_run_follows_the_wedge_to_its_time_limit(tmp_path):
    """The limit is opt-in: 0 keeps a static run going until equilibrium or its time limit."""
    data = static_scenario(critical_friction_angle(PLANE_A, PLANE_B) - 2.0)
    data["analysis"].update(static_travel_limit=0.0, duration=2.0)
    s = nmm3d.Scenario.from_dict(data).run(out=tmp_path / "run").summary
    assert s["status"] == "not_converged" and "reached the duration" in s["message"], s["message"]
    assert "not_held" not in s


def test_a_static_critical_friction_study_finds_the_wedge_angle(tmp_path):
    phi_c = critical_friction_angle(PLANE_A, PLANE_B)
    data = static_scenario(30.0)
    data["study"] = {"kind": "critical_friction", "joints": ["j"], "range": [phi_c - 8.0, phi_c + 8.0],
                     "tolerance": 0.5, "criterion": {"monitor": "wedge", "displacement": 0.01,
                                                     "time": PSEUDO_TIME}}
    s = nmm3d.Study(nmm3d.Scenario.from_dict(data), out=tmp_path / "study").run(workers=1).summary
    assert s["search_status"] == "converged", s["message"]
    low, high = s["bracket"]
    assert high - low <= 0.5 + 1e-9
    assert low - 0.5 <= phi_c <= high + 0.5, (s["bracket"], phi_c)


def test_a_study_counts_blocks_pinned_below_its_threshold_as_failed(tmp_path):
    """A travel limit below the criterion's displacement: the wedge is pinned at 5 mm, short of
    the 1 cm threshold, yet a run that did not hold it judges it unstable."""
    phi_c = critical_friction_angle(PLANE_A, PLANE_B)
    data = static_scenario(30.0)
    data["analysis"]["static_travel_limit"] = 0.005
    data["study"] = {"kind": "critical_friction", "joints": ["j"], "range": [phi_c - 8.0, phi_c + 8.0],
                     "tolerance": 0.5, "criterion": {"monitor": "wedge", "displacement": 0.01,
                                                     "time": PSEUDO_TIME}}
    s = nmm3d.Study(nmm3d.Scenario.from_dict(data), out=tmp_path / "study").run(workers=1).summary
    assert s["search_status"] == "converged", s["message"]
    assert s["bracket"][0] - 0.5 <= phi_c <= s["bracket"][1] + 0.5, (s["bracket"], phi_c)


def test_a_travel_limit_must_not_be_negative():
    """(A non-finite one is refused by the CLI's own check: `test_bad_inputs.py`.)"""
    data = static_scenario(30.0)
    data["analysis"]["static_travel_limit"] = -0.01
    with pytest.raises(nmm3d.ScenarioError, match=r"analysis\.static_travel_limit"):
        nmm3d.Scenario.from_dict(data)


def test_a_static_run_settles_its_contacts_at_the_static_tolerance(tmp_path):
    """A static run's steps are iterates towards its end, so its open–close iteration settles at
    `static_open_close_tolerance` (1e-3): the tunnel's key blocks held at 30° in fewer iterations
    than with every point's state exact, at the same rest."""
    data = static_tunnel(30.0, LIMIT)
    runs = {}
    for tol in (0.0, 1e-3):
        data["analysis"]["static_open_close_tolerance"] = tol
        runs[tol] = nmm3d.Scenario.from_dict(data).run(out=tmp_path / f"tol_{tol}").summary
    exact, tolerant = runs[0.0], runs[1e-3]
    assert exact["status"] == tolerant["status"] == "completed", (exact["message"], tolerant["message"])
    assert tolerant["open_close_iterations"] < 0.5 * exact["open_close_iterations"], (tolerant, exact)
    key = "roof_key_block.displacement.z"
    assert tolerant["final"][key] == pytest.approx(exact["final"][key], rel=0.03), key


def test_the_static_tolerance_is_validated():
    data = static_scenario(30.0)
    data["analysis"]["static_open_close_tolerance"] = 1.0
    with pytest.raises(nmm3d.ScenarioError, match=r"analysis\.static_open_close_tolerance"):
        nmm3d.Scenario.from_dict(data)


def test_the_tunnel_on_1_mpa_joints_reaches_static_equilibrium(tmp_path):
    """Joints of 1 MPa/m close by centimetres, so the static iterates detect afresh, and a face
    turned by millimetres is found again pushing several times harder or softer: with the total
    force the iterates wandered (unbalanced ratio about 1.5 after 270). A static analysis's
    re-detected pair now pushes at most 5 % harder than its points did (`contact/joint_force.rs`,
    `contact.static_carry_slack`): 42–46 iterates on this machine."""
    data = nmm3d.load(EXAMPLES / "tunnel_key_blocks.toml", ["joint.joint.normal_stiffness=1e6"]).to_dict()
    data.pop("expect", None)
    data["analysis"].update(kind="static", dt=1.0, duration=100.0, initial_equilibrium=False)
    s = nmm3d.Scenario.from_dict(data).run(out=tmp_path / "run").summary
    assert s["status"] == "completed" and s["unbalanced_force_ratio"] < 1e-3, (s["message"], s["steps"])
    assert s["final"]["roof_key_block.displacement.z"] < -0.02, "1 MPa/m joints close by centimetres"


def soft_static_tunnel(phi: float, start) -> dict:
    """The tunnel's key blocks on 10 MPa/m joints, a static check with a travel limit of 2 cm."""
    data = nmm3d.load(EXAMPLES / "tunnel_key_blocks.toml", ["joint.joint.normal_stiffness=1e7"]).to_dict()
    data.pop("expect", None)
    data["joint"][0]["friction_angle"] = phi
    data["analysis"].update(kind="static", dt=1.0, duration=100.0, output_interval=0.0,
                            static_travel_limit=0.02, initial_equilibrium=start)
    return data


def test_on_10_mpa_joints_the_travel_limit_sees_failure_not_the_joints_closing(tmp_path):
    """The rock closes 10 MPa/m joints by about a centimetre under its weight, and the roof key
    block (block theory: 22.6°) settles 10–15 mm at 45°. The travel is measured from where the
    static analysis starts — after the initial equilibrium — and at the blocks' vertices: by the
    covers (nodes up to a cell from the block, moved by its tilt times that lever) and from the
    reference configuration it was 'not held' at 45° either way. At 25° the wall key block
    (block theory: 28.0°) still goes."""
    for start in ("frictional", False):
        s = nmm3d.Scenario.from_dict(soft_static_tunnel(45.0, start)).run(out=tmp_path / f"45-{start}").summary
        assert s["status"] == "completed" and not s.get("not_held"), (start, s["message"])
    s = nmm3d.Scenario.from_dict(soft_static_tunnel(25.0, "frictional")).run(out=tmp_path / "25").summary
    assert s["status"] == "not_converged" and 24 in s["not_held"], s["message"]
