"""Faces given as geologists write them: dip, dip direction and a point (docs/conventions.md)."""

from __future__ import annotations

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.wedge import plane_normal


def as_normal_vectors(scenario: dict) -> dict:
    """The same scenario with every dip/dip-direction face written as a row [nx, ny, nz, d]."""
    for body in scenario["body"]:
        convex = body["shape"].get("convex", {})
        for f in convex.pop("faces", []):
            n = plane_normal(f["dip"], f["dip_direction"]) * (1.0 if f["keep"] == "below" else -1.0)
            convex.setdefault("planes", []).append([*n, float(n @ np.asarray(f["point"]))])
    return scenario


def test_a_face_by_dip_and_dip_direction_cuts_the_same_blocks_as_its_normal_vector():
    by_dip = nmm3d.load(EXAMPLES / "rock_slope.toml")
    d = by_dip.to_dict()
    assert any("faces" in b["shape"].get("convex", {}) for b in d["body"]), "the example gives its faces by dip"
    a, b = by_dip.blocks(), nmm3d.Scenario.from_dict(as_normal_vectors(d)).blocks()
    assert len(a["id"]) == len(b["id"]) > 40
    np.testing.assert_allclose(a["volume"], b["volume"], rtol=1e-9)
    for c in ("centroid_x", "centroid_y", "centroid_z"):
        np.testing.assert_allclose(a[c], b[c], atol=1e-9)


def cube_below(face: dict) -> float:
    s = nmm3d.Scenario.from_dict({
        "material": [{"name": "rock", "density": 2500.0, "young": 1e9, "poisson": 0.25}],
        "body": [{"name": "b", "material": "rock", "shape": {"convex": {
            "planes": [[-1, 0, 0, 0], [1, 0, 0, 1], [0, -1, 0, 0], [0, 1, 0, 1], [0, 0, -1, 0], [0, 0, 1, 1]],
            "faces": [face]}}}],
    })
    return float(s.blocks()["volume"].sum())


def test_keep_below_is_the_rock_behind_a_face_and_above_the_rest():
    # A 45/090 face through the cube's centre: each side is half the unit cube.
    below = cube_below({"dip": 45.0, "dip_direction": 90.0, "point": [0.5, 0.5, 0.5]})
    above = cube_below({"dip": 45.0, "dip_direction": 90.0, "point": [0.5, 0.5, 0.5], "keep": "above"})
    assert below == pytest.approx(0.5) and above == pytest.approx(0.5)
    # A 20/090 face through (0, y, 0.8) falls towards the east: z = 0.8 − x tan 20° over the cube.
    v = cube_below({"dip": 20.0, "dip_direction": 90.0, "point": [0.0, 0.5, 0.8]})
    assert v == pytest.approx(0.8 - 0.5 * np.tan(np.radians(20.0)), rel=1e-9)

def test_a_face_dipping_beyond_90_degrees_is_invalid_input():
    with pytest.raises(nmm3d.ScenarioError, match=r"faces\[0\]"):
        cube_below({"dip": 95.0, "dip_direction": 90.0, "point": [0.5, 0.5, 0.5]})
