"""Static equilibrium end to end: nmm3d's multigrid PCG and direct solvers against scikit-fem + pyamg.

Run: python bench/static_equilibrium.py [--sizes 12 26 55] ; writes docs/performance-static.md.

The block of `bench/_case.py` (a cube of n³ cells of 1 m, tet6 covers: 6 n³ MEs, base held,
loaded by its weight) run by nmm3d as a static analysis to equilibrium (co-rotational Newton
iterations until the unbalanced-force ratio is below 1e-7): with the default solver choice
(`linear_solver = "auto"`: multigrid-preconditioned CG for one block of 20 000 equations and
more), with the direct Cholesky and factor reuse (`"direct"`: iterations after the first solved
by PCG on the first factor), and with a factorisation per iteration (`"direct"`,
`factor_reuse = false`). In the same run, the peer a Python user would pick:
scikit-fem P1 elasticity on the same tensor-product tetrahedral mesh solved by pyamg's
smoothed-aggregation AMG as a CG preconditioner (`../shared/research/peers/skfem_block.py`,
one linear solve — the linear problem needs no iterations). Every case runs in its own
process, `--repeat` times, and its fastest run is kept; wall times are measured inside the
process, imports excluded on both sides, and so is the peak resident memory; the load average
is recorded before each case. From `--direct-once` cells per edge the direct cases run once
(their factor takes minutes and gigabytes).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PEER = ROOT.parent / "shared" / "research" / "peers" / "skfem_block.py"


CASES = {"auto": {}, "reuse": {"linear_solver": "direct"},
         "factorise": {"linear_solver": "direct", "factor_reuse": False}}


def nmm3d_case(n: int, case: str) -> dict:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import resource
    import tempfile

    import nmm3d
    from _case import block_scenario

    s = block_scenario(n)
    s["analysis"].update({"max_steps": 50, "duration": 1.0e6, **CASES[case]})
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        r = nmm3d.Scenario.from_dict(s).run(out=out).summary
        wall = time.perf_counter() - t0
    keys = ("steps", "factorizations", "krylov_solves", "krylov_iterations", "manifold_elements", "dofs",
            "linear_solver", "multigrid_iterations", "factor_nonzeros")
    return {"wall": wall, **{k: r[k] for k in keys}, "top_uz": r["final"]["top.displacement.z"],
            "message": r["message"], "timings": r["timings"],
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}


def in_process(args: list[str]) -> dict:
    out = subprocess.run([sys.executable, *args], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--sizes", type=int, nargs="*", default=[12, 26, 55], help="cells per edge")
    p.add_argument("--repeat", type=int, default=2, help="runs per case (the fastest is kept)")
    p.add_argument("--direct-once", type=int, default=40, help="from this size the direct cases run once")
    p.add_argument("--case", nargs=2, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.case:
        print(json.dumps(nmm3d_case(int(args.case[0]), args.case[1])))
        return
    rows = []
    for n in args.sizes:
        row = {"n": n}
        for name in ["auto", "reuse", "factorise", "skfem_amg"]:
            cmd = [str(PEER), str(n), "amg"] if name == "skfem_amg" else [__file__, "--case", str(n), name]
            repeat = 1 if n >= args.direct_once and name in ("reuse", "factorise") else args.repeat
            load = os.getloadavg()[0]
            runs = [in_process(cmd) for _ in range(repeat)]
            for r in runs:
                r.setdefault("wall", sum(v for k, v in r.get("timings", {}).items() if k != "import"))
            row[name] = {**min(runs, key=lambda r: r["wall"]), "load": load, "runs": len(runs)}
            print(n, name, row[name]["wall"], row[name]["peak_mb"], file=sys.stderr)
        rows.append(row)
    write(rows)


def write(rows: list[dict]) -> None:
    lines = [
        "# Performance: static equilibrium, multigrid and direct solvers, scikit-fem + pyamg",
        "",
        "`python bench/static_equilibrium.py` — the block of `bench/_case.py` (6 n³ tet6 MEs, base",
        "held, own weight) to static equilibrium: co-rotational Newton iterations until the",
        "unbalanced-force ratio is below 1e-7. nmm3d three ways: the default (`linear_solver =",
        '"auto"`: multigrid-preconditioned CG for a single block of 20 000 equations and more,',
        "`docs/theory/solver.md`), the direct Cholesky with factor reuse, and a factorisation per",
        "iteration. The peer: scikit-fem P1 on the same mesh, pyamg smoothed-aggregation AMG as the",
        "CG preconditioner (tolerance 1e-8), one linear solve. Each case in its own process; the",
        f"fastest of {rows[0]['auto']['runs']} runs (the direct ones once from 10⁶ MEs); imports",
        "excluded; peak resident memory of the case's process.",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores; load average before each case in",
        "its column.",
        "",
        "| MEs | DOFs | nmm3d default [s] | solver, Newton iterations, multigrid iterations | nmm3d direct + reuse [s] | nmm3d factorise every iteration [s] | scikit-fem + pyamg [s] | default vs pyamg | peak memory nmm3d default / direct / pyamg [GB] | top u_z nmm3d / pyamg [mm] | load |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        a, d, f, c = r["auto"], r["reuse"], r["factorise"], r["skfem_amg"]
        lines.append(
            f"| {a['manifold_elements']} | {a['dofs']} | {a['wall']:.2f} "
            f"| {a['linear_solver']}, {a['steps']}, {a['multigrid_iterations']} | {d['wall']:.2f} "
            f"| {f['wall']:.2f} ({f['factorizations']}) | {c['wall']:.2f} | **{c['wall'] / a['wall']:.2f}×** "
            f"| {a['peak_mb'] / 1024:.2f} / {d['peak_mb'] / 1024:.2f} / {c['peak_mb'] / 1024:.2f} "
            f"| {1e3 * a['top_uz']:.4f} / {1e3 * c['top_uz']:.4f} "
            f"| {a['load']:.1f} / {d['load']:.1f} / {f['load']:.1f} / {c['load']:.1f} |"
        )
    for name, title in [("auto", "the default"), ("reuse", "the direct solver with reuse")]:
        keys = sorted(rows[0][name]["timings"])
        lines += ["", f"Seconds per phase of nmm3d with {title} (summary `timings`; with multigrid, "
                  "`factorization` is the hierarchy's set-up and `krylov` its PCG):", "",
                  "| MEs | " + " | ".join(keys) + " |", "|---|" + "---|" * len(keys)]
        for r in rows:
            t = r[name]["timings"]
            lines.append(f"| {r[name]['manifold_elements']} | " + " | ".join(f"{t.get(k, 0.0):.2f}" for k in keys) + " |")
    lines += [
        "",
        "The nmm3d columns reach the same displacement (to the multigrid tolerance 1e-8); the",
        "peer's differs by the co-rotational (geometrically nonlinear) iterations nmm3d makes and",
        "the peer does not. Why factor reuse is limited to matrices without closed contact springs,",
        "and why multigrid is chosen only for a single block: `docs/theory/solver.md`.",
        "",
    ]
    (ROOT / "docs" / "performance-static.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
