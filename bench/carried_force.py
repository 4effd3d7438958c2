"""A joint's force carried across detections on soft joints; writes docs/carried-force.md and
docs/images/carried-force.png.

Run: python bench/carried_force.py [--duration 3]

Thesis case A (`examples/rock_slope.toml`, φ = 10°) on joints of 10 MPa/m, where the collapsing
layer's blocks strike each other and pass centimetres into each other: once with each joint's
points carrying the total force k_n A g (`contact.carry_joint_force = false`) and once with the
force carried across a detection and into arrivals (the default; docs/theory/contact.md, "A
joint's force carried across a detection"), back to back. *Made*: the energy the contact events
created — the steps whose contact-event account fell, summed.
"""

from __future__ import annotations

import argparse
import csv
import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _page import write_page  # noqa: E402
from _run import run_scenario  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "carried-force.md"
FIGURE = ROOT / "docs" / "images" / "carried-force.png"
SLOPE = ROOT / "examples" / "rock_slope.toml"
SOFT = ["joint.rock_joint.friction_angle=10", "joint.rock_joint.normal_stiffness=1e7",
        "joint.rock_joint.shear_stiffness=1e7"]


def made_over_time(out: Path) -> dict:
    """Time [s] and the energy made so far [J] (falls of the contact-event account, summed)."""
    with open(out / "diagnostics.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    times, made, total, last = [], [], 0.0, 0.0
    for r in rows:
        account = float(r["contact_event_dissipation"])
        total += max(last - account, 0.0)
        last = account
        times.append(float(r["time"]))
        made.append(total)
    return {"times": times, "made": made, "work": max(float(r["external_work"]) for r in rows)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=3.0, help="simulated time [s]")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    runs = []
    for carry, label in [(False, "total force"), (True, "carried (default)")]:
        sets = SOFT + [f"analysis.duration={args.duration}", f"contact.carry_joint_force={str(carry).lower()}"]
        s = run_scenario(SLOPE, sets, made_over_time)
        runs.append((label, s))
        print(label, f"made {s['made'][-1]:.4g} J in {s['wall']:.0f} s", flush=True)
    rows = [
        f"| {label} | {s['made'][-1] / 1e6:.3f} | {s['energy']['contact_event_dissipation'] / 1e6:+.3f} | "
        f"{s['work'] / 1e6:.2f} | {s['free_fall']['max_ratio']:.2f} | {s['max_penetration']:.3f} | "
        f"{s['carried_joint_forces']:,} | {s['steps']} | {s['step_cuts']} | {s['open_close_iterations']:,} | "
        f"{s['wall']:.0f} |"
        for label, s in runs
    ]
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for label, s in runs:
        ax.plot(s["times"], [m / 1e6 for m in s["made"]], label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("energy made at contact events [MJ]")
    ax.set_title("Thesis slope, φ = 10°, joints of 10 MPa/m")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    FIGURE.parent.mkdir(exist_ok=True)
    fig.savefig(FIGURE, dpi=120)
    write_page(PAGE, "A joint's force carried across detections, on soft joints", "carried_force.py", load0, [
        f"Thesis case A (`examples/rock_slope.toml`, φ = 10°) on joints of k_n = k_s = 10 MPa/m for "
        f"{args.duration:g} s: the layer collapses and its blocks strike each other, centimetres to decimetres",
        "into each other on springs this soft. *Total force*: each point's spring pushes k_n A g however the",
        "detection found it (`contact.carry_joint_force = false`); *carried*: a pair found again pushes no",
        "harder than its points did, and a point that arrives within a step pushes from where it was at the",
        "step's start (the default; [theory/contact.md](theory/contact.md#a-joints-force-carried-across-a-detection)).",
        "*Made*: the energy the contact events created — the steps whose contact-event account fell, summed;",
        "*account*: the contact-event account at the end (negative: energy from nowhere); *work*: gravity's;",
        "*free fall*: the largest block speed over the free-fall bound; *lifted*: `carried_joint_forces`.",
        "",
        "| joints | made [MJ] | account [MJ] | work [MJ] | free fall | deepest overlap [m] | lifted | steps | cuts "
        "| open–close iterations | wall [s] |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows,
        "",
        "![Energy made at contact events over time, total against carried force](images/carried-force.png)",
    ])
    print(f"wrote {PAGE.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
