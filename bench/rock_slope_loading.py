"""Thesis rock slope under water and an earthquake: limit equilibrium against the NMM; writes
docs/applications/rock-slope-loading.md and docs/images/rock_slope_loading.png.

Run: python bench/rock_slope_loading.py [--duration 2] [--tolerance 0.5]

`examples/rock_slope.toml` (the 1.5 m jointed layer on the 35° slope) at φ = 45°, where it stands
dry (every key block's factor of safety ≥ 1.43: the layer's sliding on the bedrock, tan 45° /
tan 35°), then loaded as a slope engineer checks it: a pseudo-static earthquake (`[seismic]
coefficient`, horizontal, out of the slope), a water table in the joints with a drained slope face
(`[water] free_faces = "drained"`, Hoek & Bray's assumption) and both. For each case the
key-block module's factors of safety (`nmm3d keyblocks`, the same loads) and an NMM run of
`--duration` seconds from rest: which blocks move, and how far. First, the friction angle at
which the slope stands at all, by an NMM study (`nmm3d study`, critical friction: bisection until
no layer block moves 1 cm in 1 s) against block theory's; the same with the layer's lower part held
(like for like with block theory) and with a ten times stiffer joint spring (the soft one lets the
blocks rock). Each case runs in its own process; the machine load is recorded.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "rock_slope.toml"
PAGE = ROOT / "docs" / "applications" / "rock-slope-loading.md"
IMAGE = ROOT / "docs" / "images" / "rock_slope_loading.png"
PHI = 45.0
#: Blocks smaller than this are slivers (the joints' corners at the crest) [m³].
SLIVER = 0.05
#: A block has moved when its mean displacement exceeds this [m].
MOVED = 0.01


def water(table: float) -> list[str]:
    return [f"water.table={table}", 'water.free_faces="drained"']


def quake(k: float) -> list[str]:
    return [f"seismic.coefficient=[{k}, 0.0, 0.0]"]


CASES = {
    "dry": [],
    "earthquake k_h = 0.15": quake(0.15),
    "earthquake k_h = 0.25": quake(0.25),
    "water table z = −7 m": water(-7.0),
    "water table z = −6 m, k_h = 0.1": water(-6.0) + quake(0.1),
}


def per_block_study(d: dict, tolerance: float, out: str) -> tuple[dict, list[dict]]:
    """A critical-friction study of `d`, judged per movable block larger than SLIVER: its summary
    and each block's bracket."""
    import nmm3d

    t = nmm3d.Scenario.from_dict(d).blocks()
    ids = [int(i) for i, fixed, v in zip(t["id"], t["fixed"], t["volume"]) if not fixed and v > SLIVER]
    d = {**d, "study": {"kind": "critical_friction", "joints": ["rock_joint"], "range": [20.0, 50.0],
                        "tolerance": tolerance, "criterion": {"blocks": ids, "displacement": MOVED, "time": 1.0}}}
    s = nmm3d.Study(nmm3d.Scenario.from_dict(d), out=out).run().summary
    volume = {int(i): float(v) for i, v in zip(t["id"], t["volume"])}
    return s, [{"id": b["id"], "bracket": b.get("bracket"), "status": b.get("status"), "volume": volume[b["id"]]}
               for b in s.get("blocks", [])]


#: The thesis's joint spring (Table 5-1: 260 MN/m per contact point), as the example gives it: per
#: point carrying one cell's face (0.26 GPa/m of face) [N/m].
THESIS_SPRING = float(tomllib.loads(EXAMPLE.read_text())["contact"]["normal_stiffness"])
#: Ten times the thesis's spring [N/m]: the layer's blocks then hardly rock on their joints (the
#: stiff-joint study of the page).
STIFF = 10.0 * THESIS_SPRING
#: Contact dashpots of the damped study: a third of critical damping of each block pair's bounce on
#: its joints (`contact.damping_ratio`; restitution 0.37, rock on rock) [-].
DAMPING = 0.3


def study_input(*sets: str) -> dict:
    import nmm3d

    d = nmm3d.load(EXAMPLE, ["analysis.duration=1.0", "analysis.output_interval=0.0", *sets]).to_dict()
    d.pop("expect", None)
    return d


def stable_angle(tolerance: float, out: str) -> dict:
    """The NMM's critical friction angle of the dry slope (a study) and block theory's."""
    import nmm3d

    kb = nmm3d.keyblocks(EXAMPLE)
    key = [b for b in kb.key_blocks() if b.volume > SLIVER]
    le = max(key, key=lambda b: b.mode.critical_friction_angle)
    s, per_block = per_block_study(study_input(), tolerance, out)
    return {"nmm": s.get("critical_friction_angle"), "bracket": s.get("bracket"), "runs": s.get("runs"),
            "status": s.get("search_status"), "blocks": per_block,
            "le": le.mode.critical_friction_angle, "le_block": le.id, "le_mode": le.mode.mode,
            "le_on": " + ".join(le.planes[k].label for k in le.mode.planes),
            "le_of": {b.id: (b.mode.mode, b.mode.critical_friction_angle) for b in kb.blocks}}


def upward_normal(joint_set: dict) -> np.ndarray:
    """The upward unit normal of a joint set's planes (x east, y north, z up)."""
    dip, dd = math.radians(joint_set["dip"]), math.radians(joint_set["dip_direction"])
    return np.array([math.sin(dip) * math.sin(dd), math.sin(dip) * math.cos(dd), math.cos(dip)])


def lone_block_scenario(stiffness: float, phi: float, duration: float, damping: float = 0.0) -> dict:
    """One block of the layer's shape, 1.5 m thick and 1.245 m long down the slope (between two
    planes of the set square to the face), alone on the 35° bedrock, from its initial equilibrium."""
    import nmm3d

    d = study_input(f"joint.rock_joint.friction_angle={phi}", f"analysis.duration={duration}",
                    "analysis.initial_equilibrium=true", f"contact.normal_stiffness={stiffness}",
                    f"contact.damping_ratio={damping}")
    square = d["joint_set"][2]
    n = upward_normal(square)
    o = np.asarray(square["origin"]) - 5 * square["spacing"] * n  # a plane of the set near x = 5 m
    layer = next(b for b in d["body"] if b["name"] == "layer")
    plane = {"dip": square["dip"], "dip_direction": square["dip_direction"]}
    layer["shape"]["convex"]["faces"] += [{**plane, "point": o.tolist(), "keep": "below"},
                                          {**plane, "point": (o - square["spacing"] * n).tolist(), "keep": "above"}]
    layer["shape"]["convex"]["planes"] = [p for p in layer["shape"]["convex"]["planes"] if p[0] == 0.0]
    d["joint_set"] = []
    b = nmm3d.Scenario.from_dict({**d, "monitor": []}).blocks()
    k = int(np.flatnonzero(b["body"] == "layer")[0])
    d["monitor"] = [{"name": "block", "select": {"point": [float(b[f"centroid_{a}"][k]) for a in "xyz"]},
                     "quantities": ["displacement"]}]
    return d


def lone_block(stiffness: float, out: str, reuse: bool, phi: float = 38.0, duration: float = 2.0,
               damping: float = 0.0) -> float:
    """How far that block walks at `phi` in `duration` seconds [m]; `reuse`: the run already in `out`."""
    import nmm3d

    if not (reuse and (Path(out) / "summary.json").exists()):
        nmm3d.Scenario.from_dict(lone_block_scenario(stiffness, phi, duration, damping)).run(out=out)
    f = nmm3d.Result(out).summary["final"]
    return math.sqrt(sum(f[f"block.displacement.{a}"] ** 2 for a in "xyz"))


def held_base(d: dict) -> dict:
    """`d` with the layer split at the one main-set joint that crosses it: the part below (on the
    bedrock) a fixed body, the outer part cut by the cross sets as before."""
    import nmm3d

    main = d["joint_set"][0]
    n = upward_normal(main)
    t = nmm3d.Scenario.from_dict(d).blocks()
    c = np.stack([t[f"centroid_{a}"][t["body"] == "layer"] for a in "xyz"], axis=1)
    k = np.floor((c - main["origin"]) @ n / main["spacing"])  # the blocks lie between joints k and k + 1
    if len(set(k)) != 2:
        raise SystemExit(f"the main set crosses the layer {len(set(k)) - 1} times; one expected")
    plane = {"dip": main["dip"], "dip_direction": main["dip_direction"],
             "point": (np.asarray(main["origin"]) + k.max() * main["spacing"] * n).tolist()}
    layer = next(b for b in d["body"] if b["name"] == "layer")
    base, outer = copy.deepcopy(layer), copy.deepcopy(layer)
    base.update(name="layer_base", fixed=True)
    base["shape"]["convex"]["faces"].append({**plane, "keep": "below"})
    outer.update(name="layer_outer")
    outer["shape"]["convex"]["faces"].append({**plane, "keep": "above"})
    return {**{k: v for k, v in d.items() if k != "monitor"},
            "body": [b for b in d["body"] if b["name"] != "layer"] + [base, outer],
            "joint_set": [{**s, "bodies": ["layer_outer"]} for s in d["joint_set"][1:]]}


def held_angle(tolerance: float, out: str) -> dict:
    """Like for like: the outer layer's blocks on a held base, block theory against a study."""
    import nmm3d

    d = held_base(study_input())
    kb = nmm3d.keyblocks(nmm3d.Scenario.from_dict(d))
    s, per_block = per_block_study(d, tolerance, out)
    return {"runs": s.get("runs"), "blocks": per_block,
            "le_of": {b.id: (b.mode.mode, b.mode.critical_friction_angle) for b in kb.blocks}}


def overrides(case: str, duration: float) -> list[str]:
    return [f"joint.rock_joint.friction_angle={PHI}", f"analysis.duration={duration}",
            "analysis.output_interval=0.5", *CASES[case]]


def limit_equilibrium(case: str) -> dict:
    import nmm3d

    kb = nmm3d.keyblocks(EXAMPLE, overrides=overrides(case, 1.0))
    key = [b for b in kb.key_blocks() if b.volume > SLIVER]
    failing = [b for b in key if b.mode.factor_of_safety < 1.0]
    return {"key": len(key), "min_fs": min(b.mode.factor_of_safety for b in key),
            "failing": sorted(b.id for b in failing), "failing_volume": sum(b.volume for b in failing)}


def final_displacements(out: Path) -> dict[int, dict]:
    """Each movable block's volume, reference centroid and mean displacement at the run's end."""
    import csv

    import meshio

    blocks = {int(r["id"]): r for r in csv.DictReader(open(out / "blocks.csv"))}
    frame = meshio.read(sorted((out / "frames").glob("blocks_*.vtu"))[-1])
    ids = np.concatenate(frame.cell_data["block_id"])
    cells = [c for block in frame.cells for c in block.data]
    disp = frame.point_data["displacement"]
    rows = {}
    for b, r in blocks.items():
        if r["fixed"] == "true":
            continue
        verts = np.unique(np.concatenate([np.asarray(f, dtype=int).ravel() for k in np.flatnonzero(ids == b)
                                          for f in cells[k]]))
        rows[b] = {"volume": float(r["volume"]), "x": float(r["centroid_x"]), "z": float(r["centroid_z"]),
                   "u": float(np.linalg.norm(disp[verts].mean(axis=0)))}
    return rows


def run_case(case: str, duration: float, out: str, reuse: bool = False) -> dict:
    import nmm3d

    if reuse and (Path(out) / "summary.json").exists():
        s = nmm3d.Result(out).summary
    else:
        d = nmm3d.load(EXAMPLE, overrides(case, duration)).to_dict()
        d.pop("expect", None)
        s = nmm3d.Scenario.from_dict(d).run(out=out).summary
    row = {k: s.get(k) for k in ("status", "steps", "step_cuts", "wall_seconds", "max_penetration", "energy")}
    row["blocks"] = final_displacements(Path(out))
    return row


def plot(results: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm

    fig, axes = plt.subplots(len(results), 1, figsize=(8.5, 2.2 * len(results)), sharex=True)
    norm = LogNorm(1e-4, 10.0)
    for ax, (case, res) in zip(axes, results.items()):
        ax.plot([-5, 0, 14.28, 25], [0, 0, -10, -10], color="0.3", lw=1)
        for w in CASES[case]:
            if w.startswith("water.table="):
                ax.axhline(float(w.split("=")[1]), color="tab:blue", lw=0.8, ls="--")
        b = list(res["run"]["blocks"].values())
        sc = ax.scatter([v["x"] for v in b], [v["z"] for v in b], s=[30 * v["volume"] ** (2 / 3) + 4 for v in b],
                        c=[max(v["u"], 1e-4) for v in b], cmap="plasma", norm=norm)
        ax.set_title(case, fontsize=9, loc="left")
        ax.set_ylabel("z [m]")
        ax.set_aspect("equal")
    axes[-1].set_xlabel("x [m]")
    fig.colorbar(sc, ax=axes, shrink=0.6, label="displacement after the run [m]")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--duration", type=float, default=2.0)
    p.add_argument("--tolerance", type=float, default=0.5, help="of the study's friction angle [deg]")
    p.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "nmm3d_rock_slope_loading",
                   help="where the study and the runs write (a study there is resumed)")
    p.add_argument("--reuse-runs", action="store_true", help="take the runs already in --work (redraw the page)")
    p.add_argument("--case", help=argparse.SUPPRESS)
    p.add_argument("--out", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.case:  # one case, in its own process
        run = run_case(args.case, args.duration, args.out, args.reuse_runs)
        print(json.dumps({"run": run, "le": limit_equilibrium(args.case)}))
        return
    results = {}
    tmp = args.work
    tmp.mkdir(parents=True, exist_ok=True)
    load = os.getloadavg()[0]
    stable = stable_angle(args.tolerance, str(tmp / "study"))
    stable["load"] = (load, os.getloadavg()[0])
    print("stable", {k: stable[k] for k in ("nmm", "bracket", "runs", "le")}, flush=True)
    stable["held"] = held_angle(args.tolerance, str(tmp / "held"))
    print("held", stable["held"]["blocks"], flush=True)
    s, per_block = per_block_study(study_input(f"contact.normal_stiffness={STIFF}"), args.tolerance, str(tmp / "stiff"))
    stable["stiff"] = {"runs": s.get("runs"), "bracket": s.get("bracket"), "blocks": per_block}
    stable["lone"] = {k: lone_block(k, str(tmp / f"lone_{k:g}"), args.reuse_runs) for k in (THESIS_SPRING, STIFF)}
    print("stiff", stable["stiff"]["bracket"], flush=True)
    s, per_block = per_block_study(study_input(f"contact.damping_ratio={DAMPING}"), args.tolerance, str(tmp / "damped"))
    stable["damped"] = {"runs": s.get("runs"), "nmm": s.get("critical_friction_angle"), "bracket": s.get("bracket"),
                        "blocks": per_block,
                        "lone": lone_block(THESIS_SPRING, str(tmp / "lone_damped"), args.reuse_runs, damping=DAMPING)}
    print("damped", stable["damped"]["bracket"], flush=True)
    for i, case in enumerate(CASES):
        load = os.getloadavg()[0]
        if not args.reuse_runs:
            shutil.rmtree(tmp / f"c{i}", ignore_errors=True)
        out = subprocess.run([sys.executable, __file__, "--duration", str(args.duration), "--case", case,
                              "--out", str(tmp / f"c{i}"), *(["--reuse-runs"] if args.reuse_runs else [])],
                             check=True, capture_output=True, text=True)
        results[case] = json.loads(out.stdout.strip().splitlines()[-1])
        results[case]["load"] = (load, os.getloadavg()[0])
        print(case, {k: results[case]["run"][k] for k in ("status", "steps", "wall_seconds")}, flush=True)
    plot(results, IMAGE)
    write(results, stable, args)


def stable_section(stable: dict, args) -> list[str]:
    """The friction angle at which the dry slope stands: block theory against the NMM study."""
    groups: dict[tuple, list] = {}
    for b in stable["blocks"]:
        br = b["bracket"] or [None, None]
        groups.setdefault((math.inf if br[0] is None else br[0], br[1] is None, tuple(br)), []).append(b)
    rows = []
    for (_, _, br), bs in sorted(groups.items(), key=lambda kv: kv[0][:2]):
        key = (f"> {br[0]:.1f}° (moves at every φ tried)" if br[0] is not None and br[1] is None
               else f"≤ {br[1]:.1f}° (holds at every φ tried)" if br[0] is None and br[1] is not None
               else f"{br[0]:.2f}–{br[1]:.2f}°" if br[0] is not None else "–")
        ids = sorted(b["id"] for b in bs)
        le_of = stable["le_of"]
        le = sorted({f"{le_of[i][1]:.1f}°" if i in le_of and math.isfinite(le_of[i][1] or math.nan)
                     else le_of.get(i, ("no free face",))[0] for i in ids})
        rows.append(f"| {key} | {len(bs)} | {sum(b['volume'] for b in bs):.2f} | {', '.join(map(str, ids))} | "
                    f"{', '.join(le)} |")
    return [
        f"`examples/rock_slope.toml` — the thesis's jointed layer, 1.5 m thick, on the 35° slope above a road. Block "
        f"theory's most demanding key block larger than {SLIVER:g} m³ (block {stable['le_block']}, {stable['le_mode']}: "
        f"{stable['le_on']}) needs φ ≥ **{stable['le']:.2f}°**. The NMM study (`nmm3d study`, critical friction "
        f"per block over 20–50° to {args.tolerance:g}°: a layer block larger than {SLIVER:g} m³ has failed when it "
        f"moves {100 * MOVED:g} cm within 1 s; {stable['runs']} runs, load {stable['load'][0]:.1f}–"
        f"{stable['load'][1]:.1f}) brackets each block's critical angle:",
        "",
        "| NMM critical angle | blocks | volume [m³] | ids | block theory's critical angle (or mode) |",
        "|---|---:|---:|---|---|",
        *rows,
        "",
        "The thesis's stable case (φ = 26.4°) does not stand in this geometry: its layer rests on a 35° bedrock "
        "surface.",
        "",
        *key_block_table(stable),
        *rocking_section(stable),
        *held_section(stable["held"], args),
    ]


def span(blocks: list[dict]) -> str:
    """The range of the blocks' brackets [°]."""
    lo = [b["bracket"][0] for b in blocks if b["bracket"] and b["bracket"][0] is not None]
    hi = [b["bracket"][1] for b in blocks if b["bracket"] and b["bracket"][1] is not None]
    return f"{min(lo):.2f}–{max(hi):.2f}°" if lo and hi else "–"


def rocking_section(stable: dict) -> list[str]:
    """Why the NMM's angles lie above block theory's at the thesis's joint stiffness."""
    stiff = stable["stiff"]
    le_of = stable["le_of"]
    key = [b for b in stable["blocks"] if math.isfinite((le_of.get(b["id"], ("", math.nan))[1]) or math.nan)]
    key_stiff = [b for b in stiff["blocks"] if b["id"] in {k["id"] for k in key}]
    return [
        "Why the NMM needs more friction here than block theory: the layer's blocks on the bedrock are about as "
        "thick as they are long down the slope (1.0 m × 1.245 m), so the line of their weight leaves the middle "
        "third of their base (offset h/2 · tan 35° = 0.35 m against b/6 = 0.21 m) and the upslope part of the "
        "base lifts. On the thesis's soft joint spring (260 MN/m per contact point) such a block rocks on its "
        "joints after release, and without contact damping the model damps nothing but by friction and the time "
        "scheme: the rocking walks "
        "the blocks down the slope at a few centimetres a second, which the 1 cm-in-1 s criterion counts as "
        "failure. One block of that shape, 1.5 m thick and 1.245 m long, alone on the 35° bedrock at φ = 38° (FS "
        f"1.12) and started from its initial equilibrium, walks {1e3 * stable['lone'][THESIS_SPRING]:.1f} mm in 2 s "
        f"on the thesis's spring and {1e3 * stable['lone'][STIFF]:.2f} mm on a ten times stiffer one "
        "(`lone_block` in the bench script). Block theory's translational limit equilibrium has no rocking. The "
        "same per-block study with "
        f"the joint spring ten times stiffer ({STIFF:.2g} N/m per point; {stiff['runs']} runs): the whole layer "
        f"{span(stiff['blocks'])}, the key blocks {span(key_stiff)} (block theory "
        f"{min(le_of[b['id']][1] for b in key):.2f}–{max(le_of[b['id']][1] for b in key):.2f}°).",
        "",
        *damped_section(stable, key),
    ]


def damped_section(stable: dict, key: list[dict]) -> list[str]:
    """The thesis's soft spring with contact dashpots: the study within 1° of block theory."""
    damped, le_of = stable["damped"], stable["le_of"]
    key_damped = [b for b in damped["blocks"] if b["id"] in {k["id"] for k in key}]
    lo, hi = damped["bracket"] or (math.nan, math.nan)
    return [
        "### Soft joints with contact damping",
        "",
        f"The thesis's spring with contact dashpots (`contact.damping_ratio = {DAMPING:g}`: a viscous damper beside "
        "each closed point's normal spring, a third of critical damping of each block pair's bounce on its joints — "
        "a restitution of 0.37, rock on rock; `docs/theory/contact.md`, *Contact damping*) and the same per-block "
        f"study ({damped['runs']} runs): the slope stands from **{damped['nmm']:.2f}°** (bracket {lo:.2f}–{hi:.2f}°) "
        f"against block theory's {stable['le']:.2f}°; the whole layer {span(damped['blocks'])}, the key blocks "
        f"{span(key_damped)}. The lone block above walks {1e3 * damped['lone']:.1f} mm in 2 s (undamped "
        f"{1e3 * stable['lone'][THESIS_SPRING]:.1f} mm).",
        "",
        *key_block_table({"blocks": damped["blocks"], "le_of": le_of}),
        *riders(key_damped, stable),
    ]


def riders(blocks: list[dict], stable: dict) -> list[str]:
    """The key blocks more than 1° above block theory that need less friction than the layer under them."""
    le_of = stable["le_of"]
    off = [b for b in blocks if b["bracket"] and None not in b["bracket"]
           and 0.5 * sum(b["bracket"]) - le_of[b["id"]][1] > 1.0 and le_of[b["id"]][1] < stable["le"] - 1.0]
    if not off:
        return []
    ids = ", ".join(str(b["id"]) for b in sorted(off, key=lambda b: b["id"]))
    lo, hi = min(le_of[b["id"]][1] for b in off), max(le_of[b["id"]][1] for b in off)
    return [f"Blocks {ids} need less friction on fixed rock (block theory {lo:.2f}–{hi:.2f}°) than the layer they "
            f"rest on, whose blocks slide on the bedrock below {stable['le']:.2f}°: in the whole layer they go with "
            "it, so their angle is the layer's; on a held base (next section) they are judged alone.", ""]


def key_block_table(stable: dict) -> list[str]:
    """Each key block (larger than SLIVER) with block theory's critical angle and the NMM's bracket."""
    le_of, rows, within = stable["le_of"], [], 0
    for b in sorted(stable["blocks"], key=lambda b: b["id"]):
        mode, phi_c = le_of.get(b["id"], ("no free face", None))
        br = b["bracket"] or [None, None]
        if phi_c is None or not math.isfinite(phi_c) or None in br:
            continue
        diff = 0.5 * (br[0] + br[1]) - phi_c
        within += abs(diff) <= 1.0
        rows.append(f"| {b['id']} | {b['volume']:.3f} | {mode} | {phi_c:.2f} | [{br[0]:.2f}, {br[1]:.2f}] | {diff:+.2f} |")
    return [f"The key blocks one by one ({within} of {len(rows)} within 1° of block theory; a positive difference "
            "is a block the NMM moves at friction angles block theory says it holds at):",
            "", "| key block | volume [m³] | mode (block theory) | LE φc [°] | NMM bracket [°] | NMM − LE [°] |",
            "|---:|---:|---|---:|---|---:|", *rows, ""]


def held_section(held: dict, args) -> list[str]:
    """Like for like: the outer layer's blocks on a held base (what block theory assumes)."""
    le_of, rows, within, followers = held["le_of"], [], 0, []
    for b in sorted(held["blocks"], key=lambda b: b["id"]):
        mode, phi_c = le_of.get(b["id"], ("no free face", None))
        br = b["bracket"] or [None, None]
        if phi_c is None or not math.isfinite(phi_c):
            followers.append(b)
            continue
        if None in br:
            rows.append(f"| {b['id']} | {b['volume']:.3f} | {mode} | {phi_c:.2f} | {br} | – |")
            continue
        diff = 0.5 * (br[0] + br[1]) - phi_c
        within += abs(diff) <= 1.0
        rows.append(f"| {b['id']} | {b['volume']:.3f} | {mode} | {phi_c:.2f} | [{br[0]:.2f}, {br[1]:.2f}] | {diff:+.2f} |")
    moved = sorted({tuple(b["bracket"]) for b in followers if b["bracket"] and b["bracket"][0] is not None})
    return [
        "### Like for like: the outer layer on a held base",
        "",
        "Block theory judges each block on fixed rock. The same check by the NMM: the layer's part below the one "
        "main-set joint that crosses it (layer L1, on the bedrock) made a fixed body, the outer layer (L2) cut by "
        f"the cross sets as before, and the same per-block study ({held['runs']} runs; "
        "`held_base` in the bench script). "
        f"{within} of {len(rows)} key blocks within 1° of block theory:",
        "",
        "| key block | volume [m³] | mode (block theory) | LE φc [°] | NMM bracket [°] | NMM − LE [°] |",
        "|---:|---:|---|---:|---|---:|", *rows, "",
        f"The {len(followers)} other outer blocks are not removable alone (block theory: locked by their "
        "neighbours); "
        + (f"in the NMM they move only once the key blocks below them have gone (brackets "
           f"{', '.join(f'[{lo:.2f}, {hi:.2f}]' for lo, hi in moved)}°)." if moved else
           "in the NMM none of them moves within 1 s at any angle tried."),
        "",
    ]


def crest(dry: dict, stable: dict) -> list[str]:
    """What moves in the dry run at φ = PHI, with block theory's verdict."""
    moved = sorted((int(i), b) for i, b in dry["run"]["blocks"].items() if b["u"] > MOVED)
    if not moved:
        return [f"In the dry run at φ = {PHI:g}° no block moves {100 * MOVED:g} cm.", ""]
    le_of = stable["le_of"]

    def verdict(i: int) -> str:
        mode, phi_c = le_of.get(i, ("no free face", None))
        return f"{mode}, φc {phi_c:.1f}°" if phi_c is not None and math.isfinite(phi_c) else mode

    rows = [f"| {i} | {b['volume']:.4f} | {b['x']:.2f}, {b['z']:.2f} | {b['u']:.3f} | {verdict(i)} |" for i, b in moved]
    err = 100 * ((dry["run"].get("energy") or {}).get("max_error_ratio") or 0.0)
    return [f"What moves more than {100 * MOVED:g} cm in the dry run at φ = {PHI:g}° ({dry['run']['steps']} steps), "
            "and what block theory says of each block alone:", "",
            "| block | volume [m³] | reference centroid x, z [m] | displacement [m] | block theory |",
            "|---:|---:|---|---:|---|", *rows, "",
            f"Energy balance error of the dry run: {err:.1f} %.", ""]


def write(results: dict, stable: dict, args) -> None:
    duration = args.duration
    lines = [
        "# Rock slope: water and an earthquake",
        "",
        f"Produced by `python bench/rock_slope_loading.py --duration {duration:g} --tolerance {args.tolerance:g}` "
        f"({platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}; do not edit by hand)"
        + (" — redrawn from the runs and the study already in `--work` (`--reuse-runs`): the wall times are the runs', "
           "the loads the redraw's." if args.reuse_runs else "."),
        "",
        "## Where the slope stands",
        "",
        *stable_section(stable, args),
        *crest(results["dry"], stable),
        "## Water and an earthquake",
        "",
        f"At φ = {PHI:g}° the slope stands dry: block theory gives every key block a factor of safety of at least "
        "1.43 (the layer sliding on the bedrock: tan 45° / tan 35°). The loads a slope engineer then "
        "checks: a pseudo-static earthquake (`[seismic] coefficient = [k_h, 0, 0]`, horizontal, out of the slope), "
        "a water table with a drained slope face (`[water] free_faces = \"drained\"`: the pressure in the joints "
        "and on the layer's base, the open faces dry — Hoek & Bray's assumption) and both. Limit equilibrium: "
        "`nmm3d keyblocks` with the same loads (key blocks larger than "
        f"{SLIVER:g} m³). NMM: a run of {duration:g} s from rest; a block has "
        f"moved when its mean displacement exceeds {100 * MOVED:g} cm.",
        "",
        "| case | LE: key blocks with FS < 1 | their volume [m³] | lowest FS | NMM: blocks moved | their volume [m³] | largest displacement [m] | steps | cuts | energy balance | wall [s] | load |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for case, res in results.items():
        le, run = res["le"], res["run"]
        moved = [b for b in run["blocks"].values() if b["u"] > MOVED]
        err = 100 * ((run.get("energy") or {}).get("max_error_ratio") or 0.0)
        lines.append(f"| {case} | {len(le['failing'])} of {le['key']} | {le['failing_volume']:.2f} | {le['min_fs']:.2f} | "
                     f"{len(moved)} of {len(run['blocks'])} | {sum(b['volume'] for b in moved):.2f} | "
                     f"{max(b['u'] for b in run['blocks'].values()):.3f} | {run['steps']} | {run['step_cuts']} | "
                     f"{err:.1f} % | {run['wall_seconds']:.0f} | {res['load'][0]:.1f}–{res['load'][1]:.1f} |")
    lines += [
        "",
        "![the blocks after each run](../images/rock_slope_loading.png)",
        "",
        "Each block at its reference centroid, sized by its volume and coloured by its displacement at the end of "
        "the run (log scale); the dashed line is the water table. Where limit equilibrium and the NMM differ, the "
        "NMM's blocks act on each other: a block that block theory finds unstable alone may be held by the blocks "
        "below it (or pushed by those above); and on the thesis's joint spring the layer's blocks rock and walk where "
        "their factor of safety is small (above: the cases whose lowest factor of safety lies above 1 but at most "
        f"{max(r['le']['min_fs'] for r in results.values() if r['le']['min_fs'] < 1.2):.2f} move every block a "
        "little). The earthquake here is pseudo-static, a constant force; a shaking "
        "base (`[seismic]` pulses, sines or a record) gives Newmark displacements instead — "
        "[verification.md](../verification.md), section (s).",
        "",
    ]
    PAGE.write_text("\n".join(lines))
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
