"""What single-precision factors buy; writes docs/factor-precision.md.

Run: python bench/factor_precision.py

`analysis.factor_precision = "auto"` (the default) makes a numeric factorisation in single
precision where it costs many triangular solves, and refines every solve on it to double
precision (docs/theory/solver.md, *Single-precision factors*). Each case runs with
`factor_precision = "double"` and with the default, back to back (alternating which goes
first); the answer a rock engineer reads is set beside the factorisations and the time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _page import write_page
from _run import run_scenario

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "factor-precision.md"
GOODMAN = ROOT / "examples" / "goodman_tunnel.toml"
TUNNEL = ROOT / "examples" / "tunnel_key_blocks.toml"
DOMINOS = ROOT / "bench" / "peers" / "dominos_yade_match.toml"
SLOPE = ROOT / "examples" / "rock_slope.toml"
BENCH = Path(__file__).resolve().parent
# The packed pile of `bench/contact.py` (cubes touching side to side and on each other): a web of
# contacts whose factor fills, made by that script rather than read from a file: its cubes.
PILE = 1000
STATIC = ["analysis.kind=static", "analysis.dt=1", "analysis.duration=20", "analysis.static_travel_limit=0.02"]
# (case, scenario, settings, the value read and its unit)
CASES = [
    ("Goodman's tunnel, 0.3 s", GOODMAN, [], ("roof_block.displacement.z", "m")),
    ("thesis tunnel, wall key block sliding (φ = 25°), 1 s", TUNNEL,
     ["analysis.duration=1", "joint.joint.friction_angle=25"], ("wall_key_block.displacement.y", "m")),
    ("thesis tunnel at rest, 1 s", TUNNEL, ["analysis.duration=1"], ("roof_key_block.displacement.z", "m")),
    ("thesis tunnel, static check at φ = 30°", TUNNEL, [*STATIC, "joint.joint.friction_angle=30"],
     ("roof_key_block.displacement.z", "m")),
    ("Yade-matched dominos (0.1 m cover), 1 s", DOMINOS, ["analysis.duration=1"], ("d9.rotation.y", "rad")),
    ("thesis slope case A, 1 s", SLOPE, ["analysis.duration=1"], ("toe_block.displacement.x", "m")),
    ("packed pile of 1 000 cubes, 40 steps (`bench/contact.py`)", PILE, [], ("max_penetration", "m")),
]
PRECISIONS = ("double", "auto")


def run_pile(n: int, sets: list[str]) -> dict:
    """The packed pile of `n` cubes with `sets`, in a process of its own: its summary, `wall` [s]."""
    with tempfile.TemporaryDirectory() as out:
        code = (f"import sys, json; sys.path.insert(0, {str(BENCH)!r}); import nmm3d; from contact import pile; "
                f"print(json.dumps(nmm3d.Scenario.from_dict(pile({n}, packed=True), {sets!r}).run(out={out!r}).summary))")
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
        wall = time.perf_counter() - t0
    return json.loads(r.stdout.strip().splitlines()[-1]) | {"wall": wall}


def run(scenario: Path | int, sets: list[str]) -> dict:
    """A case's run: a scenario file as a user runs it, or the generated pile of that many cubes."""
    return run_pile(scenario, sets) if isinstance(scenario, int) else run_scenario(scenario, sets)


def result(s: dict, value: str) -> float:
    """The value read at the end: a monitor's, or the summary's own."""
    return s["final"][value] if value in s.get("final", {}) else s[value]


def row(name: str, precision: str, s: dict, value: str, unit: str, load: float) -> str:
    t = s["timings"]
    return (f"| {name} | {precision} | {s['single_precision_factorizations']} / {s['factorizations']} | "
            f"{s['refinement_iterations']} | {s['factor_nonzeros']:,} | {t['factorization']:.1f} | "
            f"{t.get('step_equilibrium', 0.0):.1f} | {s['wall']:.1f} | {result(s, value):.6g} {unit} | "
            f"{s['status']} | {load:.1f} |")


def main() -> None:
    load0 = os.getloadavg()[0]
    lines, ratios = [], []
    for k, (name, scenario, sets, (value, unit)) in enumerate(CASES):
        order = PRECISIONS if k % 2 == 0 else PRECISIONS[::-1]
        runs = {}
        for precision in order:
            load = os.getloadavg()[0]
            runs[precision] = (run(scenario, [*sets, f"analysis.factor_precision={precision}"]), load)
            print(name, precision, round(runs[precision][0]["wall"], 1), flush=True)
        for precision in PRECISIONS:
            summary, load = runs[precision]
            lines.append(row(name, precision, summary, value, unit, load))
        ratios.append((name, runs["double"][0]["wall"] / runs["auto"][0]["wall"],
                       runs["double"][0]["timings"]["factorization"] / runs["auto"][0]["timings"]["factorization"]))
    write_page(PAGE, "Single-precision factors: factorisations refined to double precision", "factor_precision.py",
               load0, [
        "Each case with `analysis.factor_precision = \"double\"` and with the default `\"auto\"` (single "
        "precision where a factorisation costs at least 12 PCG iterations on its factor and the last factor's "
        "solves cost few extra iterations, [theory/solver.md](theory/solver.md#single-precision-factors)), "
        "back to back. *Single / all*: "
        "factorisations made in single precision of all made; *refinement*: the conjugate-gradient "
        "iterations that brought the solves on them to double precision; *factorisation*: the summary's "
        "`factorization` time (the numeric factorisations alone; the refined solves count in the open–close phase); *result*: the value a "
        "rock engineer reads at the end.",
        "",
        "| case | precision | single / all factorisations | refinement iterations | factor entries | "
        "factorisation [s] | step equilibrium [s] | wall [s] | result | status | load |",
        "|---|---|---:|---:|---:|---:|---:|---:|---|---|---:|",
        *lines,
        "",
        "Double against auto, wall time and factorisation time: "
        + "; ".join(f"{n} {w:.2f}× and {f:.2f}×" for n, w, f in ratios) + ".",
    ])


if __name__ == "__main__":
    main()
