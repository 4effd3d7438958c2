"""Multigrid against the direct factor on a web of touching blocks: the packed pile of
`bench/contact.py` (cubes touching side to side and on each other) with `linear_solver =
"amg"` and `"direct"`, each case in its own process, one after the other. Writes
`docs/performance-web-solvers.md`.

    python bench/web_solvers.py [--sizes 1000 3000]
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


def run_case(n: int, solver: str, out: str) -> dict:
    """The packed pile of `n` cubes on `solver`; what its summary says."""
    import nmm3d
    from contact import pile

    scenario = pile(n, packed=True)
    scenario["analysis"]["linear_solver"] = solver
    s = nmm3d.Scenario.from_dict(scenario).run(out=out).summary
    keys = ["steps", "step_cuts", "open_close_iterations", "factorizations", "multigrid_iterations",
            "factor_nonzeros", "dofs", "wall_seconds", "max_penetration"]
    return {k: s[k] for k in keys} | {"n": n, "solver": solver, "load": os.getloadavg()[0]}


def measure(sizes: list[int]) -> list[dict]:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            for solver in SOLVERS:
                load = os.getloadavg()[0]
                code = (f"import sys, json; sys.path.insert(0, {str(ROOT / 'bench')!r}); import web_solvers; "
                        f"print(json.dumps(web_solvers.run_case({n}, {solver!r}, "
                        f"{os.path.join(tmp, f'{n}{solver}')!r})))")
                r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
                rows.append(json.loads(r.stdout.strip().splitlines()[-1]) | {"load": load})
                print(f"N = {n} {solver}: {rows[-1]['wall_seconds']:.1f} s", flush=True)
    return rows


def body(rows: list[dict]) -> list[str]:
    out = ["The packed pile of `bench/contact.py` (`pile(n, packed=True)`: cubes of 0.5 m, hex8 covers",
           "of one cell per cube, touching side to side and on each other, 2 mm above the floor; 40",
           "implicit steps of at most 2 ms) solved by the direct sparse Cholesky and by conjugate",
           "gradients preconditioned by smoothed-aggregation multigrid (`analysis.linear_solver`).",
           "Each case in its own process, one after the other; *load*: the load average when it",
           "started. *factor entries*: the direct factor's, or the multigrid's coarsest level's.",
           "",
           "| cubes | equations | solver | load | wall [s] | steps | cuts | open–close iterations "
           "| factorisations or hierarchies | multigrid iterations | factor entries | deepest overlap [mm] |",
           "|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['n']:,} | {r['dofs']:,} | {r['solver']} | {r['load']:.1f} | {r['wall_seconds']:.1f} "
                   f"| {r['steps']} | {r['step_cuts']} | {r['open_close_iterations']} | {r['factorizations']} "
                   f"| {r['multigrid_iterations']} | {r['factor_nonzeros']:,} | {1e3 * r['max_penetration']:.4f} |")
    by = {(r["n"], r["solver"]): r["wall_seconds"] for r in rows}
    sizes = sorted({r["n"] for r in rows})
    out += ["", "| cubes | direct / multigrid wall time |", "|---:|---:|"]
    out += [f"| {n:,} | {by[(n, 'direct')] / by[(n, 'amg')]:.2f}× |" for n in sizes]
    if len(sizes) > 1:
        a, b = sizes[0], sizes[-1]
        growth = {s: math.log(by[(b, s)] / by[(a, s)]) / math.log(b / a) for s in SOLVERS}
        out += ["", f"From {a:,} to {b:,} cubes the run grew as N^{growth['direct']:.2f} with the direct "
                    f"factor and as N^{growth['amg']:.2f} with multigrid ([theory/solver.md](theory/solver.md))."]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="*", default=SIZES)
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    rows = measure(args.sizes)
    write_page(PAGE, "Performance: multigrid and the direct factor on a web of touching blocks",
               "web_solvers.py", load0, body(rows))


if __name__ == "__main__":
    main()
