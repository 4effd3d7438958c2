"""Fixed bodies cost what they need (issue "rock masses at the implicit step", item 7): a fixed
block is one manifold element by default — its surface for contact, no equations — and
`[[body]] fixed_mesh = true` covers it like a moving body. Both must give the same answer.
"""

from __future__ import annotations

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES


def load(example: str, meshed: bool, *overrides: str) -> nmm3d.Scenario:
    data = nmm3d.load(EXAMPLES / example, list(overrides)).to_dict()
    for body in data["body"]:
        if body.get("fixed"):
            body["fixed_mesh"] = meshed
    return nmm3d.Scenario.from_dict(data)


def with_monitor(s: nmm3d.Scenario, point: list[float]) -> nmm3d.Scenario:
    data = s.to_dict()
    data["monitor"].append(
        {"name": "slab_corner", "select": {"point": point}, "quantities": ["displacement"], "location": "point"}
    )
    return nmm3d.Scenario.from_dict(data)


def test_block_on_joint_closes_alike_on_a_slab_of_one_element(tmp_path):
    # A point of the slab two cells from the cell its element is numbered in is still found.
    runs = {
        m: with_monitor(load("block_on_joint.toml", m), [0.9, 0.9, -0.45]).run(out=tmp_path / str(m))
        for m in (False, True)
    }
    one, meshed = runs[False], runs[True]
    assert one.completed and meshed.completed
    cube_elements = 8  # hex8, 0.5 m cover, a 1 m cube
    assert one.summary["manifold_elements"] == cube_elements + 1
    assert meshed.summary["manifold_elements"] == cube_elements + 16  # a 2 x 2 x 0.5 m slab
    assert one.summary["dofs"] == meshed.summary["dofs"]
    closure = {m: r.history["base.displacement.z"][-1] for m, r in runs.items()}
    assert closure[False] == pytest.approx(-0.25e-3, rel=0.01)
    assert closure[False] == pytest.approx(closure[True], rel=1e-3)
    assert abs(one.history["slab_corner.displacement.z"][-1]) == 0.0


def test_sliding_wedge_slides_alike_on_rock_of_one_element(tmp_path):
    # Soft joints (10 MPa/m): the wedge rides on its springs, and its two fixed bodies' faces are
    # single facets metres wide. If they lost their points when the normal tilts, the wedge
    # wobbled at 0.08 m/s across its path (the meshed rock: 0.03).
    runs = {m: load("sliding_wedge.toml", m, "analysis.duration=0.8").run(out=tmp_path / str(m)) for m in (False, True)}
    assert all(r.completed for r in runs.values())
    v = {m: np.c_[[r.history[f"wedge.velocity.{c}"] for c in "xyz"]].T for m, r in runs.items()}
    assert len(v[False]) == len(v[True])
    assert float(np.abs(v[False] - v[True]).max()) < 0.005
    assert runs[False].summary["max_contact_points"] < runs[True].summary["max_contact_points"] / 3
