"""The open–close iteration's settling criterion on a real jointed rock mass.

On the thesis slope (case A, φ = 10°) the points on the side faces of neighbouring blocks flip
between stick, slide and open at nearly zero force; waiting until no point changes state costs
iterations and step cuts without changing the motion. `analysis.open_close_tolerance` settles
the iteration once the forces of the changing points are that small a fraction of all contact
forces. These tests hold the tolerance to its promise: fewer iterations and cuts, the same
motion.
"""

from __future__ import annotations

import pytest

import nmm3d
from conftest import EXAMPLES

SLOPE = ["joint.rock_joint.friction_angle=10", "analysis.duration=0.006"]


@pytest.fixture(scope="module")
def slope_runs(tmp_path_factory):
    base = tmp_path_factory.mktemp("open_close")
    runs = {}
    for tol in (0.0, 1e-3):
        scenario = nmm3d.load(EXAMPLES / "rock_slope.toml", [*SLOPE, f"analysis.open_close_tolerance={tol}"])
        runs[tol] = scenario.run(out=base / f"tol_{tol}")
    return runs


def test_a_tolerance_settles_the_slope_in_fewer_iterations(slope_runs):
    exact, tolerant = slope_runs[0.0].summary, slope_runs[1e-3].summary
    assert exact["status"] == tolerant["status"] == "completed"
    per_step = lambda s: s["open_close_iterations"] / s["steps"]  # noqa: E731
    assert per_step(tolerant) < per_step(exact), (per_step(tolerant), per_step(exact))
    assert tolerant["steps"] <= exact["steps"]


def test_a_tolerance_does_not_change_the_motion(slope_runs):
    exact, tolerant = slope_runs[0.0].summary["final"], slope_runs[1e-3].summary["final"]
    moved = abs(exact["toe_block.displacement.x"])
    assert moved > 1e-5, exact
    for axis in "xz":
        key = f"toe_block.displacement.{axis}"
        assert tolerant[key] == pytest.approx(exact[key], rel=0.02, abs=1e-7), key


def test_the_tolerance_is_validated(tmp_path):
    with pytest.raises(nmm3d.ScenarioError, match="analysis.open_close_tolerance"):
        nmm3d.load(EXAMPLES / "incline.toml", ["analysis.open_close_tolerance=1.5"])


def test_a_solve_whose_points_all_opened_is_not_settled_by_the_tolerance(tmp_path):
    """The bolted block, static, hangs from its bolt: the first solve holds it on its closed
    points, which then all open. Nothing is left to be a fraction of, so the iteration goes on
    (it once settled there, took a step more and drifted 35 nm sideways)."""
    runs = {}
    for tol in (0.0, 1e-3):
        scenario = nmm3d.load(EXAMPLES / "bolted_block.toml", [f"analysis.static_open_close_tolerance={tol}"])
        runs[tol] = scenario.run(out=tmp_path / f"tol_{tol}").summary
    assert runs[1e-3]["steps"] == runs[0.0]["steps"]
    assert runs[1e-3]["final"] == runs[0.0]["final"]
