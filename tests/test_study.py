"""Studies end to end, on Dask: critical friction angles and factors of safety against closed
forms, per-block criteria, sweeps, Monte-Carlo, 1 vs 2 workers, resume, failures, exit codes.

Closed forms: the tetrahedral wedge by the vector method (`nmm3d.wedge`, Hoek & Bray); the roof
wedges held by in-situ stress by the relaxation solution with k_s = k_n (`nmm3d.roof_wedge`,
Goodman, Shi & Boyle 1982). Tolerances (issue "Studies"): critical angle within 0.5°, factor of
safety within 2 %. Each study's criterion is strict enough (mm over a second) that the
displacement threshold biases the boundary by a few hundredths of a degree only.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time

import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d import roof_wedge
from nmm3d.wedge import critical_friction_angle, wedge

PLANES = (50.0, 130.0), (50.0, 230.0)
PRISM = roof_wedge.prism(1.0, math.sqrt(3.0), 4.0, 2000.0, 10.0, 5e4)
PYRAMID = roof_wedge.pyramid(1.0, math.sqrt(3.0), 2000.0, 10.0, 5e4)


def study(name: str, out, *overrides: str, workers: int = 2) -> nmm3d.StudyResult:
    return nmm3d.Study(EXAMPLES / name, out, overrides).run(workers=workers)


@pytest.fixture(scope="module")
def tetrahedral(tmp_path_factory):
    return study("tetrahedral_wedge.toml", tmp_path_factory.mktemp("study") / "tetra")


def test_critical_friction_of_the_tetrahedral_wedge_is_the_vector_method(tetrahedral):
    s = tetrahedral.summary
    assert s["status"] == "completed", s["message"]
    lo, hi = s["bracket"]
    assert hi - lo <= 0.4 + 1e-9
    assert s["critical_friction_angle"] == pytest.approx(critical_friction_angle(*PLANES), abs=0.5)
    rows = tetrahedral.table
    assert len(rows["value"]) == s["runs"] and set(rows["status"]) == {"completed"}
    assert (tetrahedral.directory / "study.png").is_file()
    for folder in rows["folder"]:
        assert (tetrahedral.directory / folder / "summary.json").is_file()


def test_one_worker_gives_the_same_study_as_two(tetrahedral, tmp_path):
    one = study("tetrahedral_wedge.toml", tmp_path / "one", workers=1)
    assert (one.directory / "study.json").read_text() == (tetrahedral.directory / "study.json").read_text()
    assert json.loads((one.directory / "execution.json").read_text())["workers"] == 1


@pytest.mark.parametrize("name, closed_form", [("roof_wedge_prism.toml", PRISM), ("roof_wedge_pyramid.toml", PYRAMID)])
def test_critical_friction_of_roof_wedges_under_in_situ_stress(name, closed_form, tmp_path):
    s = study(name, tmp_path).summary
    assert s["status"] == "completed", s["message"]
    assert s["critical_friction_angle"] == pytest.approx(closed_form.critical_friction_angle(), abs=0.5)


def test_the_prism_on_tet6_comes_to_rest(tmp_path):
    # It rocked for as long as it ran while contact points were detected afresh every step
    # (docs/studies.md); kept points between detections (`ContactSet::refresh`) let it rest.
    r = nmm3d.load(EXAMPLES / "roof_wedge_prism.toml", ["cover.pattern=\"tet6\"", "joint.j.friction_angle=50.0",
                                                        "analysis.output_interval=0.0"]).run(out=tmp_path)
    x = r.history["wedge.displacement.x"]
    late = x[len(x) // 2:]
    assert float(late.max() - late.min()) < 1e-6, "still rocking sideways"


@pytest.mark.parametrize("name, expected", [
    ("tetrahedral_wedge.toml", wedge(*PLANES, 40.0).factor_of_safety),
    ("roof_wedge_pyramid.toml", PYRAMID.factor_of_safety(45.0)),
])
def test_strength_reduction_factor_of_safety(name, expected, tmp_path):
    s = study(name, tmp_path, "study.kind=\"strength_reduction\"", "study.range=[0.8, 1.8]", "study.tolerance=0.02",
              "joint.j.friction_angle=40.0" if name.startswith("tetra") else "joint.j.friction_angle=45.0").summary
    assert s["status"] == "completed", s["message"]
    assert s["factor_of_safety"] == pytest.approx(expected, rel=0.02)
    assert (tmp_path / "study.png").is_file()


def test_per_block_criterion_names_the_blocks_that_go_and_when(tmp_path):
    s = study("tetrahedral_wedge.toml", tmp_path, "study.kind=\"sweep\"", "study.parameters={\"joint.j.friction_angle\" = [20.0, 40.0]}",
              "study.criterion={blocks = \"all\", displacement = 0.01, time = 0.4}").summary
    blocks = nmm3d.load(EXAMPLES / "tetrahedral_wedge.toml").blocks()
    moving = [int(i) for i, fixed in zip(blocks["id"], blocks["fixed"]) if not fixed]
    low, high = s["rows"]
    assert low["failed_blocks"] == moving and high["failed_blocks"] == []
    # Sliding from rest with a = g sin ψ (1 − FS): 1 cm after t = sqrt(2 d / a).
    a = wedge(*PLANES, 20.0).acceleration
    assert low["detach_times"][f"block:{moving[0]}"] == pytest.approx(math.sqrt(2 * 0.01 / a), abs=0.01)


def test_monte_carlo_friction_scatter_fails_where_the_vector_method_says(tmp_path):
    phi_c = critical_friction_angle(*PLANES)
    s = study("tetrahedral_wedge.toml", tmp_path, "study.kind=\"monte_carlo\"", "study.samples=16", "study.seed=3",
              "study.strength=[{joint = \"j\", friction_angle_sd = 3.0}]", "joint.j.friction_angle=32.5").summary
    assert s["samples"] == 16 and s["judged"] == 16
    # Within 0.1° of φ_c a run cannot tell (the criterion's own bias is ~0.05°; 0.006° below
    # φ_c a wedge slides 1 mm in the 0.5 s run): those samples may go either way.
    near = [r for r in s["rows"] if abs(r["joint.j.friction_angle"] - phi_c) <= 0.1]
    for r in s["rows"]:
        if r not in near:
            assert r["unstable"] == (r["joint.j.friction_angle"] < phi_c), r
    # The study's probability is the vector method's on the same samples (the sampler's
    # distribution is checked in test_study_units.py against the normal law, P = Φ((φ_c − μ)/σ)).
    below = sum(r["joint.j.friction_angle"] < phi_c for r in s["rows"] if r not in near)
    assert below <= s["failures"] <= below + len(near)
    assert s["probability_of_failure"] == s["failures"] / 16
    lo, hi = s["interval"]
    assert lo < s["failures"] / 16 < hi
    assert (tmp_path / "study.png").is_file()


def test_monte_carlo_scatters_joint_orientations(tmp_path):
    scenario = nmm3d.Scenario.from_dict({
        "analysis": {"duration": 0.01, "dt": 0.005, "gravity": [0.0, 0.0, -10.0], "output_interval": 0.0},
        "cover": {"size": 0.5},
        "material": [{"name": "rock", "density": 2500.0, "young": 1e9, "poisson": 0.25}],
        "joint": [{"name": "j", "friction_angle": 30.0}],
        "joint_plane": [{"point": [0.5, 0.5, 0.5], "dip": 40.0, "dip_direction": 120.0, "joint": "j"}],
        "body": [{"name": "cube", "material": "rock", "joint": "j", "shape": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}}],
        "study": {"kind": "monte_carlo", "samples": 4, "seed": 1, "orientation": [{"joint_plane": 0, "kappa": 50.0}],
                  "criterion": {"blocks": "all", "displacement": 1.0, "time": 0.01}},
    })
    s = nmm3d.Study(scenario, tmp_path).run(workers=2).summary
    dips = [r["joint_plane.0.dip"] for r in s["rows"]]
    assert len(set(dips)) == 4 and all(20.0 < d < 60.0 for d in dips)
    assert s["judged"] == 4 and s["failures"] == 0 and s["probability_of_failure"] == 0.0


def test_a_failed_run_is_a_row_with_its_reason(tmp_path, cube):
    cube["analysis"].update(divergence_ratio=2.0, min_dt_ratio=1.0)  # no room to cut: the big load diverges
    cube["study"] = {"kind": "sweep", "parameters": {"analysis.gravity": [[0.0, 0.0, -10.0], [0.0, 0.0, -1.0e6]]},
                     "criterion": {"monitor": "cube", "displacement": 10.0, "time": 0.1}}
    s = nmm3d.Study(nmm3d.Scenario.from_dict(cube), tmp_path).run(workers=1).summary
    ok, bad = s["rows"]
    assert ok["status"] == "completed" and ok["unstable"] is False
    assert bad["status"] == "failed" and "diverged" in bad["message"]
    assert s["status"] == "completed" and s["runs"] == 2


def nmm3d_cli(*args: str, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "nmm3d", *args], capture_output=True, text=True, timeout=900, **kw)


def test_a_study_with_an_unknown_monitor_is_exit_2_naming_the_key(tmp_path):
    r = nmm3d_cli("study", str(EXAMPLES / "tetrahedral_wedge.toml"), "--out", str(tmp_path),
                  "--set", "study.criterion.monitor=\"nope\"")
    assert r.returncode == 2, r.stderr
    assert "study.criterion.monitor" in r.stderr and "nope" in r.stderr and "Traceback" not in r.stderr
    r = nmm3d_cli("check", str(EXAMPLES / "tetrahedral_wedge.toml"), "--set", "study.tolerance=-1")
    assert r.returncode == 2 and "study.tolerance" in r.stderr


def test_an_interrupted_study_resumes_without_rerunning_finished_runs(tmp_path):
    out = tmp_path / "sweep"
    args = ["study", str(EXAMPLES / "tetrahedral_wedge.toml"), "--out", str(out), "--workers", "1", "--quiet",
            "--set", "study.kind=\"sweep\"", "--set", "study.parameters={\"joint.j.friction_angle\" = [20.0, 25.0, 30.0, 35.0]}",
            "--set", "study.criterion.time=2.0"]  # runs of about 2 s: the kill lands between two
    p = subprocess.Popen([sys.executable, "-m", "nmm3d", *args], start_new_session=True,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 300
    while not list(out.glob("runs/*/record.json")) and time.monotonic() < deadline:
        time.sleep(0.2)
    os.killpg(p.pid, signal.SIGKILL)
    p.wait()
    finished = {f: f.stat().st_mtime_ns for f in out.glob("runs/*/record.json")}
    assert 1 <= len(finished) < 4 and not (out / "study.json").exists()
    r = nmm3d_cli(*args)
    assert r.returncode == 0, r.stderr
    execution = json.loads((out / "execution.json").read_text())
    assert execution["reused_runs"] == len(finished) and execution["runs"] == 4
    assert all(f.stat().st_mtime_ns == t for f, t in finished.items())
    assert json.loads((out / "study.json").read_text())["runs"] == 4


def test_a_study_runs_on_a_running_cluster(tmp_path):
    """`--scheduler`: a scheduler and a worker started as a user would (`dask scheduler`,
    `dask worker`), on loopback."""
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port",
                               str(port), "--no-dashboard"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", "1",
                                       "--nthreads", "1", "--no-dashboard"], env=env, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
        from distributed import Client

        with Client(address, timeout=60) as client:
            client.wait_for_workers(1, timeout=60)
        r = nmm3d_cli("study", str(EXAMPLES / "tetrahedral_wedge.toml"), "--out", str(tmp_path), "--scheduler", address,
                      "--set", "study.kind=sweep", "--set", "study.parameters={\"joint.j.friction_angle\" = [20.0, 40.0]}",
                      "--set", "study.criterion.time=0.2")
        assert r.returncode == 0, r.stderr
        execution = json.loads((tmp_path / "execution.json").read_text())
        assert execution["scheduler"] == address and execution["runs"] == 2
        assert [row["unstable"] for row in json.loads((tmp_path / "study.json").read_text())["rows"]] == [True, False]
    finally:
        for p in procs:
            p.terminate()
            p.wait(timeout=30)


def two_wedges() -> nmm3d.Scenario:
    """The example's wedge (50/130 + 50/230) and, 10 m east, a flatter one (40/130 + 40/230)."""
    import numpy as np

    from nmm3d.wedge import plane_normal

    box = [[1, 0, 0, 4.0], [-1, 0, 0, 4.0], [0, 1, 0, 1.0], [0, -1, 0, 6.0], [0, 0, 1, 0.0], [0, 0, -1, 6.0]]
    bodies = []
    for name, dip, shift in (("a", 50.0, np.zeros(3)), ("b", 40.0, np.array([10.0, 0.0, 0.0]))):
        na, nb = plane_normal(dip, 130.0), plane_normal(dip, 230.0)
        moved = lambda p: [*map(float, p[:3]), float(p[3] + np.dot(p[:3], shift))]  # noqa: E731
        rock = lambda n: [moved([*n, 0.0]), *(moved(np.array(b, float)) for b in box)]  # noqa: E731
        bodies += [
            {"name": f"rock_{name}1", "material": "rock", "fixed": True, "shape": {"convex": {"planes": rock(na)}}},
            {"name": f"rock_{name}2", "material": "rock", "fixed": True, "shape": {"convex": {"planes": rock(nb)}}},
            {"name": f"wedge_{name}", "material": "rock", "joint": "j", "shape": {"convex": {"planes": [
                moved(np.array([*(-na), 0.0])), moved(np.array([*(-nb), 0.0])), moved(np.array([0, 0, 1, 0.0])),
                moved(np.array([0, -1, 0, 2.0]))]}}},
        ]
    data = nmm3d.load(EXAMPLES / "tetrahedral_wedge.toml").to_dict()
    data.update(body=bodies, monitor=[], expect=[], study={"kind": "critical_friction", "range": [15.0, 45.0], "tolerance": 0.4,
                                                "criterion": {"blocks": "all", "displacement": 0.001, "time": 0.5}})
    return nmm3d.Scenario.from_dict(data)


def test_a_per_block_search_gives_every_key_block_its_own_critical_angle(tmp_path):
    scenario = two_wedges()
    s = nmm3d.Study(scenario, tmp_path).run(workers=2).summary
    assert s["status"] == "completed", s["message"]
    blocks = scenario.blocks()
    found = {b["id"]: b for b in s["blocks"]}
    assert len(found) == 2, found
    for dip in (50.0, 40.0):
        exact = critical_friction_angle((dip, 130.0), (dip, 230.0))
        x0 = 0.0 if dip == 50.0 else 10.0
        block = next(int(i) for i, x, fixed in zip(blocks["id"], blocks["centroid_x"], blocks["fixed"])
                     if not fixed and abs(x - x0) < 1.0)
        assert found[block]["critical_friction_angle"] == pytest.approx(exact, abs=0.5), (dip, found[block])
        assert found[block]["detach_time"] > 0.0
    # the study's own value is the first block to go as φ falls: the steeper wedge
    assert s["critical_friction_angle"] == pytest.approx(critical_friction_angle(*PLANES), abs=0.5)
    assert (tmp_path / "blocks.png").is_file()
