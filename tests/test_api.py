"""The Python API of the contract: load / from_dict, run, history as numpy arrays."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES


def test_from_dict_runs_and_history_is_numpy(cube, tmp_path):
    result = nmm3d.Scenario.from_dict(cube).run(out=tmp_path / "run")
    assert result.completed
    z = result.history["cube.displacement.z"]
    assert isinstance(z, np.ndarray) and z.dtype == float
    t = result.history["time"]
    # Free fall: u = -½ g t², exact for the DDA scheme.
    np.testing.assert_allclose(z, -5.0 * t**2, rtol=1e-9, atol=1e-12)
    assert result.summary["final"]["cube.velocity.z"] == pytest.approx(-1.0, rel=1e-9)
    assert result.blocks["body"].tolist() == ["cube"]


def test_load_file_with_overrides_matches_cli_semantics():
    s = nmm3d.load(EXAMPLES / "cantilever.toml", ["material.rock.young=2e10", "cover.size=0.5"])
    d = s.to_dict()
    assert d["material"][0]["young"] == 2e10 and d["cover"]["size"] == 0.5
    assert d["analysis"]["kind"] == "static"


def test_invalid_dict_raises_scenario_error_with_key_path(cube):
    cube["material"][0]["poisson"] = 0.7
    with pytest.raises(nmm3d.ScenarioError, match=r"material\.rock\.poisson"):
        nmm3d.Scenario.from_dict(cube)
    assert issubclass(nmm3d.ScenarioError, nmm3d.NmmError)


def test_run_releases_the_gil(cube, tmp_path):
    cube["analysis"]["duration"] = 1.0
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)

    t = threading.Thread(target=count)
    t.start()
    try:
        nmm3d.Scenario.from_dict(cube).run(out=tmp_path / "gil")
    finally:
        stop.set()
        t.join()
    assert len(ticks) > 100, "the counting thread did not run while nmm3d computed"


def test_with_overrides_returns_a_new_scenario(cube):
    s = nmm3d.Scenario.from_dict(cube)
    s2 = s.with_overrides("analysis.duration=0.2")
    assert s.to_dict()["analysis"]["duration"] == 0.1
    assert s2.to_dict()["analysis"]["duration"] == 0.2


def test_blocks_as_numpy_arrays(cube):
    b = nmm3d.Scenario.from_dict(cube).blocks()
    assert b["volume"].tolist() == [1.0]
    np.testing.assert_allclose([b["centroid_x"][0], b["centroid_y"][0], b["centroid_z"][0]], [0.5, 0.5, 0.5])
    assert b["body"].tolist() == ["cube"] and b["fixed"].dtype == bool
