"""docs/walkthrough.md: every command in its bash blocks runs, in order, and says what the page says."""

from __future__ import annotations

import csv
import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

PAGE = ROOT / "docs" / "walkthrough.md"


def commands() -> list[str]:
    blocks = re.findall(r"```bash\n(.*?)```", PAGE.read_text(), flags=re.S)
    return [line.strip() for b in blocks for line in b.splitlines() if line.strip()]


def argv(command: str) -> list[str]:
    words = shlex.split(command)
    head = {"nmm3d": [sys.executable, "-m", "nmm3d"], "python": [sys.executable]}
    assert words[0] in head, f"the walk-through may only use nmm3d and python: {command}"
    return head[words[0]] + words[1:]


@pytest.fixture(scope="module")
def walked(tmp_path_factory) -> tuple[Path, dict[str, str]]:
    here = tmp_path_factory.mktemp("walk")
    for d in ("examples", "docs"):
        (here / d).symlink_to(ROOT / d)
    printed = {}
    for c in commands():
        if "picture.py" in c:
            pytest.importorskip("pyvista")
        r = subprocess.run(argv(c), cwd=here, capture_output=True, text=True, timeout=900)
        assert r.returncode == 0, f"{c}\n{r.stderr}"
        printed[c] = r.stdout
    return here, printed


def test_the_page_has_every_step():
    text = " ".join(commands())
    for step in ("nmm3d check", "nmm3d blocks", "nmm3d run", "nmm3d plot", "picture.py", "nmm3d study",
                 "two_wedges.toml", "nmm3d keyblocks"):
        assert step in text, step


def test_every_command_runs_and_gives_what_the_page_says(walked):
    here, printed = walked
    out = here / "out"
    with open(out / "slope_blocks" / "blocks.csv", newline="") as f:
        layer = [float(r["volume"]) for r in csv.DictReader(f) if r["body"] == "layer"]
    # "45 blocks of 1.23 m³ on average in the layer, 0.41 to 2.72 m³"
    assert len(layer) == 45 and round(sum(layer) / len(layer), 2) == 1.23
    assert (round(min(layer), 2), round(max(layer), 2)) == (0.41, 2.72)
    assert json.loads((out / "slope" / "summary.json").read_text())["status"] == "completed"
    for png in ("slope_blocks/stereonet.png", "slope/history.png", "slope/diagnostics.png", "slope.png",
                "wedge_study/study.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG", png
    study = json.loads((out / "wedge_study" / "study.json").read_text())
    closed = next(v for k, v in printed.items() if "critical_friction_angle" in k)
    assert "vector method: 31.81 deg" in closed
    lo, hi = study["bracket"]
    assert hi - lo <= 2.0 and lo - 1.0 < 31.81 < hi + 1.0


def test_key_blocks_get_their_own_critical_angles(walked):
    here, printed = walked
    study = json.loads((here / "out" / "key_blocks" / "study.json").read_text())
    found = {b["id"]: b for b in study["blocks"]}
    closed = next(v for k, v in printed.items() if "A {c(" in k)
    assert "A 31.81 deg, B 25.15 deg" in closed
    # The page's numbers: A (block 1) 31.85°, B (block 4) 25.19°, each within its bracket of the
    # vector method (the search stops when the bracket is narrower than the tolerance, 1°).
    for block, exact in ((1, 31.81), (4, 25.15)):
        lo, hi = found[block]["bracket"]
        assert hi - lo <= 1.0 and lo - 0.5 < exact < hi + 0.5, (block, found[block])


def test_block_theory_agrees_with_the_per_block_study(walked):
    """The key-block module's critical angles (limit equilibrium) lie in the NMM study's brackets,
    widened by the study's 1° tolerance."""
    here, printed = walked
    study = {b["id"]: b for b in json.loads((here / "out" / "key_blocks" / "study.json").read_text())["blocks"]}
    with open(here / "out" / "key_blocks_le" / "keyblocks.csv", newline="") as f:
        rows = {int(r["id"]): r for r in csv.DictReader(f)}
    shown = next(v for k, v in printed.items() if "nmm3d keyblocks" in k)
    assert "2 key blocks" in shown
    for block in (1, 4):
        lo, hi = study[block]["bracket"]
        critical = float(rows[block]["critical_friction_angle"])
        assert rows[block]["mode"] == "sliding_two_planes" and lo - 1.0 < critical < hi + 1.0
        assert f"{critical:.3f}" in shown
