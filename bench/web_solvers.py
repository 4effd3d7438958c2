"""Multigrid against the direct factor on a web of touching blocks: the packed pile of
`bench/contact.py` (cubes touching side to side and on each other) and the jointed rock slope
of `examples/rock_slope.toml` on finer covers, with `linear_solver = "amg"` and `"direct"`,
each case in its own process, one after the other. Writes `docs/performance-web-solvers.md`.

    python bench/web_solvers.py [--sizes 1000 3000] [--covers 0.35 0.25]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _page import write_page

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "performance-web-solvers.md"
SIZES = [1000, 3000]
SOLVERS = ["direct", "amg"]
# The rock slope's cover sizes [m] (the example's 1.45 m gives 1 479 equations).
COVERS = [0.35, 0.25]
SLOPE = ROOT / "examples" / "rock_slope.toml"
SLOPE_STEPS = 20
KEYS = ["steps", "step_cuts", "open_close_iterations", "factorizations", "multigrid_iterations",
        "factor_nonzeros", "dofs", "wall_seconds", "max_penetration"]


def run_case(n: int, solver: str, out: str) -> dict:
    """The packed pile of `n` cubes on `solver`; what its summary says."""
    import nmm3d
    from contact import pile

    scenario = pile(n, packed=True)
    scenario["analysis"]["linear_solver"] = solver
    s = nmm3d.Scenario.from_dict(scenario).run(out=out).summary
    return {k: s[k] for k in KEYS} | {"n": n, "solver": solver}


def run_slope(cover: float, solver: str, out: str) -> dict:
    """Thesis case A (φ = 10°) on a cover of `cover` m for SLOPE_STEPS steps of 1 ms on `solver`."""
    import nmm3d

    sets = ["joint.rock_joint.friction_angle=10", f"cover.size={cover}",
            f"analysis.duration={SLOPE_STEPS * 1e-3}", f'analysis.linear_solver="{solver}"']
    s = nmm3d.load(str(SLOPE), sets).run(out=out).summary
    return {k: s[k] for k in KEYS} | {"n": cover, "solver": solver}


def in_process(func: str, args: tuple, out: str) -> dict:
    """`web_solvers.func(*args, out)` in a process of its own, with the load when it started."""
    code = (f"import sys, json; sys.path.insert(0, {str(ROOT / 'bench')!r}); import web_solvers; "
            f"print(json.dumps(web_solvers.{func}(*{args!r}, {out!r})))")
    load = os.getloadavg()[0]
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(r.stdout.strip().splitlines()[-1]) | {"load": load}


def measure(sizes: list[int], covers: list[float]) -> tuple[list[dict], list[dict]]:
    piles, slopes = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            for solver in SOLVERS:
                piles.append(in_process("run_case", (n, solver), os.path.join(tmp, f"{n}{solver}")))
                print(f"N = {n} {solver}: {piles[-1]['wall_seconds']:.1f} s", flush=True)
        for c in covers:
            for solver in SOLVERS:
                slopes.append(in_process("run_slope", (c, solver), os.path.join(tmp, f"s{c}{solver}")))
                print(f"slope, cover {c} m, {solver}: {slopes[-1]['wall_seconds']:.1f} s", flush=True)
    return piles, slopes


COLUMNS = ("| equations | solver | load | wall [s] | steps | cuts | open–close iterations "
           "| factorisations or hierarchies | multigrid iterations | stored entries | deepest overlap [mm] |")
ALIGN = "|---:|---:|---|" + "---:|" * 9


def row(first: str, r: dict) -> str:
    return (f"| {first} | {r['dofs']:,} | {r['solver']} | {r['load']:.1f} | {r['wall_seconds']:.1f} "
            f"| {r['steps']} | {r['step_cuts']} | {r['open_close_iterations']} | {r['factorizations']} "
            f"| {r['multigrid_iterations']} | {r['factor_nonzeros']:,} | {1e3 * r['max_penetration']:.4f} |")


def walls(rows: list[dict]) -> dict:
    """Wall time [s] by (size, solver)."""
    return {(r["n"], r["solver"]): r["wall_seconds"] for r in rows}


def ratios(rows: list[dict], label: str, fmt) -> list[str]:
    by = walls(rows)
    out = ["", f"| {label} | direct / multigrid wall time |", "|---:|---:|"]
    return out + [f"| {fmt(n)} | {by[(n, 'direct')] / by[(n, 'amg')]:.2f}× |" for n in dict.fromkeys(r["n"] for r in rows)]


def pile_table(rows: list[dict]) -> list[str]:
    out = ["The packed pile of `bench/contact.py` (`pile(n, packed=True)`: cubes of 0.5 m, hex8 covers",
           "of one cell per cube, touching side to side and on each other, 2 mm above the floor; 40",
           "implicit steps of at most 2 ms) solved by the direct sparse Cholesky and by conjugate",
           "gradients preconditioned by smoothed-aggregation multigrid (`analysis.linear_solver`).",
           "Each case in its own process, one after the other; *load*: the load average when it",
           "started. *stored entries*: the direct factor's, or the multigrid hierarchy's (its levels'",
           "operators and prolongators and the coarsest level's factor).",
           "",
           "| cubes " + COLUMNS, ALIGN]
    out += [row(f"{r['n']:,}", r) for r in rows]
    out += ratios(rows, "cubes", lambda n: f"{n:,}")
    by = walls(rows)
    sizes = sorted({r["n"] for r in rows})
    if len(sizes) > 1:
        a, b = sizes[0], sizes[-1]
        growth = {s: math.log(by[(b, s)] / by[(a, s)]) / math.log(b / a) for s in SOLVERS}
        out += ["", f"From {a:,} to {b:,} cubes the run grew as N^{growth['direct']:.2f} with the direct "
                    f"factor and as N^{growth['amg']:.2f} with multigrid ([theory/solver.md](theory/solver.md))."]
    return out


def slope_table(rows: list[dict]) -> list[str]:
    out = ["", "## A jointed rock mass", "",
           "`examples/rock_slope.toml` at φ = 10° (thesis case A: 46 blocks on a fixed bedrock, joints of",
           f"0.26 GPa/m) on finer covers than the example's 1.45 m, {SLOPE_STEPS} steps of 1 ms from rest.",
           "", "| cover [m] " + COLUMNS, ALIGN]
    out += [row(f"{r['n']}", r) for r in rows]
    out += ratios(rows, "cover [m]", str)
    by = walls(rows)
    direct = all(by[(c, "direct")] < by[(c, "amg")] for c, _ in by)
    verdict = ("On every cover measured here the faster solver was the direct factor" if direct
               else "On some cover measured here multigrid was the faster")
    out += ["", f"{verdict}; `\"auto\"` solves every",
            "model of several blocks with the direct factor ([theory/solver.md](theory/solver.md))."]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="*", default=SIZES)
    ap.add_argument("--covers", type=float, nargs="*", default=COVERS)
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    piles, slopes = measure(args.sizes, args.covers)
    write_page(PAGE, "Performance: multigrid and the direct factor on a web of touching blocks",
               "web_solvers.py", load0, pile_table(piles) + slope_table(slopes))


if __name__ == "__main__":
    main()
