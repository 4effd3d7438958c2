"""The locked and the frictional initial equilibrium side by side; writes
`docs/performance-initial-equilibrium.md`.

    python bench/initial_equilibrium.py [--duration 0.05]

The thesis tunnel (`examples/tunnel_key_blocks.toml`, five faces held) on its own contact
spring and on physical joint stiffnesses, started from each method and run on for `--duration`
seconds: the settling's steps and whether it converged, the roof key block's settlement at the
release and its motion after it, the largest kinetic energy after the release (a start at rest
has none), wall time. The locked settling of joints of 10⁷ Pa/m is bounded by
`max_settle_steps = 500` here (unbounded it ran 285–436 s, unconverged); at 10⁶ Pa/m only the
frictional one runs. Then the thesis slope at φ = 45° on four joint stiffnesses (its locked
settling bounded at 500 damped steps), and the 3DEC sliding wedge (10 MPa/m joints) just above
its critical angle from both starts. Every frictional settling at the default `settle_dt`. One
case after the other in this process.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

import nmm3d
from _page import write_page

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "performance-initial-equilibrium.md"
TUNNEL = ROOT / "examples" / "tunnel_key_blocks.toml"
WEDGE = ROOT / "examples" / "sliding_wedge.toml"
# (label, joint normal stiffness [Pa/m] or None for the example's contact spring,
# [(method, its extra settings)]).
TUNNEL_CASES = [
    ("the example's contact spring", None, [("locked", []), ("frictional", [])]),
    ("10⁸ Pa/m", 1e8, [("locked", []), ("frictional", [])]),
    ("10⁷ Pa/m", 1e7, [("locked", ["analysis.max_settle_steps=500"]), ("frictional", [])]),
    ("10⁶ Pa/m", 1e6, [("frictional", [])]),
]
SLOPE = ROOT / "examples" / "rock_slope.toml"
SLOPE_FRICTION = 45.0
# Locked settling bounded at 500 damped steps.
SLOPE_LOCKED = ("locked", ["analysis.max_settle_steps=500"])
SLOPE_CASES = [
    ("10⁹ Pa/m", 1e9, [SLOPE_LOCKED, ("frictional", [])]),
    ("10⁸ Pa/m", 1e8, [SLOPE_LOCKED, ("frictional", [])]),
    ("10⁷ Pa/m", 1e7, [SLOPE_LOCKED, ("frictional", [])]),
    ("10⁶ Pa/m", 1e6, [SLOPE_LOCKED, ("frictional", [])]),
]
# The sliding wedge's critical friction angle (vector method) and the margins above it [°].
WEDGE_CRITICAL, WEDGE_MARGINS = 33.357, [1.0, 0.1]


def run(path: Path, sets: list[str], out: Path) -> tuple[dict, pd.DataFrame, pd.DataFrame]:
    r = nmm3d.load(str(path), sets).run(out=str(out))
    return r.summary, pd.read_csv(out / "history.csv"), pd.read_csv(out / "diagnostics.csv")


def motion(history: pd.DataFrame, name: str) -> tuple[float, float]:
    """`name`'s displacement at the release and its motion after it [m]."""
    cols = [f"{name}.displacement.{c}" for c in "xyz"]
    start, end = history[cols].iloc[0].to_numpy(), history[cols].iloc[-1].to_numpy()
    return float(np.linalg.norm(start)), float(np.linalg.norm(end - start))


def case_row(label: str, method: str, summary: dict, history: pd.DataFrame, diagnostics: pd.DataFrame,
             name: str, load: float) -> str:
    ie = summary["initial_equilibrium"]
    settled, after = motion(history, name)
    converged = "yes" if ie["converged"] else f"no ({ie['unbalanced_force_ratio']:.2g})"
    return (f"| {label} | {method} | {load:.1f} | {ie['steps']} | {converged} | {1e3 * settled:.3f} "
            f"| {1e3 * after:.2g} | {diagnostics['kinetic_energy'].max():.2g} | {summary['wall_seconds']:.1f} |")


HEADER = ["| joints | initial equilibrium | load | steps | converged (unbalanced ratio) | {} at the release [mm] "
          "| moved after it [mm] | largest kinetic energy after it [J] | wall [s] |",
          "|---|---|---:|---:|---|---:|---:|---:|---:|"]


def stiffness_rows(path: Path, cases: list, joint: str, block: str, sets: list[str], tmp: Path) -> list[str]:
    """One row per case and method: `path` with `sets`, `joint`'s normal stiffness set per case,
    `block`'s displacement reported."""
    out = []
    for k, (label, kn, methods) in enumerate(cases):
        stiffness = [] if kn is None else [f"joint.{joint}.normal_stiffness={kn:g}"]
        for method, extra in methods:
            load = os.getloadavg()[0]
            s, h, d = run(path, [f"analysis.initial_equilibrium={method}", *sets, *stiffness, *extra],
                          tmp / f"{path.stem}{k}{method}")
            out.append(case_row(label, method, s, h, d, block, load))
            print(out[-1], flush=True)
    return out


def tunnel(duration: float, tmp: Path) -> list[str]:
    out = [f"The thesis tunnel (`examples/tunnel_key_blocks.toml`), {duration:g} s after the release; "
           "the roof key block's displacement:", "", HEADER[0].format("roof key block"), HEADER[1]]
    return out + stiffness_rows(TUNNEL, TUNNEL_CASES, "joint", "roof_key_block", [f"analysis.duration={duration}"], tmp)


def slope(duration: float, tmp: Path) -> list[str]:
    out = ["", f"The thesis slope at φ = {SLOPE_FRICTION:g}° (`examples/rock_slope.toml`, where every joint holds), "
           f"{duration:g} s after the release; the toe block's displacement:", "",
           HEADER[0].format("toe block"), HEADER[1]]
    sets = [f"analysis.duration={duration}", f"joint.rock_joint.friction_angle={SLOPE_FRICTION}"]
    return out + stiffness_rows(SLOPE, SLOPE_CASES, "rock_joint", "toe_block", sets, tmp)


def wedge(tmp: Path) -> list[str]:
    out = ["", "The 3DEC sliding wedge (`examples/sliding_wedge.toml`, joints of 10 MPa/m, 1.5 s) just above "
           f"its critical friction angle ({WEDGE_CRITICAL}°, vector method):", "",
           HEADER[0].format("wedge").replace("| joints |", "| φ |"), HEADER[1]]
    for margin in WEDGE_MARGINS:
        phi = WEDGE_CRITICAL + margin
        for method in ["locked", "frictional"]:
            load = os.getloadavg()[0]
            sets = [f"analysis.initial_equilibrium={method}", f"joint.j.friction_angle={phi}"]
            s, h, d = run(WEDGE, sets, tmp / f"w{margin}{method}")
            out.append(case_row(f"{phi:.3f}°", method, s, h, d, "wedge", load))
            print(out[-1], flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--duration", type=float, default=0.05)
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as d:
        body = tunnel(args.duration, Path(d)) + slope(args.duration, Path(d)) + wedge(Path(d))
    body += ["", "`locked`: `initial_equilibrium = true`; `frictional`: `\"frictional\"` "
             "([theory/contact.md](theory/contact.md), *Initial equilibrium*)."]
    write_page(PAGE, "Performance: the locked and the frictional initial equilibrium", "initial_equilibrium.py",
               load0, body)


if __name__ == "__main__":
    main()
