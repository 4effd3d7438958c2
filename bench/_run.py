"""One scenario run the way a user runs it (`python -m nmm3d run … --quiet --set …`) in a
temporary directory: its summary and wall time, and whatever `read` takes from its outputs."""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path


def run_scenario(scenario: Path, sets: list[str], read: Callable[[Path], dict] | None = None) -> dict:
    """`summary.json` with `wall` [s] added, and `read(out)` for the run's output directory."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        args = [a for s in sets for a in ("--set", s)]
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-m", "nmm3d", "run", str(scenario), "--out", str(out), "--quiet", *args],
                       check=True, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        summary = json.loads((out / "summary.json").read_text())
        extra = read(out) if read else {}
    return {**summary, "wall": wall, **extra}
