"""Outputs one can trust: a used directory is refused unless --overwrite (then cleared), one
run writes a directory at a time, an empty --out is input, and a static run that does not reach
equilibrium says so (status "not_converged", exit 1)."""

from __future__ import annotations

import json
import os

from conftest import EXAMPLES
from test_cli import GOOD, nmm3d, write

EXIT_INPUT, EXIT_FAILED = 2, 1


def test_a_used_directory_is_refused_unless_overwritten_then_cleared(tmp_path):
    p, out = write(tmp_path, GOOD), tmp_path / "out"
    assert nmm3d("run", str(p), "--out", str(out)).returncode == 0
    stray = out / "frames" / "blocks_09999.vtu"
    stray.write_text("a frame of some earlier run")
    mine = out / "notes.txt"
    mine.write_text("the user's own file")

    again = nmm3d("run", str(p), "--out", str(out))
    assert again.returncode == EXIT_INPUT, again.stderr
    assert "--overwrite" in again.stderr and "summary.json" in again.stderr
    assert stray.exists(), "nothing touched when refused"

    r = nmm3d("run", str(p), "--out", str(out), "--overwrite")
    assert r.returncode == 0, r.stderr
    assert not stray.exists(), "the earlier run's frames are gone"
    assert mine.exists(), "files a run does not write are kept"
    frames = sorted(f.name for f in (out / "frames").glob("blocks_*.vtu"))
    pvd = (out / "result.pvd").read_text()
    assert frames and all(f in pvd for f in frames), "every frame there is the new run's"
    assert not (out / ".nmm3d.lock").exists(), "the lock goes with the run"


def test_a_directory_another_run_is_writing_is_refused(tmp_path):
    p, out = write(tmp_path, GOOD), tmp_path / "out"
    out.mkdir()
    (out / ".nmm3d.lock").write_text(str(os.getpid()))  # this test's process: alive
    r = nmm3d("run", str(p), "--out", str(out))
    assert r.returncode == EXIT_INPUT, r.stderr
    assert "being written by another run" in r.stderr and str(os.getpid()) in r.stderr
    assert not (out / "summary.json").exists()
    # The same lock left by a process that is gone is taken over.
    (out / ".nmm3d.lock").write_text("4294967295")
    assert nmm3d("run", str(p), "--out", str(out)).returncode == 0


def test_an_empty_output_directory_is_input(tmp_path):
    r = nmm3d("run", str(write(tmp_path, GOOD)), "--out", "")
    assert r.returncode == EXIT_INPUT, r.stderr
    assert "--out" in r.stderr and "Traceback" not in r.stderr


def test_a_static_run_short_of_equilibrium_is_not_converged(tmp_path):
    out = tmp_path / "out"
    r = nmm3d("run", str(EXAMPLES / "cantilever.toml"), "--out", str(out), "--set", "analysis.max_steps=2",
              "--set", "cover.size=0.5")
    assert r.returncode == EXIT_FAILED, r.stderr
    assert "not converged" in r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "not_converged" and "before equilibrium" in s["message"], s["message"]
    assert s["steps"] == 2
    # Given the steps it needs, the same run converges.
    r = nmm3d("run", str(EXAMPLES / "cantilever.toml"), "--out", str(out), "--overwrite", "--set", "cover.size=0.5")
    assert r.returncode == 0, r.stderr
    assert json.loads((out / "summary.json").read_text())["status"] == "completed"


def test_an_output_that_cannot_be_written_still_leaves_a_failed_summary(tmp_path):
    p, out = write(tmp_path, GOOD), tmp_path / "out"
    # The last frame's file name is taken by a directory: writing it fails mid-run.
    (out / "frames" / "blocks_00001.vtu").mkdir(parents=True)
    r = nmm3d("run", str(p), "--out", str(out))
    assert r.returncode == EXIT_FAILED, r.stderr
    assert "blocks_00001.vtu" in r.stderr and "Traceback" not in r.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "failed" and "blocks_00001.vtu" in s["message"], s
    assert s["steps"] >= 1
