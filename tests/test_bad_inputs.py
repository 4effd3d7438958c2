"""Bad inputs from the reliability audit end in a clean exit 2 naming what is wrong, never a
traceback or a hang: non-finite numbers anywhere, a FIFO or a directory as the scenario, plot
inputs that are not nmm3d's tables, a plot into a folder that does not exist yet."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from test_cli import GOOD, nmm3d, write

EXIT_INPUT = 2


@pytest.mark.parametrize("key, value, path", [
    ("cover.origin", "[nan, 0.0, 0.0]", "cover.origin[0]"),
    ("analysis.gravity", "[0.0, 0.0, -inf]", "analysis.gravity"),
    ("analysis.static_travel_limit", "inf", "analysis.static_travel_limit"),
    ("body.cube.velocity", "[0.0, nan, 0.0]", "body.cube.velocity"),
    ("material.rock.density", "nan", "material.rock.density"),
])
def test_a_non_finite_number_anywhere_is_named(tmp_path, key, value, path):
    p = write(tmp_path, GOOD)
    for command in (["check", str(p)], ["run", str(p), "--out", str(tmp_path / "out")]):
        r = nmm3d(*command, "--set", f"{key}={value}")
        assert r.returncode == EXIT_INPUT, (command, r.stdout, r.stderr)
        assert path in r.stderr and "finite" in r.stderr, r.stderr
        assert "Traceback" not in r.stderr
        assert sum(path in line for line in r.stderr.splitlines()) == 1, f"reported once: {r.stderr}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
def test_a_fifo_or_a_directory_as_scenario_is_refused_at_once(tmp_path):
    fifo = tmp_path / "scenario.toml"
    os.mkfifo(fifo)
    for target in (fifo, tmp_path):
        r = subprocess.run([sys.executable, "-m", "nmm3d", "check", str(target)], capture_output=True, text=True,
                           timeout=60)
        assert r.returncode == EXIT_INPUT, r.stderr
        assert "not a regular file" in r.stderr and "Traceback" not in r.stderr


def test_plot_makes_its_folder_and_refuses_foreign_tables(tmp_path):
    out = tmp_path / "run"
    assert nmm3d("run", str(write(tmp_path, GOOD)), "--out", str(out)).returncode == 0
    png = tmp_path / "figures" / "new" / "history.png"
    r = nmm3d("plot", str(out), "--out", str(png))
    assert r.returncode == 0, r.stderr
    assert png.is_file() and png.with_name("history_diagnostics.png").is_file()
    (out / "history.csv").write_bytes(b"time,step,cube.displacement.x\xff\n0,0,1\n")
    r = nmm3d("plot", str(out))
    assert r.returncode == EXIT_INPUT and "not the ones nmm3d writes" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


@pytest.mark.parametrize("override, key", [
    ("cover.size=1e-4", "cover.size"),
    ("joint_set.0.spacing=1e-12", "joint_set[0].spacing"),
    ("joint_set.0.spacing=5e-324", "joint_set[0].spacing"),
])
def test_a_model_beyond_the_memory_limit_is_refused_before_anything_is_built(tmp_path, override, key):
    text = GOOD.replace("[[body]]", '[[joint]]\nname = "j"\nfriction_angle = 30.0\n\n[[body]]', 1)
    text += '\n[[joint_set]]\ndip = 30.0\ndip_direction = 90.0\nspacing = 0.25\njoint = "j"\n'
    # The joints cut the cube into blocks: the monitor takes one by a point (a body of several is refused).
    text = text.replace('select = { body = "cube" }', "select = { point = [0.5, 0.5, 0.5] }")
    p = write(tmp_path, text)
    assert nmm3d("check", str(p)).returncode == 0
    for command in (["check", str(p)], ["run", str(p), "--out", str(tmp_path / "out")],
                    ["blocks", str(p), "--out", str(tmp_path / "blocks")]):
        r = subprocess.run([sys.executable, "-m", "nmm3d", *command, "--set", override], capture_output=True,
                           text=True, timeout=60)
        assert r.returncode == EXIT_INPUT, (command, r.stderr)
        assert f": {key}:" in r.stderr and "analysis.max_memory" in r.stderr, r.stderr
    # The limit is a key: a tight one refuses even the small model.
    r = nmm3d("check", str(p), "--set", "analysis.max_memory=1e3")
    assert r.returncode == EXIT_INPUT and "more than the" in r.stderr, r.stderr


def test_a_tunnel_of_billions_of_segments_is_refused_at_once(tmp_path):
    from conftest import EXAMPLES

    r = subprocess.run([sys.executable, "-m", "nmm3d", "check", str(EXAMPLES / "tunnel_key_blocks.toml"), "--set",
                        "excavation.0.shape.tunnel.segments=4294967295"], capture_output=True, text=True, timeout=60)
    assert r.returncode == EXIT_INPUT, r.stderr
    assert "excavation[0].shape.tunnel" in r.stderr and "10000" in r.stderr


MODEL_ERRORS = {
    # a monitor point in no block: found only once the blocks are cut
    "monitor": (GOOD.replace('select = { body = "cube" }', "select = { point = [5.0, 5.0, 5.0] }"),
                "monitor.cube.select.point"),
    # two bodies overlapping: found only by the first contact detection
    "overlap": (GOOD + '\n[[body]]\nname = "other"\nmaterial = "rock"\n'
                'shape = { box = { min = [0.5, 0.5, 0.5], max = [1.5, 1.5, 1.5] } }\n', "overlaps"),
}


@pytest.mark.parametrize("case", sorted(MODEL_ERRORS))
def test_check_refuses_what_run_refuses_once_the_model_is_built(tmp_path, case):
    """`check` builds what a run builds before its first step: both exit 2 with one message."""
    text, named = MODEL_ERRORS[case]
    p = write(tmp_path, text)
    checked, ran = nmm3d("check", str(p)), nmm3d("run", str(p), "--out", str(tmp_path / "out"))
    assert checked.returncode == ran.returncode == EXIT_INPUT, (checked.stdout, checked.stderr, ran.stderr)
    assert named in checked.stderr and "Traceback" not in checked.stderr, checked.stderr
    assert checked.stderr == ran.stderr


def test_check_reports_the_model_it_built(tmp_path):
    r = nmm3d("check", str(write(tmp_path, GOOD)))
    assert r.returncode == 0, r.stderr
    assert "the model: 1 blocks" in r.stdout and "MEs" in r.stdout


def test_a_study_refuses_a_model_no_run_could_start(tmp_path):
    """A monitor point in no block: the study exits 2 before its first run, as `check` does."""
    example = os.path.join(os.path.dirname(__file__), "..", "examples", "sliding_wedge.toml")
    point = "monitor.wedge.select={ point = [50.0, 50.0, 50.0] }"
    study = nmm3d("study", example, "--out", str(tmp_path / "study"), "--set", point, "--quiet")
    checked = nmm3d("check", example, "--set", point)
    assert study.returncode == checked.returncode == EXIT_INPUT, (study.stderr, checked.stderr)
    assert "monitor.wedge.select.point" in study.stderr and "Traceback" not in study.stderr, study.stderr
    assert not (tmp_path / "study" / "study.json").exists()
