"""Initial equilibrium (issue 10, item 3): the locked static iteration converges in a few
Newton iterations for block systems that are statically admissible, whatever the penalty.

Before the contact points were kept through the locked iterations, an asymmetric two-plane
wedge (40/130 + 60/220) stalled at an unbalanced ratio of 0.01–0.03 (one point at the edge of a
face coming and going with round-off, inheriting its neighbour's springs) until `max_steps`,
and the thesis tunnel with five faces held diverged after it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d
from nmm3d.wedge import critical_friction_angle, wedge
from test_wedge_nmm import scenario

PLANE_A, PLANE_B = (40.0, 130.0), (60.0, 220.0)

G = 9.81
T = 0.4  # s
MAX_STEPS = 500


def wedge_scenario(phi: float, duration: float = T, stiffness: float | None = None) -> dict:
    data = scenario(phi, (PLANE_A, PLANE_B))
    data["analysis"].update(duration=duration, max_steps=MAX_STEPS)
    data["contact"] = {} if stiffness is None else {"normal_stiffness": stiffness, "shear_stiffness": stiffness}
    return data


def run(data: dict, out) -> nmm3d.Result:
    result = nmm3d.Scenario.from_dict(data).run(out=out)
    assert result.completed, result.summary["message"]
    return result


@pytest.mark.parametrize("stiffness", [1e9, 1e10, None], ids=["1e9", "1e10", "auto"])
def test_asymmetric_wedge_settles_in_a_few_iterations_at_any_penalty(stiffness, tmp_path):
    result = run(wedge_scenario(45.0, duration=0.002, stiffness=stiffness), tmp_path / "run")
    settled = result.summary["initial_equilibrium"]
    assert settled["steps"] <= 10, settled
    assert settled["unbalanced_force_ratio"] <= 1e-7, settled


def displacement(result: nmm3d.Result) -> np.ndarray:
    return np.array([result.summary["final"][f"wedge.displacement.{c}"] for c in "xyz"])


def test_asymmetric_wedge_stays_above_its_critical_angle(tmp_path):
    phi = critical_friction_angle(PLANE_A, PLANE_B) + 1.0
    assert wedge(PLANE_A, PLANE_B, phi, g=G).stable
    d = displacement(run(wedge_scenario(phi), tmp_path / "run"))
    assert np.linalg.norm(d) < 1e-4


def test_asymmetric_wedge_slides_as_the_vector_method_below_it(tmp_path):
    phi = critical_friction_angle(PLANE_A, PLANE_B) - 5.0
    ref = wedge(PLANE_A, PLANE_B, phi, g=G)
    assert ref.acceleration > 0
    data = wedge_scenario(phi)
    data["analysis"]["max_steps"] = 100_000
    d = displacement(run(data, tmp_path / "run"))
    dist = float(np.linalg.norm(d))
    angle = math.degrees(math.acos(min(1.0, float(d @ ref.direction) / dist)))
    assert angle < 1.0, f"slides {angle:.2f}° off the vector method's direction ({ref.mode})"
    assert 2.0 * dist / T**2 == pytest.approx(ref.acceleration, rel=0.02)


def test_thesis_tunnel_with_five_faces_held_starts_from_rest(tmp_path):
    data = nmm3d.load("examples/tunnel_key_blocks.toml").to_dict()
    assert len(data["constraint"]) == 5 and data["analysis"]["initial_equilibrium"]
    data["analysis"].update(duration=0.005, max_steps=MAX_STEPS)
    data.pop("expect", None)
    result = run(data, tmp_path / "run")
    settled = result.summary["initial_equilibrium"]
    assert settled["steps"] <= 10, settled
    assert settled["unbalanced_force_ratio"] <= 1e-7, settled
    crown = abs(result.summary["final"]["crown.displacement.z"])
    assert crown < 1e-4, f"the crown moved {crown} m in 5 ms after equilibrium"
