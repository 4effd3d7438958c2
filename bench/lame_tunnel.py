"""Writes examples/staged_tunnel_lame.toml: a circular tunnel excavated in hydrostatic in-situ
stress (staged analysis), a quarter of a thick plane-strain cylinder whose outer traction stays
the in-situ stress, for the closed form `nmm3d.analytic.lame_excavation`.
Run: python bench/lame_tunnel.py [--outer 5] [--size 0.1]

The outer arc is 48 faces, each loaded by its own `[[surface_load]]` (σ₀·n); the opening a
64-sided disc; symmetry planes x = 0 and y = 0 and both slab faces on rollers.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
A, P, E, NU, T = 1.0, 1.0e7, 1.0e10, 0.25, 0.2  # radius [m], in-situ pressure [Pa], E [Pa], ν, slab [m]
RADII = (1.0, 1.5, 2.0, 4.0)                     # monitored radii [m]


def points(pts) -> str:
    return "[" + ", ".join(f"[{x:.12g}, {y:.12g}]" for x, y in pts) + "]"


def held(lo, hi, axis: str) -> str:
    return (f"\n[[constraint]]\nselect = {{ box = {{ min = [{lo[0]:g}, {lo[1]:g}, {lo[2]:g}], "
            f"max = [{hi[0]:g}, {hi[1]:g}, {hi[2]:g}] }} }}\ndirections = [\"{axis}\"]\n")


def outer_loads(arc) -> str:
    out = ""
    for (x0, y0), (x1, y1) in zip(arc, arc[1:]):
        nx, ny = y1 - y0, -(x1 - x0)
        n = math.hypot(nx, ny)
        nx, ny = nx / n, ny / n
        lo, hi = (min(x0, x1) - 1e-3, min(y0, y1) - 1e-3), (max(x0, x1) + 1e-3, max(y0, y1) + 1e-3)
        out += (f"\n[[surface_load]]\nselect = {{ box = {{ min = [{lo[0]:.12g}, {lo[1]:.12g}, -0.01], "
                f"max = [{hi[0]:.12g}, {hi[1]:.12g}, {T + 0.01}] }} }}\nnormal = [{nx:.12g}, {ny:.12g}, 0.0]\n"
                f"traction = [{-P * nx:.12g}, {-P * ny:.12g}, 0.0]\n")
    return out


def scenario(outer: float, size: float) -> str:
    arc = [(outer * math.cos(0.5 * math.pi * k / 48), outer * math.sin(0.5 * math.pi * k / 48)) for k in range(49)]
    disc = [(A * math.cos(2 * math.pi * k / 64), A * math.sin(2 * math.pi * k / 64)) for k in range(64)]
    b, e = outer + 0.01, 1e-3
    text = f"""# A circular tunnel excavated in hydrostatic in-situ stress: staged analysis against Lamé's
# thick cylinder (docs/verification.md (u), nmm3d.analytic.lame_excavation). Written by
# `python bench/lame_tunnel.py --outer {outer:g} --size {size:g}`; do not edit by hand.
# A quarter of a plane-strain slab (x, y >= 0, {T} m thick, outer radius {outer:g} m, the outer arc
# loaded by the in-situ stress), p = {P:g} Pa in every direction, E = {E:g} Pa, nu = {NU}.
# Stage "in situ": the tunnel's rock in place, static equilibrium. Stage "excavate": the
# tunnel of radius {A:g} m is removed; the rock around it moves in by
# u(r) = A r + B/r (radial stress change +p at the wall, 0 at the outer arc): 1.328 mm at the
# wall, 0.703 mm at r = 2 m (outer radius 5 m). Hoop stress at the wall: -2p less the outer
# radius's effect. NMM within 1.6 % at the wall, 0.6 % beyond, at cover size 0.1 m.

[scenario]
name = "staged-tunnel-lame"
description = "Circular tunnel excavated in hydrostatic in-situ stress (Lame)"

[analysis]
kind = "static"
dt = 1.0
max_displacement_ratio = 1.0
equilibrium_tolerance = 1e-9
gravity = [0.0, 0.0, 0.0]
output_interval = 0.0

[cover]
size = {size:g}

[[material]]
name = "rock"
density = 2500.0
young = {E:g}
poisson = {NU}

[[body]]
name = "rock"
material = "rock"
shape = {{ prism = {{ polygon = {points([(0.0, 0.0)] + arc)}, z = [0.0, {T}] }} }}

[[excavation]]
name = "tunnel"
shape = {{ prism = {{ polygon = {points(disc)}, z = [-1.0, 1.0] }} }}

[in_situ_stress]
stress = [{-P:g}, {-P:g}, {-P:g}, 0.0, 0.0, 0.0]
"""
    text += held((-0.01, -0.01, -0.01), (b, b, e), "z") + held((-0.01, -0.01, T - e), (b, b, T + 0.01), "z")
    text += held((-e, -0.01, -0.01), (e, b, T + 0.01), "x") + held((-0.01, -e, -0.01), (b, e, T + 0.01), "y")
    text += "\n# The outer arc: the in-situ traction sigma0 . n on each of its faces."
    text += outer_loads(arc)
    for r in RADII:
        x = r + 1e-6 if r == A else r
        text += (f"\n[[monitor]]\nname = \"r{str(r).replace('.', '_')}\"\nselect = {{ point = [{x:g}, 1e-6, {T / 2:g}] }}\n"
                 "location = \"point\"\nquantities = [\"displacement\"]\n")
    text += """
[[stage]]
name = "in-situ"
duration = 20.0

[[stage]]
name = "excavate"
duration = 50.0
excavate = ["tunnel"]
"""
    return text


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--outer", type=float, default=5.0, help="outer radius [m]")
    ap.add_argument("--size", type=float, default=0.1, help="cover size [m]")
    args = ap.parse_args()
    path = ROOT / "examples" / "staged_tunnel_lame.toml"
    path.write_text(scenario(args.outer, args.size))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
