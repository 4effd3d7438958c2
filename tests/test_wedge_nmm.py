"""Verification (d): the NMM tetrahedral wedge against the analytic two-plane module.

A tetrahedral wedge rests on two planes through the origin (dip 50°, dip directions 130° and
230°); their half-spaces below are fixed rock. Released from its initial equilibrium, it must
slide as `nmm3d.wedge` says: the mode, the direction along the line of intersection within 1°,
the acceleration within 2 %; and stay put 1° above the critical friction angle.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d
from nmm3d.wedge import critical_friction_angle, plane_normal, wedge

PLANE_A, PLANE_B = (50.0, 130.0), (50.0, 230.0)
G = 9.81
T = 0.4  # s


def scenario(phi: float, planes: tuple = (PLANE_A, PLANE_B)) -> dict:
    """The wedge on two joint planes (dip, dip direction) between fixed rock, at rest."""
    na, nb = plane_normal(*planes[0]), plane_normal(*planes[1])
    box = [[1, 0, 0, 4.0], [-1, 0, 0, 4.0], [0, 1, 0, 1.0], [0, -1, 0, 6.0], [0, 0, 1, 0.0], [0, 0, -1, 6.0]]
    rock = lambda n: [[*n.tolist(), 0.0], *box]  # noqa: E731 (below the plane: n·x ≤ 0)
    return {
        "analysis": {"duration": T, "dt": 0.002, "max_displacement_ratio": 0.002, "gravity": [0.0, 0.0, -G],
                     "output_interval": 0.0, "initial_equilibrium": True},
        "cover": {"pattern": "tet6", "size": 0.5},
        "material": [{"name": "rock", "density": 2600.0, "young": 1.0e10, "poisson": 0.0}],
        "joint": [{"name": "j", "friction_angle": phi}],
        "body": [
            {"name": "rock_a", "material": "rock", "fixed": True, "shape": {"convex": {"planes": rock(na)}}},
            {"name": "rock_b", "material": "rock", "fixed": True, "shape": {"convex": {"planes": rock(nb)}}},
            {"name": "wedge", "material": "rock", "joint": "j", "shape": {"convex": {"planes": [
                [*(-na).tolist(), 0.0], [*(-nb).tolist(), 0.0], [0, 0, 1, 0.0], [0, -1, 0, 2.0]]}}},
        ],
        "monitor": [{"name": "wedge", "select": {"body": "wedge"}, "quantities": ["displacement"]}],
    }


def slide(phi: float, tmp_path) -> np.ndarray:
    result = nmm3d.Scenario.from_dict(scenario(phi)).run(out=tmp_path / f"phi{phi}")
    assert result.completed, result.summary["message"]
    return np.array([result.summary["final"][f"wedge.displacement.{c}"] for c in "xyz"])


def test_sliding_wedge_follows_the_vector_method(tmp_path):
    phi = 20.0
    ref = wedge(PLANE_A, PLANE_B, phi, g=G)
    assert ref.mode == "sliding on both" and ref.acceleration > 0
    d = slide(phi, tmp_path)
    dist = float(np.linalg.norm(d))
    angle = math.degrees(math.acos(min(1.0, float(d @ ref.direction) / dist)))
    assert angle < 1.0, f"slides {angle:.2f}° off the line of intersection"
    accel = 2.0 * dist / T**2
    assert accel == pytest.approx(ref.acceleration, rel=0.02)


def test_wedge_stays_above_the_critical_angle(tmp_path):
    phi = critical_friction_angle(PLANE_A, PLANE_B) + 1.0
    assert wedge(PLANE_A, PLANE_B, phi, g=G).stable
    d = slide(phi, tmp_path)
    assert np.linalg.norm(d) < 1e-4
