"""Thesis rock slope, case A (φ = 10°, free collapse): the application page with the block model,
the failure sequence and the nine measuring blocks' histories; writes
docs/applications/rock-slope.md and docs/images/rock_slope_{model,sequence,histories}.png.

Run: python bench/rock_slope_collapse.py [--duration 9] [--work DIR] [--reuse-run]

`examples/rock_slope.toml` at φ = 10° for `--duration` seconds (the thesis ran 9 s), frames every
0.1 s, into `--work` (`--reuse-run` redraws from the run already there). The block statistics
against the thesis's, where the blocks end (slope, transition zone, road), the run's cost and
energy balance. The machine load is recorded.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import re
import tempfile
from pathlib import Path

import numpy as np

import nmm3d
from rock_slope import measuring_blocks  # bench/, the script's folder
from rock_slope_barrier import ROAD, TOE, final_blocks

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "rock_slope.toml"
PAGE = ROOT / "docs" / "applications" / "rock-slope.md"
IMAGES = ROOT / "docs" / "images"
PHI = 10.0
#: Thesis Part 5: 45 blocks, mean, smallest and largest volume [m³].
THESIS = {"blocks": 45, "mean": 1.22995, "smallest": 0.4155, "largest": 2.7687}
#: Layer (L1 on the bedrock, L2 outer) of each block, by its depth below the free face [m].
LAYER_DEPTH = 0.75


def run(duration: float, out: Path, reuse: bool) -> dict:
    if not (reuse and (out / "summary.json").exists()):
        sets = [f"joint.rock_joint.friction_angle={PHI}", f"analysis.duration={duration}"]
        d = nmm3d.load(EXAMPLE, sets).to_dict()
        d.pop("expect", None)
        nmm3d.Scenario.from_dict(d).run(out=out, progress=False)
    return nmm3d.Result(out).summary


def frames_of(out: Path) -> tuple[list[float], list[Path]]:
    """The frames and their times, from the run's ParaView collection."""
    found = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', (out / "result.pvd").read_text())
    return [float(t) for t, _ in found], [out / f for _, f in found]


def layer_blocks(out: Path) -> dict[int, dict]:
    """The layer's blocks: volume, reference centroid and layer (1 on the bedrock, 2 outer)."""
    a = np.radians(35.0)
    rows = {}
    for r in csv.DictReader(open(out / "blocks.csv")):
        if r["body"] != "layer":
            continue
        x, z = float(r["centroid_x"]), float(r["centroid_z"])
        depth = np.sin(a) * -x + np.cos(a) * (1.831161 - z)  # below the layer's free face
        rows[int(r["id"])] = {"volume": float(r["volume"]), "layer": 1 if depth > LAYER_DEPTH else 2}
    return rows


def layer_elements(out: Path, blocks: dict[int, dict]) -> int:
    """The manifold elements of the layer's blocks (cells of the first frame)."""
    import meshio

    of = np.concatenate(meshio.read(frames_of(out)[1][0]).cell_data["block_id"])
    return int(np.isin(of, list(blocks)).sum())


def draw_blocks(ax, mesh, colour_of: dict[int, tuple]) -> None:
    """Each block's outer surface (faces its MEs do not share) in its colour."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    of = np.concatenate(mesh.cell_data["block_id"])
    cells = [c for block in mesh.cells for c in block.data]
    scale = 1e-6 * max(1.0, float(np.abs(mesh.points).max()))
    for b, colour in colour_of.items():
        faces: dict[tuple, np.ndarray] = {}
        for c in np.flatnonzero(of == b):
            for f in cells[c]:
                pts = mesh.points[np.asarray(f, dtype=int)]
                key = tuple(sorted(map(tuple, np.round(pts / scale).astype(np.int64))))
                faces.pop(key, None) if key in faces else faces.__setitem__(key, pts)
        ax.add_collection3d(Poly3DCollection(list(faces.values()), facecolor=colour, edgecolor="none"))


def ground(ax) -> None:
    """The bedrock's profile at both sides of the model."""
    xs, zs = [-5.0, 0.0, TOE, 55.0], [0.0, 0.0, -10.0, -10.0]
    for y in (0.0, 10.0):
        ax.plot(xs, [y] * 4, zs, color="0.4", lw=0.8)
    ax.plot([ROAD, ROAD], [0.0, 10.0], [-10.0, -10.0], color="tab:red", lw=1.0)


def view(ax, xlim=(0.0, 55.0), zoom: float = 1.0) -> None:
    ax.set_xlim(*xlim)
    ax.set_ylim(0.0, 10.0)
    ax.set_zlim(-11.0, 2.0)
    ax.set_box_aspect((xlim[1] - xlim[0], 10.0, 13.0), zoom=zoom)
    ax.view_init(elev=28, azim=-62)
    ax.set_axis_off()


def colours(blocks: dict[int, dict]) -> dict[int, tuple]:
    """Tan for layer L1, blue for L2, each block a little lighter or darker than its neighbours."""
    import matplotlib.colors as mc

    base = {1: np.array(mc.to_rgb("#c9a66b")), 2: np.array(mc.to_rgb("#7fa7c4"))}
    return {b: tuple(np.clip(base[r["layer"]] * (0.8 + 0.1 * (b * 7 % 5)), 0.0, 1.0)) for b, r in blocks.items()}


def model_picture(out: Path, blocks: dict[int, dict], monitors: dict[str, int], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import meshio

    mesh = meshio.read(frames_of(out)[1][0])
    c = colours(blocks)
    for b in monitors.values():
        c[b] = (0.82, 0.29, 0.36)
    fig = plt.figure(figsize=(9, 5))
    ax = fig.add_subplot(projection="3d")
    draw_blocks(ax, mesh, c)
    ground(ax)
    view(ax, (0.0, 11.0))
    ax.set_title("layer L1 on the bedrock (tan), outer layer L2 (blue), the nine measuring blocks (red)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def sequence_picture(out: Path, blocks: dict[int, dict], times: list[float], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import meshio

    stamps, files = frames_of(out)
    rows = (len(times) + 2) // 3
    fig = plt.figure(figsize=(15, 3.4 * rows))
    for n, t in enumerate(times):
        k = int(np.argmin([abs(s - t) for s in stamps]))
        ax = fig.add_subplot(rows, 3, n + 1, projection="3d")
        draw_blocks(ax, meshio.read(files[k]), colours(blocks))
        ground(ax)
        view(ax, zoom=1.15)
        ax.set_title(f"t = {stamps[k]:.1f} s", fontsize=9)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.95, wspace=0.0, hspace=0.05)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def monitor_blocks(d: dict, blocks_csv: Path) -> dict[str, int]:
    """The block under each measuring block's monitor point (the nearest centroid)."""
    rows = list(csv.DictReader(open(blocks_csv)))
    c = np.array([[float(r[f"centroid_{a}"]) for a in "xyz"] for r in rows])
    return {m["name"]: int(rows[int(np.argmin(np.linalg.norm(c - m["select"]["point"], axis=1)))]["id"])
            for m in d["monitor"] if m["name"].startswith("L1-")}


def where(b: dict) -> str:
    """Where a block ended (a row of `final_blocks`)."""
    if not 0.0 <= b["y"] <= 10.0 or b["z"] < -11.0:
        return "off the model"
    return "road" if b["x"] > ROAD else "transition zone" if b["x"] > TOE else "slope"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=9.0)
    p.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "nmm3d_rock_slope_collapse")
    p.add_argument("--reuse-run", action="store_true", help="take the run already in --work")
    args = p.parse_args()
    load = os.getloadavg()[0]
    out = args.work / "case_a"
    s = run(args.duration, out, args.reuse_run)
    print("run", {k: s.get(k) for k in ("status", "steps", "step_cuts", "wall_seconds")}, flush=True)
    d = nmm3d.load(EXAMPLE).to_dict()
    blocks = layer_blocks(out)
    monitors = monitor_blocks(d, out / "blocks.csv")
    IMAGES.mkdir(parents=True, exist_ok=True)
    model_picture(out, blocks, monitors, IMAGES / "rock_slope_model.png")
    times = [t for t in (0.0, 1.0, 2.0, 3.0, 5.0, args.duration) if t <= args.duration]
    sequence_picture(out, blocks, times, IMAGES / "rock_slope_sequence.png")
    measuring_blocks(nmm3d.Result(out).history, IMAGES / "rock_slope_histories.png")  # Fig. 5-4
    ends = {b["id"]: where(b) for b in final_blocks(out) if b["id"] in blocks}
    s["layer_elements"] = layer_elements(out, blocks)
    write(s, blocks, monitors, ends, load, args)


def write(s: dict, blocks: dict[int, dict], monitors: dict[str, int], ends: dict[int, str], load: float,
          args) -> None:
    v = np.array([r["volume"] for r in blocks.values()])
    ours = {"blocks": len(v), "mean": v.mean(), "smallest": v.min(), "largest": v.max()}
    fmt = lambda k, x: f"{x:d}" if k == "blocks" else f"{x:.4f}"  # noqa: E731
    stats = [f"| {k} | {fmt(k, ours[k])} | {fmt(k, THESIS[k])} |" for k in THESIS]
    places = ["slope", "transition zone", "road", "off the model"]
    count = {w: [b for b, e in ends.items() if e == w] for w in places}
    per_layer = {L: sum(1 for r in blocks.values() if r["layer"] == L) for L in (1, 2)}
    e = s.get("energy") or {}
    h = nmm3d.Result(args.work / "case_a").history
    rest = {n: next((float(t) for t, u in zip(h["time"], h[f"{n}.displacement.x"]) if u >= 0.99 * h[f"{n}.displacement.x"][-1]), None)
            for n in monitors}
    lines = [
        "# Application: the thesis rock slope collapsing (case A)",
        "",
        f"Produced by `python bench/rock_slope_collapse.py --duration {args.duration:g}` (do not edit by hand) on "
        f"`examples/rock_slope.toml` at φ = {PHI:g}°. Machine: {platform.machine()}, {os.cpu_count()} cores, "
        f"load average {load:.1f} at the start"
        + (" (redrawn from the run already in `--work`)." if args.reuse_run else "."),
        "",
        "Thesis Part 5: a rock slope above an expressway; a layer of jointed rock on the slope, cut by a main "
        "joint set nearly parallel to the face and two cross sets into 45 blocks that may slide; only the slope's "
        "bottom, the transition zone and the road are fixed, and at φ = 10° the blocks \"slide down freely without "
        "lateral confinement\" (case A). The model: a fixed bedrock (crest plateau, a 35° slope facing east, "
        "the transition zone from the toe at x = 14.28 m and the road from x = 18 m, flat ground beyond); "
        "on it a layer 1.5 m thick, 2 ≤ x ≤ 8.87 m, 3 ≤ y ≤ 7.4 m, cut by the sets 33/090 (one joint crosses "
        "the layer: layer L1 on the bedrock, L2 outside it), 88/000 (groups G1–G3 across the slope) and "
        "55/270 (square to the face: blocks B1 at the crest to B8 at the toe); rock and contact parameters "
        "of Table 5-1 (unit weight 25.7 kN/m³, E = 24.5 GPa, ν = 0.23, 260 MN/m per contact point). The "
        "thesis does not publish its joints' positions; their spacings and origins here were chosen (a search "
        "with `nmm3d blocks`) so that the blocks' statistics match the thesis's:",
        "",
        "| layer blocks | this model | thesis |",
        "|---|---:|---:|",
        *stats,
        "",
        f"Layer L1 has {per_layer[1]} blocks (8 per group), L2 {per_layer[2]} (7 per group). Cover: tet6, 1.45 m; "
        f"the layer has {s['layer_elements']} manifold elements, the whole model {s['manifold_elements']} "
        "(thesis: 1 067) — the fixed bedrock is one, as every fixed body unless meshed "
        "([theory/covers.md](../theory/covers.md#fixed-blocks)). "
        "The joint sets on a stereonet: [blocks.md](../blocks.md).",
        "",
        "![the block model](../images/rock_slope_model.png)",
        "",
        "## The collapse",
        "",
        "| reached t [s] | steps | step cuts | open–close iterations / step | wall [s] | energy balance error | deepest overlap [mm] |",
        "|---:|---:|---:|---:|---:|---:|---:|",
        f"| {s['time']:.2f} ({s['status']}) | {s['steps']} | {s['step_cuts']} | "
        f"{s['open_close_iterations'] / max(s['steps'], 1):.1f} | {s['wall_seconds']:.0f} | "
        f"{100 * (e.get('max_error_ratio') or 0.0):.1f} % | {1e3 * s['max_penetration']:.1f} |",
        "",
        "Where the layer's blocks end (the centroid of each block's final shape): "
        + "; ".join(f"{w}: {len(count[w])} blocks, {sum(blocks[b]['volume'] for b in count[w]):.2f} m³"
                    for w in places) + ".",
        "",
        "![the failure sequence](../images/rock_slope_sequence.png)",
        "",
        "## The measuring blocks (thesis Fig. 5-3 and 5-4)",
        "",
        "The nine measuring blocks are monitored in the example (`[[monitor]]` L1-G1-B1 … L1-G3-B8: layer L1, "
        "groups G1–G3, blocks B1 at the crest, B4 mid-slope and B8 at the toe; the material point at each block's centroid). "
        "Their centroids' displacements, as the thesis's Fig. 5-4 plots them:",
        "",
        "![the measuring blocks' histories](../images/rock_slope_histories.png)",
        "",
        "| block | run-out x [m] | drop z [m] | at 99 % of its run-out from t [s] |",
        "|---|---:|---:|---:|",
        *[f"| {n} | {h[f'{n}.displacement.x'][-1]:.2f} | {h[f'{n}.displacement.z'][-1]:.2f} | "
          f"{'–' if rest[n] is None else f'{rest[n]:.2f}'} |" for n in monitors],
        "",
        "The thesis shows the whole layer sliding off the slope (Fig. 5-2) and the measuring blocks' "
        "curves (Fig. 5-4) without tabulating them; the comparison it allows is the picture. The stable case, "
        "water and earthquakes: [rock-slope-loading.md](rock-slope-loading.md); laterally confined (case B) "
        "and bollards (case D): [rock-slope-barrier.md](rock-slope-barrier.md); the cost of the run against "
        "the time-step controls: [performance-rock-slope.md](../performance-rock-slope.md).",
        "",
    ]
    PAGE.write_text("\n".join(lines))
    print(f"wrote {PAGE}", json.dumps({w: len(count[w]) for w in places}))


if __name__ == "__main__":
    main()
