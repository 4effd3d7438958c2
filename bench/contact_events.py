"""Contact events and factor reuse; writes docs/performance-contact-events.md.

Run: python bench/contact_events.py

Two measurements of issue 10's contact work, each case in its own process, back to back:

* the two-end dominos (`examples/dominos.toml`, 5 s) on tet6 and hex8 covers, with the lagged
  verification of contacts (`contact.arrival_rounds = 3`, the default) and without it (0): the
  energy accounts (balance error, contact-event dissipation, the most negative step of
  D_n + D_c — energy a step gave the blocks at its contacts), the largest overlap, wall time;
* the tunnel at rest (`examples/tunnel_key_blocks.toml`, five faces held, 1 s) with factor
  reuse by closeness (`analysis.factor_reuse_closeness = 1e-6`, the default) and without it (0):
  factorisations, PCG solves, solve time, wall time, and the largest difference of the monitored
  displacements between the two.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DOMINOS = [
    (f"{pattern}, {label}", "dominos.toml", [f"cover.pattern={pattern}", f"contact.arrival_rounds={rounds}"])
    for pattern in ("tet6", "hex8")
    for label, rounds in (("lagged verification", 3), ("without it", 0))
]
TUNNEL = [
    ("factor reuse by closeness (1e-6) until its PCG iterations cost a factorisation", "tunnel_key_blocks.toml", []),
    ("closeness off (0): only identical matrices on the factor", "tunnel_key_blocks.toml", ["analysis.factor_reuse_closeness=0"]),
]


def run_case(example: str, overrides: list[str], out: str) -> dict:
    import nmm3d

    result = nmm3d.load(ROOT / "examples" / example, overrides).run(out=out)
    s = result.summary
    with open(result.directory / "diagnostics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    taken = [float(r["numerical_dissipation"]) + float(r["contact_event_dissipation"]) for r in rows]
    steps = [b - a for a, b in zip(taken, taken[1:])]
    worst = min(steps, default=0.0)
    worst_pair = min((a + b for a, b in zip(steps, steps[1:])), default=0.0)
    displacements = [c for c in result.history if ".displacement." in c]
    return {
        "steps": s["steps"], "wall": s["wall_seconds"], "overlap": s["max_penetration"], "energy": s["energy"],
        "worst_step": worst, "worst_pair": worst_pair, "worst_time": float(rows[1 + steps.index(worst)]["time"]) if steps else 0.0,
        "factorizations": s["factorizations"], "krylov_solves": s["krylov_solves"],
        "krylov_iterations": s["krylov_iterations"], "krylov_failures": s["krylov_failures"],
        "solving": s["timings"].get("factorization", 0.0) + s["timings"].get("krylov", 0.0),
        "history": {c: [float(x) for x in result.history[c]] for c in displacements},
    }


def measure(example: str, overrides: list[str]) -> tuple[float, dict]:
    """One case in its own process: (load average when it started, its row)."""
    load = os.getloadavg()[0]
    cmd = [sys.executable, __file__, "--case", json.dumps([example, overrides])]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    print(example, overrides, row["steps"], row["wall"], file=sys.stderr)
    return load, row


def largest_difference(a: dict, b: dict) -> tuple[float, float]:
    """Largest difference of the monitored displacements of two runs, and their largest value."""
    diff = max(max(abs(x - y) for x, y in zip(a[c], b[c])) for c in a)
    scale = max(max(abs(x) for x in a[c]) for c in a)
    return diff, scale


def write(dominos: list, tunnel: list) -> None:
    lines = [
        "# Performance: contact events and factor reuse",
        "",
        f"`python bench/contact_events.py`. Machine: {platform.machine()}, {os.cpu_count()} cores; the load",
        "average when each case started is in its row. Theory: [theory/contact.md](theory/contact.md)",
        "(approaching corners, lagged verification), [theory/energy.md](theory/energy.md) (contact",
        "events), [theory/solver.md](theory/solver.md) (reuse by closeness).",
        "",
        "## Dominos, 5 s: energy at the contacts",
        "",
        "\"Worst step\" is the most negative D_n + D_c of one step: energy the step gave the blocks at",
        "its contacts (at the time given); \"worst two steps\" the most negative sum over two steps in a",
        "row. Where one step's value is large and the pair's small, the step did not create the energy:",
        "its split between the scheme's dissipation D_n and the contact events D_c swings between",
        "consecutive steps of a vibrating block, and the next step takes it back. The balance error is",
        "relative to the largest account (positive: energy lost).",
        "",
        "| case | load | steps | balance error | contact events D_c [J] | worst step [J] (t [s]) | worst two steps [J] | largest overlap [mm] | wall [s] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, load, r in dominos:
        e = r["energy"]
        ratio = e["error"] / max(abs(v) for k, v in e.items() if isinstance(v, float) and k not in ("error", "max_error_ratio", "max_error_time"))
        lines.append(f"| {name} | {load:.1f} | {r['steps']} | {100 * ratio:+.1f} % | {e['contact_event_dissipation']:.1f} | "
                     f"{r['worst_step']:.3f} ({r['worst_time']:.3f}) | {r['worst_pair']:.3f} | {1e3 * r['overlap']:.3f} | {r['wall']:.1f} |")
    diff, scale = largest_difference(tunnel[0][2]["history"], tunnel[1][2]["history"])
    lines += [
        "",
        "## Tunnel at rest, 1 s: factorisations",
        "",
        "| case | load | steps | factorisations | PCG solves | PCG iterations | PCG fell back | solving [s] | wall [s] |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, load, r in tunnel:
        lines.append(f"| {name} | {load:.1f} | {r['steps']} | {r['factorizations']} | {r['krylov_solves']} | {r['krylov_iterations']} | "
                     f"{r['krylov_failures']} | {r['solving']:.1f} | {r['wall']:.1f} |")
    lines += [
        "",
        f"Largest difference of the monitored displacements between the two: {diff:.2e} m "
        f"({diff / scale:.1e} of the largest, {scale:.2e} m).",
        "",
    ]
    (ROOT / "docs" / "performance-contact-events.md").write_text("\n".join(lines))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--case", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.case is not None:
        example, overrides = json.loads(args.case)
        with tempfile.TemporaryDirectory() as d:
            print(json.dumps(run_case(example, overrides, d)))
        return
    dominos = [(name, *measure(example, o)) for name, example, o in DOMINOS]
    tunnel = [(name, *measure(example, o)) for name, example, o in TUNNEL]
    write(dominos, tunnel)


if __name__ == "__main__":
    main()
