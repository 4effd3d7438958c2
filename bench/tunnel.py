"""The thesis tunnel with its boundary conditions; writes docs/performance-tunnel.md.

Run: python bench/tunnel.py [--duration 2]

`examples/tunnel_key_blocks.toml` (horseshoe tunnel through three joint sets and three local
joints, every face but the top held, thesis Part 5) starts from its static equilibrium
(`initial_equilibrium = true`) and runs `--duration` seconds at the requested Δt = 1 ms:

* at the thesis's φ = 59°: the rock mass must rest;
* at φ = 25°, below the critical angle of its side-wall key block (block theory: block 24,
  0.041 m³, sliding on the local joint 28/024, φc = 28°) and above the roof key block's (22.6°):
  the wall block must slide out of the wall at block theory's acceleration
  g (sin δ − cos δ tan φ) along the joint's dip vector, then fall into the tunnel, while the
  rest stays put.

Per case: the initial equilibrium's iterations and unbalanced-force ratio, steps against the
requested Δt, step cuts, open–close iterations, factorisations, wall time and its split per
phase, the key block's motion against the closed form, energy balance and the deepest overlap.
Each case runs in its own process; the machine load is recorded. The key block's history is
plotted (docs/images/tunnel_key_block.png).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "tunnel_key_blocks.toml"
# The side-wall key block's centroid (block 24, `nmm3d keyblocks examples/tunnel_key_blocks.toml`)
# and its sliding joint.
KEY_POINT = [6.586, -0.959, -0.443]
JOINT_DIP, JOINT_DIP_DIRECTION = 28.0, 24.0
CRITICAL_ANGLE = JOINT_DIP  # sliding on one plane: φc = the plane's dip
G = 9.8
CASES = [("φ = 59° (thesis): rests", 59.0), ("φ = 25°: the wall key block slides out and falls", 25.0)]
PHASES = ["assembly", "contact_detection", "contact_pattern", "factorization", "krylov", "contact_open_close"]
KEYS = ("status", "steps", "step_cuts", "open_close_iterations", "wall_seconds", "timings", "final", "max_penetration",
        "step_diagnostics", "energy", "penalty_raises", "manifold_elements", "dofs", "blocks", "initial_equilibrium",
        "factorizations", "krylov_solves")


def run_case(phi: float, duration: float, out: str) -> dict:
    import nmm3d

    data = nmm3d.load(EXAMPLE, [f"joint.joint.friction_angle={phi}", f"analysis.duration={duration}"]).to_dict()
    data.pop("expect", None)
    data["monitor"].append({"name": "key", "select": {"point": KEY_POINT}, "quantities": ["displacement"]})
    result = nmm3d.Scenario.from_dict(data).run(out=out)
    row = {k: result.summary.get(k) for k in KEYS}
    h = result.history
    row["history"] = {k: [float(x) for x in h[k]] for k in h if k == "time" or k.startswith("key.")}
    return row


def measure(phi: float, duration: float) -> tuple[float, dict]:
    """One case in its own process: (load average when it started, its summary and history)."""
    load = os.getloadavg()[0]
    cmd = [sys.executable, __file__, "--duration", str(duration), "--phi", str(phi)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    row = json.loads(out.stdout.strip().splitlines()[-1])
    print(phi, row["steps"], row["wall_seconds"], file=sys.stderr)
    return load, row


def dip_vector() -> list[float]:
    """Unit vector down the joint's dip (x east, y north, z up)."""
    d, a = math.radians(JOINT_DIP), math.radians(JOINT_DIP_DIRECTION)
    return [math.cos(d) * math.sin(a), math.cos(d) * math.cos(a), -math.sin(d)]


def sliding(r: dict, phi: float) -> tuple[float, float, float] | None:
    """The key block's sliding before it leaves its joint: (time of the fit [s], acceleration
    measured / block theory's, angle between its path and the dip vector [°]); `None` if block
    theory says it holds. Fitted where the block has slid 1–5 cm (it leaves the joint later)."""
    a = G * (math.sin(math.radians(JOINT_DIP)) - math.cos(math.radians(JOINT_DIP)) * math.tan(math.radians(phi)))
    if a <= 0.0:
        return None
    h = r["history"]
    for i, t in enumerate(h["time"]):
        d = [h[f"key.displacement.{c}"][i] for c in "xyz"]
        dist = math.sqrt(sum(x * x for x in d))
        if dist >= 0.05 or (dist >= 0.01 and i == len(h["time"]) - 1):
            cos = sum(x * y for x, y in zip(d, dip_vector())) / dist
            return t, 2.0 * dist / (t * t) / a, math.degrees(math.acos(min(1.0, cos)))
    return None


def write(rows: list, duration: float) -> None:
    first = rows[0][2]
    lines = [
        "# Performance: the thesis tunnel (five faces held)",
        "",
        f"`python bench/tunnel.py --duration {duration:g}` — `examples/tunnel_key_blocks.toml` ({first['blocks']} blocks,",
        f"{first['manifold_elements']} MEs, {first['dofs']} DOFs; every face but the top held, as in the thesis), started",
        f"from its static equilibrium and run for {duration:g} s at the requested Δt = 1 ms ({round(duration / 1e-3)} steps).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores; load average when each case started in its row.",
        "Issue 10 measured before: `initial_equilibrium` diverged (\"overlap … even at the smallest",
        "time step\") and without it a simulated second took about 95 min.",
        "",
        "| case | load | initial equilibrium: iterations, unbalanced ratio | steps | cuts | Δt < 1 ms | iterations / step | factorisations | wall [s] | crown z [mm] | key block [mm] | energy balance error | deepest overlap [mm] |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, load, r in rows:
        f, ie = r["final"], r["initial_equilibrium"] or {}
        below = sum(b["steps"] for b in r["step_diagnostics"]["dt_histogram"] if b["to"] < 0.99e-3)
        key = math.sqrt(sum(f[f"key.displacement.{c}"] ** 2 for c in "xyz"))
        err = (r.get("energy") or {}).get("max_error_ratio")
        lines.append(
            f"| {label} | {load:.1f} | {ie.get('steps')}, {ie.get('unbalanced_force_ratio', float('nan')):.1e} | {r['steps']} | "
            f"{r['step_cuts']} | {below} | {r['open_close_iterations'] / r['steps']:.1f} | {r['factorizations']} | "
            f"{r['wall_seconds']:.0f} | {1e3 * f['crown.displacement.z']:.3f} | {1e3 * key:.1f} | "
            f"{'' if err is None else f'{100 * err:.1f} %'} | {1e3 * r['max_penetration']:.3f} |"
        )
    lines += ["", "Seconds per phase:", "", "| case | " + " | ".join(PHASES) + " |", "|---|" + "---|" * len(PHASES)]
    for label, _, r in rows:
        lines.append(f"| {label} | " + " | ".join(f"{r['timings'].get(k, 0.0):.1f}" for k in PHASES) + " |")
    lines += ["", "The key block against block theory while it slides on its joint (fitted where it has slid", "5 cm):", ""]
    lines += ["| case | at t [s] | acceleration / g (sin δ − cos δ tan φ) | angle to the dip vector [°] |", "|---|---|---|---|"]
    for label, _, r in rows:
        phi = next(p for name, p in CASES if name == label)
        fit = sliding(r, phi)
        if fit is None:
            why = "holds (φ ≥ φc)" if phi >= CRITICAL_ANGLE else "has not slid 1 cm"
            lines.append(f"| {label} | {why} | | |")
        else:
            lines.append(f"| {label} | {fit[0]:.3f} | {fit[1]:.3f} | {fit[2]:.2f} |")
    plot(rows)
    lines += [
        "",
        "![key block of the thesis tunnel](images/tunnel_key_block.png)",
        "",
        "Reading the table: \"iterations, unbalanced ratio\" are the static solve's Newton iterations",
        "with every joint locked and its final out-of-balance force relative to the weight; \"key",
        "block\" is the displacement of the wall key block's centroid (block 24) at the end; the balance error is the",
        "largest over the run relative to its largest account (5 % gets a warning in `summary.json`).",
        "",
    ]
    (ROOT / "docs" / "performance-tunnel.md").write_text("\n".join(lines))


def plot(rows: list) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    for label, _, r in rows:
        h = r["history"]
        dist = [math.sqrt(sum(h[f"key.displacement.{c}"][i] ** 2 for c in "xyz")) for i in range(len(h["time"]))]
        ax.plot(h["time"], dist, label=label)
    phi = CASES[1][1]
    a = G * (math.sin(math.radians(JOINT_DIP)) - math.cos(math.radians(JOINT_DIP)) * math.tan(math.radians(phi)))
    t = [i * 0.01 for i in range(101)]
    ax.plot(t, [0.5 * a * x * x for x in t], "k--", lw=1, label=f"block theory, sliding at φ = {phi:g}°")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("key block displacement [m]")
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "images" / "tunnel_key_block.png", dpi=120)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=2.0)
    p.add_argument("--phi", type=float, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.phi is not None:
        with tempfile.TemporaryDirectory() as d:
            print(json.dumps(run_case(args.phi, args.duration, d)))
        return
    write([(label, *measure(phi, args.duration)) for label, phi in CASES], args.duration)


if __name__ == "__main__":
    main()
