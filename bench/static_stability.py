"""The static stability check against the dynamic study: the tunnel key blocks' critical-friction
study (`bench/tunnel_key_blocks.py`'s, bisection over 10–45°) on dynamic runs of 1 s and on
static runs with `analysis.static_travel_limit`, back to back in one process each after the
other. Writes `docs/performance-static-stability.md`.

    python bench/static_stability.py [--tolerance 0.5] [--work DIR]
"""

from __future__ import annotations

import argparse
import os
import shutil
import tempfile
import time
from pathlib import Path

import nmm3d
from _page import write_page
from tunnel_key_blocks import CRITERION, CRITERION_TIME, EXAMPLE, classify, study, tunnel_profile

PAGE = Path(__file__).resolve().parent.parent / "docs" / "performance-static-stability.md"
#: The static runs: Δt only regularises; pseudo-time limit [s]; travel limit [m].
STATIC_DT, STATIC_TIME, TRAVEL_LIMIT = 1.0, 20.0, 2.0 * CRITERION


def run_study(d: dict, ids: list[int], tolerance: float, out: Path, t: float) -> dict:
    shutil.rmtree(out, ignore_errors=True)
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    s = study(d, ids, tolerance, out, time=t)
    s["wall"], s["load"] = time.perf_counter() - t0, load
    return s


def row(label: str, s: dict, names: dict[int, str]) -> str:
    brackets = {b["id"]: b["bracket"] for b in s["blocks"]}
    cells = [f"[{brackets[i][0]:.2f}°, {brackets[i][1]:.2f}°]" for i in names]
    return f"| {label} | {s['runs']} | {s['run_seconds']:.0f} | {s['wall']:.0f} | {s['load']:.1f} | " + " | ".join(cells) + " |"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--tolerance", type=float, default=0.5)
    p.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "nmm3d_static_stability")
    args = p.parse_args()
    load0 = os.getloadavg()[0]
    d = nmm3d.load(EXAMPLE).to_dict()
    half, _, crown = tunnel_profile(d)
    key = classify(nmm3d.keyblocks(EXAMPLE), half, crown)
    names = {b.id: f"{name} block {b.id}" for name, b in key.items()}
    dynamic = run_study(d, list(names), args.tolerance, args.work / "dynamic", CRITERION_TIME)
    print("dynamic", dynamic["run_seconds"], dynamic["wall"], flush=True)
    ds = nmm3d.load(EXAMPLE).to_dict()
    ds["analysis"].update(kind="static", dt=STATIC_DT, static_travel_limit=TRAVEL_LIMIT)
    static = run_study(ds, list(names), args.tolerance, args.work / "static", STATIC_TIME)
    print("static", static["run_seconds"], static["wall"], flush=True)
    head = " | ".join(names.values())
    write_page(PAGE, "Static stability check against the dynamic study: the tunnel's key blocks",
               "static_stability.py", load0, [
        f"`examples/tunnel_key_blocks.toml`, per-block critical friction (`nmm3d study`, bisection over 10–45° "
        f"to {args.tolerance:g}°; a block has failed when its centroid has moved {CRITERION:g} m). Dynamic: "
        f"{CRITERION_TIME:g} s of motion per run (as `docs/applications/tunnel-key-blocks.md`). Static: "
        f"`analysis.kind = \"static\"`, Δt = {STATIC_DT:g} (a regulariser), pseudo-time limit {STATIC_TIME:g} s, "
        f"`analysis.static_travel_limit = {TRAVEL_LIMIT:g}` m: each run releases the blocks beyond it (no contact "
        "points on them), pins them where they crossed it and stops once the others are in equilibrium "
        "(`docs/user-guide.md`, *Static or dynamic*). The two studies ran one after the other, two runs at "
        "a time each.",
        "",
        f"| runs | number | run seconds | study wall [s] | load at start | {head} |",
        "|---|---:|---:|---:|---:|" + "---|" * len(names),
        row(f"dynamic, {CRITERION_TIME:g} s per run", dynamic, names),
        row(f"static, travel limit {TRAVEL_LIMIT:g} m", static, names),
        "",
        f"Static against dynamic: **{dynamic['run_seconds'] / static['run_seconds']:.1f}×** less run time, "
        f"{dynamic['wall'] / static['wall']:.1f}× less study wall time. Block theory (`nmm3d keyblocks`): "
        + ", ".join(f"{names[b.id]} {b.mode.critical_friction_angle:.1f}°" for b in key.values()
                    if b.mode.critical_friction_angle is not None)
        + ". Why the roof block's brackets differ: `docs/theory/contact.md` (*Joint elements*).",
    ])


if __name__ == "__main__":
    main()
