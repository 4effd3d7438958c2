"""Thesis rock slope, cases A, B and D: the collapsing layer free, confined laterally, and against
bollards; writes docs/applications/rock-slope-barrier.md and docs/images/rock_slope_barrier.png.

Run: python bench/rock_slope_barrier.py [--duration 9] [--only K] [--replot]

`examples/rock_slope_bollards.toml` is the slope of `examples/rock_slope.toml` at φ = 10° (thesis
case A, free collapse) with a row of eleven fixed bollards, 0.45 m wide and 1.7 m high, in the
transition zone between the slope's toe (x = 14.28 m) and the road (x > 18 m). Both it and the
same slope without the bollards (case A) and the slope confined between fixed side walls
(`examples/rock_slope_confined.toml`, case B) run `--duration` seconds (the thesis ran 9 s). The
answer a road engineer asks for: how many blocks, and what volume, end on the road. A
block is on the road when the centroid of its final shape lies beyond x = 18 m, in the
transition zone when it lies between the toe and there. Each case runs in its own process; the
machine load is recorded. `--only K` runs case K alone and keeps the others' rows from `--rows`.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "rock_slope_bollards.toml"
TOE, ROAD = 14.28148007, 18.0  # x of the slope's toe and of the road's edge [m]
WIDTH, GROUND = 10.0, -10.0  # the model's width along y and the road's level [m]


def where(b: dict) -> str:
    """"road", "held" (slope or transition zone) or "off" (left the 10 m wide model over a side
    and fell past the road's level: the model's width, not the barrier)."""
    if not (0.0 <= b["y"] <= WIDTH) or b["z"] < GROUND - 1.0:
        return "off"
    return "road" if b["x"] > ROAD else "held"
CONFINED = ROOT / "examples" / "rock_slope_confined.toml"
CASES = [("without bollards (case A)", "A"), ("laterally confined (case B)", "B"), ("with bollards (case D)", "D")]


def scenario(case: str, duration: float):
    """Case "A" (free), "B" (confined) or "D" (bollards)."""
    import nmm3d

    path = CONFINED if case == "B" else EXAMPLE
    data = nmm3d.load(path, [f"analysis.duration={duration}", "analysis.output_interval=1.0"]).to_dict()
    data.pop("expect", None)
    if case == "A":
        data["body"] = [b for b in data["body"] if not b["name"].startswith("bollard")]
    return nmm3d.Scenario.from_dict(data)


def flat(cell) -> np.ndarray:
    """The point indices of a cell (a polyhedron's come as a list of faces)."""
    try:
        return np.asarray(cell, dtype=int).ravel()
    except ValueError:
        return np.concatenate([flat(face) for face in cell])


def final_blocks(out: Path) -> list[dict]:
    """Each movable block's volume and the centroid of its final shape (mean of its ME vertices)."""
    import csv

    import meshio

    blocks = {int(r["id"]): r for r in csv.DictReader(open(out / "blocks.csv"))}
    frame = meshio.read(sorted((out / "frames").glob("blocks_*.vtu"))[-1])
    rows = []
    ids = np.concatenate(frame.cell_data["block_id"])
    cells = [c for block in frame.cells for c in block.data]
    for b, r in blocks.items():
        if r["fixed"] == "true":
            continue
        verts = np.unique(np.concatenate([flat(cells[k]) for k in np.flatnonzero(ids == b)]))
        c = frame.points[verts].mean(axis=0)
        rows.append({"id": b, "volume": float(r["volume"]), "x": float(c[0]), "y": float(c[1]), "z": float(c[2])})
    return rows


def run_case(case: str, duration: float, out: str) -> dict:
    r = scenario(case, duration).run(out=out)
    s = r.summary
    keys = ("status", "steps", "step_cuts", "wall_seconds", "max_penetration", "energy", "manifold_elements")
    row = {k: s.get(k) for k in keys}
    row["blocks"] = final_blocks(Path(out))
    row["toe"] = float(s["final"]["toe_block.displacement.x"])
    return row


def plot(rows: list[tuple[str, dict]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    fig, axes = plt.subplots(1, len(rows), figsize=(6 * len(rows), 4.2), sharey=True)
    for ax, (title, row) in zip(np.atleast_1d(axes), rows):
        b = row["blocks"]
        x, y, v = (np.array([r[k] for r in b]) for k in ("x", "y", "volume"))
        on_road = np.array([where(r) == "road" for r in b])
        inside = np.array([where(r) != "off" for r in b])
        x, y, v, on_road = x[inside], y[inside], v[inside], on_road[inside]
        ax.scatter(x[~on_road], y[~on_road], s=60 * v[~on_road], c="tab:blue", label="held (slope, transition zone)")
        ax.scatter(x[on_road], y[on_road], s=60 * v[on_road], c="tab:red", label="on the road")
        ax.axvline(TOE, color="0.4", lw=1, ls="--")
        ax.axvline(ROAD, color="k", lw=1)
        ax.text(TOE, 10.2, " toe", fontsize=8)
        ax.text(ROAD, 10.2, " road", fontsize=8)
        if "case D" in title:
            for k in range(11):
                ax.add_patch(Rectangle((16.5, 0.225 + 0.9 * k), 0.45, 0.45, color="0.3"))
        if "case B" in title:
            for y0 in (2.0, 7.0):
                ax.add_patch(Rectangle((2.0, y0), TOE - 2.0, 1.0, color="0.75"))
        ax.set_title(f"{title}: {int(on_road.sum())} blocks, {v[on_road].sum():.2f} m³ on the road "
                     f"({int((~inside).sum())} off the model)", fontsize=9)
        ax.set_xlabel("x [m] (east, down the slope)")
        ax.set_xlim(-2, 45)
        ax.set_ylim(-0.5, 11)
        ax.set_aspect("equal")
    np.atleast_1d(axes)[0].set_ylabel("y [m]")
    np.atleast_1d(axes)[0].legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=9.0)
    p.add_argument("--case", type=int, help=argparse.SUPPRESS)
    p.add_argument("--out", help=argparse.SUPPRESS)
    p.add_argument("--rows", type=Path, default=Path(tempfile.gettempdir()) / "rock_slope_barrier_rows.json",
                   help="where the runs' results are kept (read back with --replot)")
    p.add_argument("--replot", action="store_true", help="write the page and figure from --rows without running")
    p.add_argument("--only", type=int, help="run only case K (0 A, 1 B, 2 D); the others' rows from --rows")
    args = p.parse_args()
    if args.case is not None:
        print(json.dumps(run_case(CASES[args.case][1], args.duration, args.out)))
        return
    if args.replot:
        rows = json.loads(args.rows.read_text())
    elif args.only is not None:
        kept = dict(json.loads(args.rows.read_text())) if args.rows.exists() else {}
        kept.update(run_all(args.duration, [args.only]))
        rows = [(title, kept[title]) for title, _ in CASES if title in kept]
    else:
        rows = run_all(args.duration)
    args.rows.write_text(json.dumps(rows))
    write(rows, args.duration)


def run_all(duration: float, only: list[int] | None = None) -> list:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (title, _) in enumerate(CASES):
            if only is not None and k not in only:
                continue
            load = os.getloadavg()[0]
            cmd = [sys.executable, __file__, "--case", str(k), "--duration", str(duration), "--out",
                   str(Path(tmp) / f"case{k}")]
            done = subprocess.run(cmd, check=True, capture_output=True, text=True)
            row = json.loads(done.stdout.strip().splitlines()[-1])
            row["load"] = (load, os.getloadavg()[0])
            rows.append((title, row))
            print(f"{title}: {row['status']}, {row['steps']} steps, {row['wall_seconds']:.0f} s", flush=True)
    return rows


def write(rows: list, duration: float) -> None:
    images = ROOT / "docs" / "images"
    plot(rows, images / "rock_slope_barrier.png")
    lines = ["# Rock slope, cases A, B and D: free, confined, and bollards in the transition zone", "",
             f"Produced by `python bench/rock_slope_barrier.py --duration {duration:g}` (a case rerun alone with "
             "`--only K` keeps the others' rows; each row records its own load) "
             f"({platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; do not edit by "
             "hand). Thesis Part 5, case D: \"a group of concrete columns (bollards) with a width of 450 mm and a "
             "height of 1700 mm are set at the transition zone between the highway and the potential failure "
             "slope … most of falling blocks are fended within the transition zone; some small-volume blocks "
             "fall outside to the road\".", "",
             "`examples/rock_slope_bollards.toml`: the layer of `examples/rock_slope.toml` (45 blocks, 1.5 m thick, "
             "on the 35° slope) at φ = 10° (case A, free collapse) against eleven fixed bollards, 0.45 × 0.45 × "
             "1.7 m, at x = 16.5–16.95 m, 0.45 m apart across the 10 m wide model (the thesis gives their size "
             "and place, not their spacing; no wire netting, as in the thesis). Without bollards: the same file "
             "with them removed (case A: \"free sliding without lateral constraints\"). Case B "
             "(`examples/rock_slope_confined.toml`): case A with the rock continuing beyond the layer's two sides "
             "as fixed walls 1 m thick along the slope to its toe, which the blocks rub against with the joints' "
             "friction — the lateral condition the thesis compares A with (its case B is not described further in "
             "the summary we have). A block is *on the road* when the centroid of its final shape lies beyond "
             f"x = {ROAD:g} m, *held* otherwise (on the slope or in the transition zone between the toe, "
             f"x = {TOE:.2f} m, and the road).", "",
             "| case | blocks on the road | their volume [m³] | largest there [m³] | blocks held | off the model "
             "(volume [m³]) | toe block's run-out [m] | steps | cuts | energy balance | deepest overlap [mm] | "
             "wall [s] | load |",
             "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---|"]
    for title, row in rows:
        b = row["blocks"]
        road = [r for r in b if where(r) == "road"]
        off = [r for r in b if where(r) == "off"]
        largest = max((r["volume"] for r in road), default=0.0)
        energy = row["energy"] or {}
        lines.append(f"| {title} | {len(road)} of {len(b)} | {sum(r['volume'] for r in road):.2f} of "
                     f"{sum(r['volume'] for r in b):.2f} | {largest:.3f} | {len(b) - len(road) - len(off)} | "
                     f"{len(off)} ({sum(r['volume'] for r in off):.2f}) | {row['toe']:.2f} | "
                     f"{row['steps']} | {row['step_cuts']} | {100 * energy.get('max_error_ratio', float('nan')):.1f} % | "
                     f"{1e3 * row['max_penetration']:.1f} | {row['wall_seconds']:.0f} | "
                     f"{row['load'][0]:.1f}–{row['load'][1]:.1f} |")
    lines += ["", "![final block positions, plan view](../images/rock_slope_barrier.png)", "",
              "Dots: each block's final centroid, sized by its volume (red: on the road). *Off the model*: "
              "blocks that left the 10 m wide model over a side (beside the road, or thrown sideways off a "
              "bollard) and fell past the road's level — the model's width, not the barrier, decides where "
              "they end. Energy balance: the "
              "largest balance error over the run relative to the largest energy account "
              "([theory/energy.md](../theory/energy.md)). The bollards are fixed bodies in contact like the "
              "bedrock; their own strength is not modelled (\"sturdy enough\", as the thesis assumes).", ""]
    (ROOT / "docs" / "applications" / "rock-slope-barrier.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
