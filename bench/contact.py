"""Contact benchmark; writes docs/performance-contact.md. Run: python bench/contact.py

A pile of N cubes (0.5 m, hex8 covers of one cell per cube) in a square grid of columns of
four, 2 mm apart, dropped onto a fixed floor: every cube touches the floor or the cube below
and its neighbours are within the warning distance. A fixed number of implicit steps each;
time per step split into warning (candidate pairs), detection (planes, facet overlay,
transfer), pattern (sparsity rebuilds when new ME pairs touch), assembly (elastic), solve
(contact springs, factorisation and triangular solves) and the open–close iterations beyond the
first. Every case runs in its own process.
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
SIZES = [10, 100, 1000, 3000, 8000]
PACKED_SIZES = [100, 1000]
STEPS = 40


def pile(n: int, packed: bool = False) -> dict:
    """n cubes in columns of up to four on a √(n/4) × √(n/4) grid, 2 mm apart (`packed`: touching
    side to side and on each other, the whole pile 2 mm above the floor)."""
    side, gap, h = 0.5, 0.002, 4
    pitch = side if packed else side + gap
    cols = max(1, math.ceil(n / h))
    per_row = math.ceil(math.sqrt(cols))
    bodies = []
    for k in range(n):
        c, level = divmod(k, h)
        i, j = divmod(c, per_row)
        x, y, z = i * pitch, j * pitch, level * pitch + gap
        bodies.append({"name": f"b{k}", "material": "rock", "joint": "j",
                       "shape": {"box": {"min": [x, y, z], "max": [x + side, y + side, z + side]}}})
    extent = per_row * pitch + 1.0
    floor = {"name": "floor", "material": "rock", "fixed": True,
             "shape": {"box": {"min": [-1.0, -1.0, -0.5], "max": [extent, extent, 0.0]}}}
    # One cell per cube: the cells' pitch is the cubes' and each cube sits half a gap inside
    # its cell, or fills it when packed (a cube cut by cell planes would get more covers the
    # further it is from the mesh's origin, and its cost per block would grow with the pile).
    origin = [0.0, 0.0, gap] if packed else [-gap / 2, -gap / 2, gap / 2]
    return {
        "analysis": {"duration": 10.0, "dt": 0.002, "max_steps": STEPS, "max_displacement_ratio": 0.01,
                     "gravity": [0.0, 0.0, -9.81], "output_interval": 0.0},
        "cover": {"pattern": "hex8", "size": pitch, "origin": origin},
        "material": [{"name": "rock", "density": 2600.0, "young": 1.0e10, "poisson": 0.25}],
        "joint": [{"name": "j", "friction_angle": 30.0}],
        "body": [floor, *bodies],
    }


def run_case(n: int, out: str, packed: bool = False) -> dict:
    import nmm3d

    s = nmm3d.Scenario.from_dict(pile(n, packed)).run(out=out).summary
    return {"n": n, "steps": s["steps"], "points": s["max_contact_points"], "iterations": s["open_close_iterations"],
            "cuts": s["step_cuts"], "rebuilds": s["pattern_rebuilds"], "factor": s["factor_nonzeros"], "dofs": s["dofs"],
            "timings": s["timings"], "wall": s["wall_seconds"], "elements": s["manifold_elements"]}


def dominos(out: str) -> dict:
    import nmm3d

    s = nmm3d.load(ROOT / "examples" / "dominos.toml").run(out=out).summary
    return {"steps": s["steps"], "wall": s["wall_seconds"], "points": s["max_contact_points"],
            "penetration": s["max_penetration"], "time": s["time"],
            "tilts": [s["final"][f"d{k}.rotation.y"] for k in range(8)]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--sizes", type=int, nargs="*", default=SIZES)
    ap.add_argument("--packed-sizes", type=int, nargs="*", default=PACKED_SIZES)
    args = ap.parse_args()
    rows, packed = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for n, pack in [(n, False) for n in args.sizes] + [(n, True) for n in args.packed_sizes]:
            code = f"import sys, json; sys.path.insert(0, {str(ROOT / 'bench')!r}); import contact; " \
                   f"print(json.dumps(contact.run_case({n}, {os.path.join(tmp, f'{n}{pack}')!r}, {pack})))"
            r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
            (packed if pack else rows).append(json.loads(r.stdout.strip().splitlines()[-1]))
            print(f"N = {n}{' packed' if pack else ''}: {(packed if pack else rows)[-1]['wall']:.1f} s", flush=True)
        code = f"import sys, json; sys.path.insert(0, {str(ROOT / 'bench')!r}); import contact; " \
               f"print(json.dumps(contact.dominos({os.path.join(tmp, 'dominos')!r})))"
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        dom = json.loads(r.stdout.strip().splitlines()[-1])
        print(f"dominos: {dom['wall']:.1f} s", flush=True)
    write(rows, packed, dom)


def meet(tilts: list[float]) -> str:
    """The pair where the two waves met (tilt changes sign)."""
    k = next((k for k in range(len(tilts) - 1) if tilts[k] > 0.0 >= tilts[k + 1]), None)
    return "none" if k is None else f"{k} and {k + 1}"


CONTACT_PHASES = ("contact_warning", "contact_detection", "contact_pattern", "contact_open_close")


def per_step(r: dict, keys: tuple[str, ...]) -> float:
    return sum(r["timings"].get(k, 0.0) for k in keys) / max(r["steps"], 1)


def growth(rows: list[dict]) -> list[str]:
    """Growth exponents of the contact phases between successive sizes, next to N log N's."""
    big = [r for r in rows if r["n"] >= 100]
    if len(big) < 2:
        return []
    out = ["Growth of the time per step between successive sizes, as the exponent p of N^p (N log N",
           "gives slightly more than 1 over the same range):", "",
           "| from N | to N | warning + detection | pattern + open–close | all contact phases | whole step | N log N |",
           "|---:|---:|---:|---:|---:|---:|---:|"]
    for a, b in zip(big, big[1:]):
        ratio = math.log(b["n"] / a["n"])
        p = lambda keys: math.log(per_step(b, keys) / per_step(a, keys)) / ratio  # noqa: E731
        whole = math.log((b["wall"] / b["steps"]) / (a["wall"] / a["steps"])) / ratio
        nlogn = math.log(b["n"] * math.log(b["n"]) / (a["n"] * math.log(a["n"]))) / ratio
        out.append(f"| {a['n']:,} | {b['n']:,} | {p(CONTACT_PHASES[:2]):.2f} | {p(CONTACT_PHASES[2:]):.2f} | "
                   f"{p(CONTACT_PHASES):.2f} | {whole:.2f} | {nlogn:.2f} |")
    out += ["", "The same phases per unit of work: warning + detection per contact point, open–close per",
            "iteration beyond a step's first, pattern growth per rebuild — the counts themselves (points",
            "per block, iterations and rebuilds per step) are in the table above:", "",
            "| N | warning + detection per point [µs] | open–close per extra iteration [ms] | pattern per rebuild [ms] | factor entries | factorisation + solve per iteration and million factor entries [ms] |",
            "|---:|---:|---:|---:|---:|---:|"]
    for r in big:
        t = r["timings"]
        extra = max(r["iterations"] - r["steps"], 1)
        out.append(f"| {r['n']:,} | {1e6 * per_step(r, CONTACT_PHASES[:2]) / r['points']:.2f} | "
                   f"{1e3 * t.get('contact_open_close', 0.0) / extra:.2f} | {1e3 * t.get('contact_pattern', 0.0) / max(r['rebuilds'], 1):.1f} | "
                   f"{r['factor']:,} | {1e9 * (t.get('factorization', 0.0) + t.get('solve', 0.0)) / r['iterations'] / max(r['factor'], 1):.2f} |")
    first, last = big[0], big[-1]
    per = lambda r, k: r[k] / r["n"]  # noqa: E731
    point_us = lambda r: 1e6 * per_step(r, CONTACT_PHASES[:2]) / r["points"]  # noqa: E731
    out += ["", f"Every cube is one cell of the cover, so a block has {per(first, 'dofs'):.0f} equations at N = {first['n']:,} "
            f"and {per(last, 'dofs'):.0f} at {last['n']:,}. (Until 2026-11-27 the cells were 0.5 m and the cubes",
            "0.502 m apart: a cube far from the mesh's origin was cut into up to eight MEs, its equations and",
            "its factor's entries grew with the pile — 27.8 equations and 1,403 entries per block at N = 3,000",
            "against 24 and 1,008 at 1,000 — and the whole step measured as N^1.24–1.30.) Contact points",
            f"per block: {per(first, 'points'):.1f} at N = {first['n']:,}, {per(last, 'points'):.1f} at {last['n']:,}. "
            "The sparsity pattern couples only pairs of MEs with a closed point, so the",
            f"factor follows the contacts: {per(first, 'factor'):,.0f} entries per block at N = {first['n']:,}, "
            f"{per(last, 'factor'):,.0f} at {last['n']:,} (the",
            "columns of the pile touch each other nowhere). Detection takes each step's own margin (twice",
            "how far its points can move, `docs/theory/contact.md`), not the step control's bound, which",
            "grows with the model (0.24 m at N = 8,000) and had made detection per block grow as N^1.6;",
            f"warning and detection now take {', '.join(f'{point_us(r):.2f}' for r in big)} µs per point."]
    return out


def packed_section(rows: list[dict]) -> list[str]:
    """The packed pile: a three-dimensional web of closed contacts."""
    if not rows:
        return []
    out = ["## A packed pile: a web of contacts", "",
           "The same cubes touching side to side and on each other, the whole pile 2 mm above the",
           "floor (`--packed-sizes`): every block touches its neighbours (across faces, edges and",
           "corners) and its springs couple all its covers to all of theirs, as in a jointed rock mass.",
           "The direct factor of that three-dimensional web fills as N^(4/3) and costs N² (George",
           "1973; Lipton, Rose & Tarjan 1979) — the limit of the direct solver for contact, measured:", "",
           "| N | MEs | equations | contact points | open–close iterations | pattern rebuilds | factor entries | factorisation [ms/step] | whole step [ms] |",
           "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        steps = max(r["steps"], 1)
        out.append(f"| {r['n']:,} | {r['elements']:,} | {r['dofs']:,} | {r['points']:,} | {r['iterations']} | {r['rebuilds']} | "
                   f"{r['factor']:,} | {1e3 * r['timings'].get('factorization', 0.0) / steps:.1f} | {1e3 * r['wall'] / steps:.1f} |")
    if len(rows) >= 2:
        a, b = rows[0], rows[-1]
        p = lambda x, y: math.log(y / x) / math.log(b["n"] / a["n"])  # noqa: E731
        out += ["", f"From N = {a['n']:,} to {b['n']:,} the factor's entries grow as N^{p(a['factor'], b['factor']):.2f} and "
                f"the whole step as N^{p(a['wall'] / a['steps'], b['wall'] / b['steps']):.2f}: a rock mass of thousands of",
                "touching blocks costs the direct factor's N² (the iterative solvers tried on these matrices: docs/theory/solver.md)."]
    return out


def write(rows: list[dict], packed: list[dict], dom: dict) -> None:
    lines = [
        "# Performance: contact",
        "",
        "Produced by `python bench/contact.py` (do not edit by hand). Machine: "
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}.",
        "",
        "A pile of N cubes (0.5 m) in columns of four, 2 mm apart, dropped onto a fixed floor; hex8",
        "covers of one cell per cube (cells of 0.502 m, each cube half a gap inside its cell);",
        f"{STEPS} implicit steps of at most 2 ms. Milliseconds per step by phase: warning (candidate",
        "pairs by sort and sweep, rebuilt by the Verlet trigger), detection (contact planes, facet",
        "overlay, transfer of state), pattern (sparsity rebuilds and symbolic analysis when new ME",
        "pairs close: only pairs of MEs with a closed point are coupled), assembly (elastic tangent),",
        "numeric factorisations and triangular solves of all iterations, and the open–close",
        "iterations beyond the first (the wall time of those iterations: contact springs, their",
        "factorisations and solves, state updates). Whole step: wall time of the run per step.",
        "",
        "| N | contact points | steps | open–close iterations | pattern rebuilds | warning | detection | pattern | assembly | factorisation | solve | open–close | whole step [ms] | per block [ms] |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        t = r["timings"]
        steps = max(r["steps"], 1)
        ms = lambda k: 1e3 * t.get(k, 0.0) / steps  # noqa: E731
        total = 1e3 * r["wall"] / steps
        lines.append(
            f"| {r['n']:,} | {r['points']:,} | {r['steps']} | {r['iterations']} | {r['rebuilds']} | {ms('contact_warning'):.2f} | "
            f"{ms('contact_detection'):.2f} | {ms('contact_pattern'):.2f} | {ms('assembly'):.2f} | "
            f"{ms('factorization'):.2f} | {ms('solve'):.2f} | "
            f"{ms('contact_open_close'):.2f} | {total:.1f} | {total / r['n']:.3f} |"
        )
    lines += ["", *growth(rows), "", *packed_section(packed)]
    lines += ["", "## Dominos, two-end run", "",
              f"`examples/dominos.toml` (8 dominos, {dom['time']:.0f} s simulated): {dom['steps']} steps, "
              f"**{dom['wall']:.1f} s** wall on this machine (target < 60 s on 2 cores); up to {dom['points']} contact "
              f"points; largest overlap {dom['penetration']:.1e} m (1 % of the thickness is 1e-3 m). Final tilts [rad]: "
              + ", ".join(f"{t:+.3f}" for t in dom["tilts"]) + f" — dominos {meet(dom['tilts'])} lean together (Λ).", ""]
    (ROOT / "docs" / "performance-contact.md").write_text("\n".join(lines))
    print("wrote docs/performance-contact.md")


if __name__ == "__main__":
    main()
