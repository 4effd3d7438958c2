"""Rock slope benchmark (thesis case A, φ = 10°); writes docs/performance-rock-slope.md.

Run: python bench/rock_slope.py [--duration 0.3]

`examples/rock_slope.toml` at φ = 10° (47 blocks sliding on a 35° slope) for `--duration`
seconds of simulated time, with the open–close controls of the defaults and of the example:
steps taken against the requested Δt = 1 ms, step cuts, open–close iterations, wall time and
its split per phase, and the toe block's displacement (the same motion is the condition for
any speed-up). Each case runs in its own process; the machine load is recorded.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "rock_slope.toml"
CASES = {
    "defaults (exact settling, 12 iterations, then cut)": ["analysis.open_close_tolerance=0", "analysis.max_open_close=12"],
    "force tolerance 1e-3, 12 iterations": ["analysis.open_close_tolerance=1e-3", "analysis.max_open_close=12"],
    "the example: force tolerance 1e-3, 25 iterations": [],
}
PHASES = ["assembly", "contact_warning", "contact_detection", "contact_pattern", "factorization", "contact_open_close", "solve"]


def run_case(overrides: list[str], duration: float, out: str) -> dict:
    import nmm3d

    sets = ["joint.rock_joint.friction_angle=10", f"analysis.duration={duration}", *overrides]
    s = nmm3d.load(EXAMPLE, sets).run(out=out).summary
    return {k: s[k] for k in ("status", "steps", "step_cuts", "open_close_iterations", "wall_seconds", "timings", "final", "max_penetration")}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=0.3)
    p.add_argument("--case", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.case is not None:
        with tempfile.TemporaryDirectory() as d:
            print(json.dumps(run_case(json.loads(args.case), args.duration, d)))
        return
    rows = []
    for name, overrides in CASES.items():
        load = os.getloadavg()[0]
        out = subprocess.run([sys.executable, __file__, "--duration", str(args.duration), "--case", json.dumps(overrides)], check=True, capture_output=True, text=True)
        rows.append((name, load, json.loads(out.stdout.strip().splitlines()[-1])))
        print(name, rows[-1][2]["steps"], rows[-1][2]["wall_seconds"], file=sys.stderr)
    write(rows, args.duration)


def write(rows: list, duration: float) -> None:
    ideal = round(duration / 1e-3)
    lines = [
        "# Performance: the rock slope (thesis case A)",
        "",
        f"`python bench/rock_slope.py --duration {duration}` — `examples/rock_slope.toml` at φ = 10°",
        f"(47 blocks on a 35° slope, 15 847 MEs, 2 766 DOFs) for {duration} s simulated; requested Δt = 1 ms",
        f"({ideal} steps). Machine: {platform.machine()}, {os.cpu_count()} cores; load average when each",
        "case started in its row. Earlier measurement (issue 10, before these controls): 0.3 s took",
        "2 753 steps, 417 cuts and 865 s.",
        "",
        "| open–close controls | load | steps | cuts | iterations / step | wall [s] | toe x [mm] | toe z [mm] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, load, r in rows:
        f = r["final"]
        lines.append(
            f"| {name} | {load:.1f} | {r['steps']} | {r['step_cuts']} | {r['open_close_iterations'] / r['steps']:.1f} | {r['wall_seconds']:.0f} | "
            f"{1e3 * f['toe_block.displacement.x']:.2f} | {1e3 * f['toe_block.displacement.z']:.2f} |"
        )
    lines += ["", "Seconds per phase (factorisations of the open–close iterations beyond the first are in both", "`factorization` and `contact_open_close`):", ""]
    lines.append("| open–close controls | " + " | ".join(PHASES) + " |")
    lines.append("|---|" + "---|" * len(PHASES))
    for name, _, r in rows:
        lines.append(f"| {name} | " + " | ".join(f"{r['timings'].get(k, 0.0):.1f}" for k in PHASES) + " |")
    lines += [
        "",
        "What the numbers say: the faces between neighbouring blocks flip between stick, slide and",
        "open at nearly zero force, so exact settling cycles and a cut step does not help; settling",
        "on the contact forces and allowing more iterations keeps the requested step with the same",
        "motion. Each open–close iteration is still a numeric factorisation of a dense-ish factor,",
        "which is now most of the time (`docs/theory/contact.md`).",
        "",
    ]
    (ROOT / "docs" / "performance-rock-slope.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
