"""Studies against their closed forms, and the speed-up from 1 to 2 Dask workers.

Usage: python bench/study.py [OUT]   (default bench/results/study) → docs/studies-results.md and
the pyramid's plots in docs/images/

Runs the critical-friction and strength-reduction studies of the wedge examples (the same
studies the test suite checks) and one study on 1 and on 2 local workers, back to back.
"""

from __future__ import annotations

import math
import os
import shutil
import sys
import time
from pathlib import Path

import nmm3d
from nmm3d import roof_wedge
from nmm3d.wedge import critical_friction_angle, wedge

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
PLANES = (50.0, 130.0), (50.0, 230.0)
C1 = roof_wedge.RoofWedge(30.0, 2000.0 * 10.0 * math.sqrt(3.0) / 3.0, 3.0 * 2.0 / math.sqrt(3.0), 5e4)
PRISM = roof_wedge.prism(1.0, math.sqrt(3.0), 4.0, 2000.0, 10.0, 5e4)
PYRAMID = roof_wedge.pyramid(1.0, math.sqrt(3.0), 2000.0, 10.0, 5e4)
SRM = ['study.kind="strength_reduction"', "study.range=[0.8, 1.8]", "study.tolerance=0.02"]

CASES = [  # (label, example, overrides, quantity, closed form)
    ("tetrahedral wedge 50/130 + 50/230, vector method", "tetrahedral_wedge.toml", [], "critical_friction_angle",
     critical_friction_angle(*PLANES)),
    ("roof wedge C1, three faces (3DEC falling wedge)", "roof_wedge.toml", [], "critical_friction_angle",
     C1.critical_friction_angle()),
    ("roof wedge, four-faced pyramid (tet6)", "roof_wedge_pyramid.toml", [], "critical_friction_angle",
     PYRAMID.critical_friction_angle()),
    ("roof wedge, two-faced prism (hex8)", "roof_wedge_prism.toml", [], "critical_friction_angle",
     PRISM.critical_friction_angle()),
    ("roof wedge, two-faced prism on tet6 (rocks: see above)", "roof_wedge_prism.toml", ['cover.pattern="tet6"'],
     "critical_friction_angle", PRISM.critical_friction_angle()),
    ("tetrahedral wedge at φ = 40°, strength reduction", "tetrahedral_wedge.toml",
     [*SRM, "joint.j.friction_angle=40.0"], "factor_of_safety", wedge(*PLANES, 40.0).factor_of_safety),
    ("roof wedge pyramid at φ = 45°, strength reduction", "roof_wedge_pyramid.toml",
     [*SRM, "joint.j.friction_angle=45.0"], "factor_of_safety", PYRAMID.factor_of_safety(45.0)),
    ("roof wedge prism at φ = 45°, strength reduction", "roof_wedge_prism.toml",
     [*SRM, "joint.j.friction_angle=45.0"], "factor_of_safety", PRISM.factor_of_safety(45.0)),
]


FIGURES = {2: "study_pyramid_critical_friction.png", 6: "study_pyramid_strength_reduction.png"}  # case → name


def fresh(path: Path) -> Path:
    shutil.rmtree(path, ignore_errors=True)
    return path


def timed(example: str, out: Path, overrides: list[str], workers: int) -> tuple[nmm3d.StudyResult, float]:
    t0 = time.perf_counter()
    result = nmm3d.Study(EXAMPLES / example, fresh(out), overrides).run(workers=workers)
    return result, time.perf_counter() - t0


def main() -> None:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "bench" / "results" / "study"
    lines = ["# Studies: measured", "", "Written by `python bench/study.py` on this machine "
             f"({os.cpu_count()} cores; load average before the runs {os.getloadavg()[0]:.2f}).", "",
             "## Against closed forms", "",
             "| case | quantity | closed form | study | difference | bracket | runs |", "|---|---|---|---|---|---|---|"]
    for i, (label, example, overrides, key, exact) in enumerate(CASES):
        r, _ = timed(example, out / f"case{i}", overrides, workers=2)
        if i in FIGURES:
            shutil.copyfile(r.directory / "study.png", ROOT / "docs" / "images" / FIGURES[i])
        s = r.summary
        v = s.get(key)
        diff = "—" if v is None else (f"{v - exact:+.3f}°" if key == "critical_friction_angle" else f"{100 * (v / exact - 1):+.2f} %")
        lo, hi = s["bracket"]
        unit = "°" if key == "critical_friction_angle" else ""
        lines.append(f"| {label} | {key.replace('_', ' ')} | {exact:.3f}{unit} | "
                     f"{'—' if v is None else f'{v:.3f}{unit}'} | {diff} | {lo:.3f}–{hi:.3f} | {s['runs']} |")
        print(lines[-1], flush=True)
    lines += ["", "## Speed-up from 1 to 2 workers", "",
              "The critical-friction study of `examples/roof_wedge_pyramid.toml` (10 runs of 1 s simulated), "
              "run on a local Dask cluster with 1 and then 2 worker processes, back to back; each worker's "
              "Rust threads are the cores divided by the workers.", "",
              "| workers | wall [s] | sum of run walls [s] | speed-up |", "|---|---|---|---|"]
    base = None
    for workers in (1, 2):
        r, wall = timed("roof_wedge_pyramid.toml", out / f"speed{workers}", [], workers)
        runs = sum(float(x) for x in r.table["wall_seconds"])
        base = base or wall
        lines.append(f"| {workers} | {wall:.1f} | {runs:.1f} | {base / wall:.2f}× |")
        print(lines[-1], flush=True)
    lines += ["", "Both give the same `study.json` (also a test: `tests/test_study.py`).", ""]
    (ROOT / "docs" / "studies-results.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
