"""Cutting benchmark; writes docs/performance-cutting.md. Run: python bench/cutting.py [--spacings 5 4 2 1]

A 100 m cube cut by three joint sets (50/130, 45/045, 76/090) at one spacing: time and peak
memory for cutting, and for cutting + building hex8 covers of 5 m cells. Each case runs in its
own process (peak memory = that process's maximum resident set).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CASE = r'''
import json, resource, sys, time
import nmm3d
from nmm3d import _core
spacing, covers = float(sys.argv[1]), sys.argv[2] == "covers"
sets = [{"dip": d, "dip_direction": a, "spacing": spacing, "origin": [0.3, 0.7, 1.1]} for d, a in ((50, 130), (45, 45), (76, 90))]
scenario = nmm3d.Scenario.from_dict({
    "material": [{"name": "rock", "density": 2600.0, "young": 1e10, "poisson": 0.25}],
    "body": [{"name": "cube", "material": "rock", "shape": {"box": {"min": [0, 0, 0], "max": [100, 100, 100]}}}],
    "joint_set": sets, "cutting": {"sliver_ratio": 1e-4},
    "cover": {"pattern": "hex8", "size": 5.0},
})
t0 = time.perf_counter()
if covers:
    r = json.loads(_core.cover_report_json(scenario._json, "bench"))
else:
    b = scenario.blocks()
    r = {"blocks": len(b["id"]), "cutting_seconds": time.perf_counter() - t0}
r["wall"] = time.perf_counter() - t0
r["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps(r))
'''


def run(spacing: float, covers: bool, timeout: float) -> dict | None:
    try:
        p = subprocess.run([sys.executable, "-c", CASE, str(spacing), "covers" if covers else "cut"],
                           capture_output=True, text=True, timeout=timeout, check=True)
    except subprocess.TimeoutExpired:
        return None
    return json.loads(p.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--spacings", type=float, nargs="*", default=[5.0, 4.0, 2.0, 1.0])
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per case")
    args = ap.parse_args()
    rows = []
    for s in args.spacings:
        cut = run(s, False, args.timeout)
        cov = run(s, True, args.timeout) if s >= 2.0 else None
        rows.append((s, cut, cov))
        print(s, cut, cov, flush=True)
    lines = ["# Performance: cutting", "",
             f"Produced by `python bench/cutting.py` (do not edit by hand). Machine: {platform.machine()}, "
             f"{os.cpu_count()} cores.", "",
             "A 100 m cube cut by three joint sets (50/130, 45/045, 76/090) at one spacing. `cutting`: building",
             "the blocks (`Scenario.blocks()`); `covers`: cutting plus hex8 covers of 5 m cells (manifold",
             "elements and physical covers, no element matrices). Peak memory of each case's process.", "",
             "| spacing [m] | blocks | cutting [s] | peak MB | MEs | physical covers | covers [s] | peak MB (cut + covers) |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for s, cut, cov in rows:
        if cut is None:
            lines.append(f"| {s:g} | – | timed out | – | – | – | – | – |")
            continue
        c = (f"{cov['manifold_elements']:,} | {cov['physical_covers']:,} | {cov['covers_seconds']:.2f} | {cov['peak_mb']:.0f}"
             if cov else "– | – | – | –")
        lines.append(f"| {s:g} | {cut['blocks']:,} | {cut['cutting_seconds']:.2f} | {cut['peak_mb']:.0f} | {c} |")
    done = [(s, c) for s, c, _ in rows if c]
    if len(done) >= 2:
        (_, a), (_, b) = done[0], done[-1]
        import math
        k = math.log(b["cutting_seconds"] / a["cutting_seconds"]) / math.log(b["blocks"] / a["blocks"])
        lines += ["", f"Cutting time grows as (blocks)^{k:.2f} between {a['blocks']:,} and {b['blocks']:,} blocks."]
    lines += ["", "Target (issue 3): at 2 m (about 125 000 blocks) cutting < 10 s and < 2 GB on 2 cores.", ""]
    (ROOT / "docs" / "performance-cutting.md").write_text("\n".join(lines))
    print("wrote docs/performance-cutting.md")


if __name__ == "__main__":
    main()
