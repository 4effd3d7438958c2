"""The thesis tunnel's key blocks, end to end (thesis Part 5, "Rock tunnel stability analysis");
writes docs/applications/tunnel-key-blocks.md and its pictures.

Run: python bench/tunnel_key_blocks.py [--duration 2] [--tolerance 0.5] [--work DIR] [--reuse-run]

On `examples/tunnel_key_blocks.toml` (three joint sets and local joints around a horseshoe
tunnel along x, five faces held), as a rock engineer would go about it:

1. the cut rock mass against the thesis's description (`nmm3d blocks`);
2. the key blocks by block theory (`nmm3d keyblocks`): the roof and the side-wall key block,
   their failure modes and critical friction angles by limit equilibrium;
3. their critical friction angles by the NMM (`nmm3d study`, a per-block critical-friction
   search: each block judged by its own displacement);
4. the failure at φ = 8° (the thesis's Fig. 5-15/5-16): when each key block leaves the rock
   around it (its fall becomes free: vertical acceleration within 3 % of g), when it first
   strikes something (an upward acceleration of half g) and when it comes to rest, the
   histories and the failure sequence as frames;
5. the same at φ = 8° held by the pattern of grouted rebars that the key-block module designs
   (`examples/tunnel_key_blocks_bolted.toml`, `nmm3d.design_bolt_pattern`): the key blocks'
   factors of safety bare and bolted, the run against the unsupported one, the bars' forces.

The thesis's joint positions are not published; its numbers are quoted beside ours, not
matched. Each step runs in this process; the load average is recorded.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import platform
import shutil
import tempfile
from pathlib import Path

import numpy as np

import nmm3d

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "tunnel_key_blocks.toml"
BOLTED = ROOT / "examples" / "tunnel_key_blocks_bolted.toml"
PAGE = ROOT / "docs" / "applications" / "tunnel-key-blocks.md"
IMAGES = ROOT / "docs" / "images"
G = 9.8
#: The thesis (Part 5, Tables 5-2/5-3, Fig. 5-16).
THESIS = {"blocks": 12, "volume": 277.4533, "excavated": 25.6507, "largest_key": 0.148,
          "roof": {"phi_c": 11.107, "detach": 0.776, "land": 1.172},
          "wall": {"phi_c": 17.645, "detach": 0.709, "land": 1.605}}
#: Friction angle of the failure run (thesis Fig. 5-15).
PHI_FAIL = 8.0
#: Study criterion: a block has failed when its centroid has moved this far [m] at `CRITERION_TIME` [s].
CRITERION = 0.01
CRITERION_TIME = 1.0
#: Free fall: vertical acceleration within this fraction of g.
FREE_FALL = 0.97
#: The stretch of the tunnel the frames show (the key blocks lie at x ≈ 6–7 m) [m].
X_VIEW = (4.0, 8.0)
#: The key blocks' colours in the pictures.
COLOURS = {"roof": "tab:red", "wall": "tab:orange"}


def tunnel_profile(d: dict) -> tuple[float, float, float]:
    """The horseshoe's half width, its floor and crown heights [m] (profile centred on the axis)."""
    t = d["excavation"][0]["shape"]["tunnel"]
    z0 = t["start"][2]
    return t["width"] / 2.0, z0 - t["height"] / 2.0, z0 + t["height"] / 2.0


def classify(kb, half_width: float, crown: float) -> dict[str, object]:
    """The roof key block (its centroid within the span, highest) and the side-wall one (beside
    the span)."""
    key = kb.key_blocks()
    roof = [b for b in key if abs(b.centroid[1]) < half_width and b.centroid[2] > crown - half_width]
    wall = [b for b in key if abs(b.centroid[1]) >= half_width * 0.8 and b not in roof]
    out = {}
    if roof:
        out["roof"] = max(roof, key=lambda b: b.volume)
    if wall:
        out["wall"] = max(wall, key=lambda b: b.volume)
    return out


def study(d: dict, ids: list[int], tolerance: float, out: Path, time: float = CRITERION_TIME) -> dict:
    """Per-block critical friction angles by the NMM (`time`: the criterion's time — a static
    scenario's pseudo-time limit)."""
    d = json.loads(json.dumps(d))
    d.pop("expect", None)
    d["analysis"]["duration"] = time
    d["analysis"]["output_interval"] = 0.0
    d["study"] = {"kind": "critical_friction", "joints": ["joint"], "range": [10.0, 45.0], "tolerance": tolerance,
                  "criterion": {"blocks": ids, "displacement": CRITERION, "time": time}}
    result = nmm3d.Study(nmm3d.Scenario.from_dict(d), out=out).run()
    s = result.summary
    # Each run's own wall time (kept in its record, also when a resumed study reuses it).
    records = [json.loads(p.read_text()) for p in sorted((out / "runs").glob("*/record.json"))]
    s["runs"], s["run_seconds"] = len(records), sum(r.get("wall_seconds", 0.0) for r in records)
    return s


def failure(d: dict, ids: dict[str, int], duration: float, out: Path) -> dict:
    """The run of `d` at φ = 8°: each key block's centroid history."""
    d = json.loads(json.dumps(d))
    d.pop("expect", None)
    d["joint"][0]["friction_angle"] = PHI_FAIL
    d["analysis"]["duration"] = duration
    d["analysis"]["output_interval"] = 0.05
    for name, i in ids.items():
        d["monitor"].append({"name": name, "select": {"block": i}, "quantities": ["displacement", "velocity"]})
    r = nmm3d.Scenario.from_dict(d).run(out=out)
    h = r.history
    return {"summary": r.summary, "history": {k: np.asarray(h[k]) for k in h}}


def events(h: dict, name: str) -> dict[str, float | None]:
    """When the block's fall became free (it left the rock around it), when it first struck
    something (an upward acceleration of half g after it has moved 1 cm) and when it came to
    rest (its centroid within 1 cm of where it ends, from then on) [s]; `None` where it did not."""
    t, vz = h["time"], h[f"{name}.velocity.z"]
    u = np.stack([h[f"{name}.displacement.{c}"] for c in "xyz"], axis=1)
    out: dict[str, float | None] = {"free": None, "impact": None, "rest": None}
    if len(t) < 3:
        return out
    # Accelerations over 10 ms windows (steps are 1 ms; a single step's is noisy at contacts).
    k = max(1, int(round(0.01 / max(np.median(np.diff(t)), 1e-9))))
    az = (vz[k:] - vz[:-k]) / (t[k:] - t[:-k])
    tm = 0.5 * (t[k:] + t[:-k])
    moved = np.linalg.norm(u[:-k], axis=1) > 0.01
    free = np.flatnonzero(np.abs(az + G) <= (1.0 - FREE_FALL) * G)
    out["free"] = float(tm[free[0]]) if len(free) else None
    hit = np.flatnonzero(moved & (az >= 0.5 * G))
    out["impact"] = float(tm[hit[0]]) if len(hit) else None
    away = np.flatnonzero(np.linalg.norm(u - u[-1], axis=1) > 0.01)
    if len(away) and away[-1] + 1 < len(t) and np.linalg.norm(u[-1]) > 0.01:
        out["rest"] = float(t[away[-1] + 1])
    return out


def reused_or_run(d: dict, ids: dict[str, int], duration: float, out: Path, reuse: bool) -> dict:
    """The run of `d` at φ = 8°: the one in `out` if asked and complete, else a new one."""
    if reuse and (out / "summary.json").exists():
        r = nmm3d.Result(out)
        return {"summary": r.summary, "history": {k: np.asarray(v) for k, v in r.history.items()}}
    shutil.rmtree(out, ignore_errors=True)
    return failure(d, ids, duration, out)


def frames(out: Path, ids: dict[str, int], times: list[float], d: dict, path: Path) -> None:
    """The key blocks at `times` inside the tunnel's outline."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import meshio

    import re

    # The frames and their times, from the run's ParaView collection.
    pvd = (out / "result.pvd").read_text()
    found = re.findall(r'timestep="([^"]+)" part="0" file="([^"]+)"', pvd)
    stamps, files = [float(t) for t, _ in found], [out / f for _, f in found]
    fig = plt.figure(figsize=(3.6 * len(times), 4.2))
    for n, t in enumerate(times):
        k = int(np.argmin([abs(s - t) for s in stamps]))
        ax = fig.add_subplot(1, len(times), n + 1, projection="3d")
        key_blocks(ax, meshio.read(files[k]), ids, alpha=0.9)
        ax.set_title(f"t = {stamps[k]:.2f} s", fontsize=9)
        tunnel_view(ax, d, half_width=2.0, above=1.0, elev=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def key_blocks(ax, mesh, ids: dict[str, int], alpha: float) -> None:
    """The key blocks of a frame (a meshio mesh), each in its colour."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ids_of = np.concatenate(mesh.cell_data["block_id"])
    cells = [c for block in mesh.cells for c in block.data]
    for name, b in ids.items():
        polys = [mesh.points[np.asarray(face, dtype=int)] for c in np.flatnonzero(ids_of == b) for face in cells[c]]
        ax.add_collection3d(Poly3DCollection(polys, facecolor=COLOURS[name], edgecolor="none", alpha=alpha))


def tunnel_view(ax, d: dict, half_width: float, above: float, elev: float) -> None:
    """The tunnel's outline over X_VIEW, ±`half_width` across and up to `above` over the crown [m]."""
    half, floor, crown = tunnel_profile(d)
    outline(ax, d, half, floor, crown)
    ax.set_xlim(X_VIEW[0], X_VIEW[1])
    ax.set_ylim(-half_width, half_width)
    ax.set_zlim(floor - 0.2, crown + above)
    ax.set_box_aspect((X_VIEW[1] - X_VIEW[0], 2.0 * half_width, crown - floor + above + 0.2))
    ax.view_init(elev=elev, azim=-60)
    ax.set_axis_off()


def outline(ax, d: dict, half: float, floor: float, crown: float) -> None:
    """The horseshoe's outline at both ends of the model and along its floor corners and crown."""
    centre = crown - half
    arc = [(half * math.cos(a), centre + half * math.sin(a)) for a in np.linspace(0, math.pi, 25)]
    profile = [(half, floor), *arc, (-half, floor), (half, floor)]
    for x in X_VIEW:
        ax.plot([x] * len(profile), [p[0] for p in profile], [p[1] for p in profile], color="0.3", lw=0.8)
    for y, z in ((half, floor), (-half, floor), (half, centre), (-half, centre), (0.0, crown)):
        ax.plot(list(X_VIEW), [y, y], [z, z], color="0.6", lw=0.6)


def histories(run: dict, ids: dict[str, int], ev: dict, path: Path) -> None:
    """Vertical displacement of the key blocks' centroids (the thesis's Fig. 5-16)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = run["history"]
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for name in ids:
        ax.plot(h["time"], h[f"{name}.displacement.z"], color=COLOURS[name], label=f"{name} key block (block {ids[name]})")
        for t, mark in ((ev[name]["free"], "o"), (ev[name]["impact"], "s"), (ev[name]["rest"], "^")):
            if t is not None:
                z = float(np.interp(t, h["time"], h[f"{name}.displacement.z"]))
                ax.plot([t], [z], mark, color=COLOURS[name], ms=6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("centroid displacement z [m]")
    ax.set_title(f"φ = {PHI_FAIL:g}°: ○ the fall becomes free, □ first impact, △ at rest", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def bolt_picture(out: Path, ids: dict[str, int], d: dict, path: Path) -> float:
    """The key blocks and the bars at the bolted run's end, each bar's segments coloured by the
    axial force at their joint; returns the largest force [N]."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import meshio
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    last = sorted((out / "frames").glob("bolts_*.vtu"))[-1]
    bars = meshio.read(last)
    blocks = meshio.read(out / "frames" / last.name.replace("bolts_", "blocks_"))
    force = np.abs(bars.point_data["axial_force"])
    lines = np.concatenate([c.data for c in bars.cells])
    seg_force = force[lines].max(axis=1)
    top = float(force.max())
    fig = plt.figure(figsize=(7.5, 5.0))
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    key_blocks(ax, blocks, ids, alpha=0.6)
    norm = matplotlib.colors.Normalize(0.0, max(top, 1.0) / 1e3)
    segs = bars.points[lines]
    keep = (segs[:, :, 0].min(axis=1) >= X_VIEW[0] - 0.1)
    lc = Line3DCollection(segs[keep], cmap="viridis", norm=norm, linewidths=2.0)
    lc.set_array(seg_force[keep] / 1e3)
    ax.add_collection3d(lc)
    tunnel_view(ax, d, half_width=3.0, above=2.2, elev=14)
    fig.colorbar(lc, ax=ax, shrink=0.6, label="axial force at the joint [kN]")
    ax.set_title(f"φ = {PHI_FAIL:g}° with the designed grouted bars, t = {float(bars.field_data['TimeValue'][0]):.2f} s",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return top


def block_stats(d: dict, tmp: Path) -> dict:
    shutil.rmtree(tmp / "blocks", ignore_errors=True)
    report = nmm3d.Scenario.from_dict(d).write_blocks(tmp / "blocks")
    with open(tmp / "blocks" / "blocks.csv") as f:
        vols = [float(r["volume"]) for r in csv.DictReader(f)]
    return {"report": report, "volumes": vols}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=2.0)
    p.add_argument("--tolerance", type=float, default=0.5)
    p.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "nmm3d_tunnel_key_blocks",
                   help="where the study and the failure run write (a study there is resumed)")
    p.add_argument("--reuse-run", action="store_true", help="take the failure run already in --work")
    args = p.parse_args()
    load = os.getloadavg()[0]
    d = nmm3d.load(EXAMPLE).to_dict()
    half, floor, crown = tunnel_profile(d)
    tmp = args.work
    tmp.mkdir(parents=True, exist_ok=True)
    stats = block_stats(d, tmp)
    kb = nmm3d.keyblocks(EXAMPLE)
    key = classify(kb, half, crown)
    ids = {name: b.id for name, b in key.items()}
    print("key blocks", ids, flush=True)
    from nmm3d.key_block_plots import plot_blocks, plot_key_stereonet

    plot_blocks(kb, IMAGES / "keyblocks_tunnel_key_blocks.png")
    plot_key_stereonet(kb, IMAGES / "keyblocks_tunnel_key_blocks_stereonet.png")
    s = study(d, list(ids.values()), args.tolerance, tmp / "study")
    print("study", json.dumps(s)[:400], flush=True)
    run = reused_or_run(d, ids, args.duration, tmp / "fail", args.reuse_run)
    ev = {name: events(run["history"], name) for name in ids}
    print("events", ev, flush=True)
    histories(run, ids, ev, IMAGES / "tunnel_key_blocks_histories.png")
    marks: list[float] = []
    for x in sorted({0.0, *[x for e in ev.values() for x in e.values() if x is not None], args.duration}):
        if not marks or x - marks[-1] >= 0.05:
            marks.append(x)
    frames(tmp / "fail", ids, marks[:6], d, IMAGES / "tunnel_key_blocks_frames.png")
    write(stats, kb, key, s, run, ev, load, args, bolted(ids, args, tmp))


def bolted(ids: dict[str, int], args, tmp: Path) -> dict:
    """The bolted tunnel at φ = 8°: the key blocks' factors of safety bare and bolted (the
    key-block module on the example with and without its bars) and the run."""
    d = nmm3d.load(BOLTED).to_dict()
    fs = lambda data: {b.id: b.mode.factor_of_safety for b in nmm3d.keyblocks(nmm3d.Scenario.from_dict(data)).blocks}  # noqa: E731
    bars = d["bolt"]
    run = reused_or_run(d, ids, args.duration, tmp / "bolted", args.reuse_run)
    top = bolt_picture(tmp / "bolted", ids, d, IMAGES / "tunnel_key_blocks_bolted.png")
    return {"bare": fs(dict(d, bolt=[])), "held": fs(d), "run": run, "top": top, "bars": len(bars),
            "capacity": min(b.get("yield_force") or math.inf for b in bars), "bond": bars[0].get("bond_strength")}


def bolted_section(key: dict, b: dict, bare_run: dict) -> list[str]:
    """The page's section on the designed bolt pattern."""
    sb, su = b["run"]["summary"], bare_run["summary"]
    h = b["run"]["history"]
    lines = [
        f"## Held by a designed bolt pattern (φ = {PHI_FAIL:g}°)",
        "",
        "`examples/tunnel_key_blocks_bolted.toml`: the same tunnel at φ = 8° with fully grouted 25 mm rebars "
        f"({b['bars']} bars of 2.5 m: vertical ones up into the roof, horizontal ones into the south wall, "
        f"grout bond {b['bond'] / 1e3:g} kN/m, yield {b['capacity'] / 1e3:g} kN) at the spacing "
        "`nmm3d.design_bolt_pattern` chose: the widest, from 2 m down, at which the key-block module gives every "
        "key block FS ≥ 1.5 with the bars' passive support (each bar's axial capacity at the joints of the block "
        "it crosses, min(yield, bond strength × shorter bonded side)); `tests/test_bolts.py` checks that the "
        "example is what the design gives.",
        "",
        "| key block | FS bare (LE) | FS bolted (LE) | centroid displacement at the end, bare [m] | bolted [m] |",
        "|---|---:|---:|---:|---:|",
    ]
    hb = bare_run["history"]
    for name, kblock in key.items():
        disp = lambda hist: float(np.linalg.norm([hist[f"{name}.displacement.{c}"][-1] for c in "xyz"]))  # noqa: E731
        lines.append(f"| {name} (block {kblock.id}) | {b['bare'][kblock.id]:.2f} | {b['held'][kblock.id]:.2f} | "
                     f"{disp(hb):.3f} | {disp(h):.2e} |")
    ratio = sb["steps"] / max(su["steps"], 1)
    lines += [
        "",
        f"The bolted run: {sb['steps']} steps ({sb['step_cuts']} cut) against {su['steps']} unsupported "
        f"(**{ratio:.2f}×**), {sb['wall_seconds']:.0f} s wall against {su['wall_seconds']:.0f} s, deepest overlap "
        f"{1e3 * sb['max_penetration']:.2f} mm, energy balance error "
        f"{100 * ((sb.get('energy') or {}).get('max_error_ratio') or 0):.1f} %. The largest axial force in a bar at a "
        f"joint is {b['top'] / 1e3:.1f} kN ({100 * b['top'] / b['capacity']:.1f} % of its yield force). The frames "
        "draw the bars (`frames/bolts_NNNNN.vtu`, part 2 of `result.pvd`, with `axial_force`, `elongation`, "
        "`shear_force` at each joint):",
        "",
        "![bolted key blocks](../images/tunnel_key_blocks_bolted.png)",
        "",
    ]
    return lines


def reading(key: dict, per_block: dict) -> list[str]:
    """What the two angles say, from the numbers."""
    out = []
    for name, b in key.items():
        br = (per_block.get(b.id) or {}).get("bracket") or [None, None]
        if None in br:
            continue
        diff = 0.5 * (br[0] + br[1]) - b.mode.critical_friction_angle
        if abs(diff) <= 1.0:
            out.append(f"The {name} block fails where limit equilibrium says (within {abs(diff):.2f}°): it slides "
                       "as a rigid block on its joint(s), the surrounding rock clamping it no more than its weight does.")
        else:
            out.append(f"The {name} block holds down to {abs(diff):.1f}° {'below' if diff < 0 else 'above'} its "
                       "limit-equilibrium angle"
                       + (": the rock around it, stressed by its own weight (the initial equilibrium), presses on "
                          "its faces beyond what the block's weight alone gives — the clamping that translational "
                          "theory leaves out and that the thesis also found for its narrow roof block."
                          if diff < 0 else ": something the translational theory leaves out moves it sooner "
                          "(block theory flags it as one that may rotate)." if b.rotation_warning else "."))
    crit = {name: b.mode.critical_friction_angle for name, b in key.items()}
    if {"roof", "wall"} <= crit.keys():
        first = max(crit, key=crit.get)
        out.append(f"As the friction angle falls the {first} block goes first, as in the thesis "
                   f"({'side wall' if first == 'wall' else 'roof'} before {'roof' if first == 'wall' else 'side wall'}; "
                   "the thesis: side wall 17.6°, roof 11.1°).")
    return out


def write(stats, kb, key, s, run, ev, load, args, bolts) -> None:
    r, vols = stats["report"], stats["volumes"]
    fmt = lambda x: "–" if x is None else f"{x:.3f}"  # noqa: E731
    lines = [
        "# Application: key blocks around the thesis tunnel",
        "",
        f"Produced by `python bench/tunnel_key_blocks.py --duration {args.duration:g} --tolerance {args.tolerance:g}` "
        "(do not edit by hand) on `examples/tunnel_key_blocks.toml`. "
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, load average {load:.1f} at the start"
        + (" (the failure run redrawn from an earlier one in `--work`, the study resumed there)." if args.reuse_run else "."),
        "",
        "A horseshoe tunnel (1.8 m wide, 2 m high) along x through three joint sets (50/130, 45/045, 76/090) "
        "and local joints; every face of the model but the top held; rock and contact parameters of the "
        "thesis's Table 5-2 (unit weight 38.57 kN/m³, E = 24.5 GPa, ν = 0.25, φ = 59°, 320 MN/m per "
        "contact point). The thesis does not publish where its joints lie: this model follows its "
        "description with persistent joints (each plane crosses the whole model, so more blocks form than "
        "the thesis's 12), placed so that a roof and a side-wall key block form.",
        "",
        "## The rock mass",
        "",
        "| | this model | thesis |",
        "|---|---:|---:|",
        f"| blocks | {len(vols)} | {THESIS['blocks']} |",
        f"| rock volume [m³] | {sum(vols):.2f} | {THESIS['volume']:.2f} |",
        f"| excavated volume [m³] | {r.get('excavated_volume', float('nan')):.2f} | {THESIS['excavated']:.2f} |",
        f"| smallest / mean / largest block [m³] | {min(vols):.3f} / {np.mean(vols):.2f} / {max(vols):.2f} | – |",
        f"| key blocks (block theory) | {len(kb.key_blocks())} | 2 (roof #11, side wall #12) |",
        f"| largest key block [m³] | {max((b.volume for b in kb.key_blocks()), default=0.0):.3f} | {THESIS['largest_key']} |",
        "",
        "The blocks with a free face and the key blocks (`nmm3d keyblocks`), the joints and the key blocks' "
        "sliding directions on a stereonet (lower hemisphere), and the joint sets as `nmm3d blocks` draws them:",
        "",
        "![key blocks](../images/keyblocks_tunnel_key_blocks.png) "
        "![key-block stereonet](../images/keyblocks_tunnel_key_blocks_stereonet.png)",
        "",
        "![joint stereonet](../images/tunnel_key_blocks_stereonet.png)",
        "",
        "## Key blocks: limit equilibrium against the NMM",
        "",
        f"Limit equilibrium: `nmm3d keyblocks` (Goodman–Shi removability, the vector method). NMM: "
        f"`nmm3d study`, critical friction per block (bisection over 10–45° to {args.tolerance:g}°; a block has failed "
        f"when its centroid has moved {100 * CRITERION:g} cm after {CRITERION_TIME:g} s), "
        f"{s['runs']} runs of {s['run_seconds']:.0f} s in all (two at a time).",
        "",
        "| key block | id | volume [m³] | mode | sliding on | trend / plunge [°] | LE φc [°] | NMM bracket [°] | NMM − LE [°] | thesis NMM φc [°] |",
        "|---|---:|---:|---|---|---|---:|---|---:|---:|",
    ]
    per_block = {b["id"]: b for b in s.get("blocks", [])}
    for name, b in key.items():
        m, (tr, pl) = b.mode, b.trend_plunge()
        nm = per_block.get(b.id, {})
        br = nm.get("bracket") or [None, None]
        mid = None if None in br else 0.5 * (br[0] + br[1])
        on = " + ".join(b.planes[k].label for k in m.planes) or "–"
        lines.append(f"| {name} | {b.id} | {b.volume:.4f} | {m.mode} | {on} | {tr:.1f} / {pl:.1f} | "
                     f"{m.critical_friction_angle:.3f} | [{fmt(br[0])}, {fmt(br[1])}] | "
                     f"{'–' if mid is None else f'{mid - m.critical_friction_angle:+.2f}'} | {THESIS[name]['phi_c']} |")
    lines += ["", *reading(key, per_block), ""]
    summ = run["summary"]
    lines += [
        f"## Failure at φ = {PHI_FAIL:g}°",
        "",
        f"{args.duration:g} s simulated from the static equilibrium: {summ['steps']} steps "
        f"({summ['step_cuts']} cut), {summ['wall_seconds']:.0f} s wall, deepest overlap {1e3 * summ['max_penetration']:.2f} mm, "
        f"energy balance error {100 * ((summ.get('energy') or {}).get('max_error_ratio') or 0):.1f} %. "
        "A key block has left the rock around it when its fall becomes free (vertical acceleration "
        f"within {100 * (1 - FREE_FALL):.0f} % of g, over 10 ms); its first impact is the first upward acceleration "
        "of half g once it has moved 1 cm; it is at rest once its centroid stays within 1 cm of where it ends.",
        "",
        "| key block | falls freely from [s] | first impact [s] | at rest from [s] | centroid drop [m] | thesis: detached / at the bottom [s] |",
        "|---|---:|---:|---:|---:|---|",
    ]
    h = run["history"]
    for name in key:
        e = ev[name]
        drop = -float(h[f"{name}.displacement.z"][-1])
        lines.append(f"| {name} | {fmt(e['free'])} | {fmt(e['impact'])} | {fmt(e['rest'])} | {drop:.2f} | "
                     f"{THESIS[name]['detach']} / {THESIS[name]['land']} |")
    lines += [
        "",
        "![key block histories](../images/tunnel_key_blocks_histories.png)",
        "",
        "The failure sequence (the key blocks in colour inside the tunnel's outline):",
        "",
        "![failure sequence](../images/tunnel_key_blocks_frames.png)",
        "",
        *bolted_section(key, bolts, run),
        "The same tunnel at 30 m depth, excavated after in-situ equilibrium (a staged analysis: the roof key block "
        "clamped by the redistributed stress): [tunnel-staged.md](tunnel-staged.md).",
        "",
    ]
    PAGE.write_text("\n".join(lines))
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
