"""A cover size per body (`[[body]] cover_size`, issue "rock masses at the implicit step", item 7):
a body meshed finely where it matters, the rest coarsely — each block on its own body's mesh.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES


def with_size(example: str, body: str, size: float, *overrides: str) -> nmm3d.Scenario:
    data = nmm3d.load(EXAMPLES / example, list(overrides)).to_dict()
    next(b for b in data["body"] if b["name"] == body)["cover_size"] = size
    return nmm3d.Scenario.from_dict(data)


def test_a_finer_block_on_a_joint_closes_alike_and_its_frames_read(tmp_path):
    # hex8: the 1 m cube on 0.25 m cells is 64 MEs (8 on the 0.5 m cover); the fixed slab one.
    r = with_size("block_on_joint.toml", "cube", 0.25, "analysis.output_interval=0.001").run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    assert r.summary["manifold_elements"] == 64 + 1
    assert r.summary["dofs"] == 3 * 5**3
    assert r.history["base.displacement.z"][-1] == pytest.approx(-0.25e-3, rel=0.01)
    pv = pytest.importorskip("pyvista")
    frames = sorted((tmp_path / "run" / "frames").glob("blocks_*.vtu"))
    assert frames and pv.read(frames[-1]).n_cells == r.summary["manifold_elements"]


def test_a_fine_block_on_a_coarse_cover_slides_at_the_closed_form_rate(tmp_path):
    """The staged incline's k_h stage (tests/test_stages.py) with only the cube on 0.25 m cells:
    the points on its edge-loaded base are as fine as with the whole cover at 0.25 m."""
    d = with_size("staged_incline.toml", "cube", 0.25).to_dict()
    d["stage"], d["bolt"] = d["stage"][:2], []
    d["stage"][1]["set"] = {"seismic.coefficient": [0.3, 0.0, 0.0]}
    r = nmm3d.Scenario.from_dict(d).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    g, c, s, k = 10.0, math.cos(math.radians(30)), math.sin(math.radians(30)), 0.3
    a = g * ((s + k * c) - math.tan(math.radians(40)) * (c - k * s))
    v = float(np.interp(0.7, r.history["time"], r.history["cube.velocity.x"]))
    assert v == pytest.approx(a * 0.5 * c, rel=0.01)


def test_each_body_is_meshed_at_its_own_size():
    coarse = nmm3d.load(EXAMPLES / "block_tower.toml").check()["stages"][0]
    tower = nmm3d.load(EXAMPLES / "block_tower.toml").to_dict()
    names = [b["name"] for b in tower["body"] if not b.get("fixed")]
    fine = with_size("block_tower.toml", names[0], 0.5 * tower["cover"]["size"]).check()["stages"][0]
    # One of the moving cubes on cells of half the edge: eight times its MEs.
    per_cube = (coarse["manifold_elements"] - 1) // len(names)
    assert fine["manifold_elements"] == coarse["manifold_elements"] + 7 * per_cube


@pytest.mark.parametrize("value", ["0.0", "-1.0", "nan"])
def test_a_cover_size_must_be_positive(value, tmp_path):
    path = tmp_path / "s.toml"
    text = (EXAMPLES / "block_on_joint.toml").read_text()
    path.write_text(text.replace('name = "cube"\n', f'name = "cube"\ncover_size = {value}\n'))
    with pytest.raises(nmm3d.ScenarioError, match="body.cube.cover_size"):
        nmm3d.load(path).check()
