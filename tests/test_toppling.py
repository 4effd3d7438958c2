"""Sliding versus toppling of a block on an incline: the classical chart (Hoek & Bray 1981, fig.
9.2; Goodman & Bray 1976). A block of base b and height h on a plane dipping α:

* stable            α < φ and b/h > tan α
* sliding           α > φ and b/h > tan α
* toppling          α < φ and b/h < tan α
* sliding + toppling α > φ and b/h < tan α

Each cell of the chart is run for 0.6 s from the initial equilibrium; the block's tilt (rotation
about the strike) tells toppling, its displacement along the dip sliding.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d

ALPHA = 30.0


def block_on_incline(base: float, height: float, phi: float) -> dict:
    a = math.radians(ALPHA)
    n = [0.0, math.sin(a), math.cos(a)]   # up-normal of the slope (dips towards +y)
    s = [0.0, math.cos(a), -math.sin(a)]  # down-dip
    x = [1.0, 0.0, 0.0]                   # strike
    neg = lambda v: [-c for c in v]       # noqa: E731
    incline = [[*n, 0.0], [*neg(n), 0.2], [*s, 1.0], [*neg(s), 0.6], [*x, 0.4], [*neg(x), 0.4]]
    block = [[*neg(n), 0.0], [*n, height], [*s, base / 2], [*neg(s), base / 2], [*x, 0.25], [*neg(x), 0.25]]
    return {
        "analysis": {"duration": 0.6, "dt": 0.002, "max_displacement_ratio": 0.002, "gravity": [0.0, 0.0, -9.81],
                     "output_interval": 0.0, "initial_equilibrium": True},
        "cover": {"pattern": "tet6", "size": 0.1},
        "material": [{"name": "rock", "density": 2600.0, "young": 1.0e10, "poisson": 0.0}],
        "joint": [{"name": "j", "friction_angle": phi}],
        "body": [
            {"name": "incline", "material": "rock", "fixed": True, "shape": {"convex": {"planes": incline}}},
            {"name": "block", "material": "rock", "joint": "j", "shape": {"convex": {"planes": block}}},
        ],
        "monitor": [{"name": "block", "select": {"body": "block"}, "quantities": ["displacement", "rotation"]}],
    }


def behaviour(base: float, height: float, phi: float, tmp_path) -> tuple[bool, bool]:
    r = nmm3d.Scenario.from_dict(block_on_incline(base, height, phi)).run(out=tmp_path / f"b{base}h{height}p{phi}")
    assert r.completed, r.summary["message"]
    f = r.summary["final"]
    a = math.radians(ALPHA)
    u = np.array([f[f"block.displacement.{c}"] for c in "xyz"])
    tilt = abs(f["block.rotation.x"])  # about the strike
    # Sliding: the base moves down-dip; toppling: the block tilts by more than 5°.
    base_slip = float(u @ np.array([0.0, math.cos(a), -math.sin(a)])) - tilt * height / 2
    return tilt > math.radians(5.0), base_slip > 0.02


@pytest.mark.parametrize("case, base, height, phi, expected", [
    ("stable", 0.4, 0.4, 40.0, (False, False)),
    ("sliding", 0.4, 0.4, 20.0, (False, True)),
    ("toppling", 0.2, 0.6, 40.0, (True, False)),
    ("sliding and toppling", 0.2, 0.6, 20.0, (True, True)),
])
def test_the_chart_cells(case, base, height, phi, expected, tmp_path):
    # The cell of the chart from α, φ and b/h.
    assert ((base / height < math.tan(math.radians(ALPHA))), (phi < ALPHA)) == expected
    topples, slides = behaviour(base, height, phi, tmp_path)
    assert (topples, slides) == expected, case
