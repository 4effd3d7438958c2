"""The static stability check against the dynamic study: the tunnel key blocks' critical-friction
study (`bench/tunnel_key_blocks.py`'s, bisection over 10–45°) on dynamic runs of 1 s (the default
integrator, and Newmark's with contact dashpots), and on static runs with
`analysis.static_travel_limit`, one after the other in one process; then both kinds again on soft
joints (10 MPa/m) from the frictional initial equilibrium. Writes
`docs/performance-static-stability.md`.

    python bench/static_stability.py [--tolerance 0.5] [--damping-ratio 0.3] [--soft-stiffness 1e7]
                                     [--work DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import tempfile
import time
from pathlib import Path

import nmm3d
from _page import write_page
from tunnel_key_blocks import CRITERION, CRITERION_TIME, EXAMPLE, IMAGES, classify, study, tunnel_profile

PAGE = Path(__file__).resolve().parent.parent / "docs" / "performance-static-stability.md"
FIGURE = IMAGES / "static_stability_band.png"
#: The static runs: Δt only regularises; pseudo-time limit [s]; travel limit [m].
STATIC_DT, STATIC_TIME, TRAVEL_LIMIT = 1.0, 20.0, 2.0 * CRITERION


def static(d: dict) -> dict:
    """`d` as a static stability check."""
    d["analysis"].update(kind="static", dt=STATIC_DT, static_travel_limit=TRAVEL_LIMIT)
    return d


def soft(stiffness: float) -> dict:
    """The example on joints of `stiffness` [Pa/m] (normal and shear), from the frictional initial
    equilibrium: the locked one does not converge on joints that close by centimetres."""
    d = nmm3d.load(EXAMPLE, [f"joint.joint.normal_stiffness={stiffness:g}"]).to_dict()
    d["analysis"]["initial_equilibrium"] = "frictional"
    return d


def run_study(d: dict, ids: list[int], tolerance: float, out: Path, t: float) -> dict:
    shutil.rmtree(out, ignore_errors=True)
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    s = study(d, ids, tolerance, out, time=t)
    s["wall"], s["load"] = time.perf_counter() - t0, load
    return s


def row(label: str, s: dict, names: dict[int, str]) -> str:
    brackets = {b["id"]: b["bracket"] for b in s["blocks"]}
    cells = [f"[{brackets[i][0]:.2f}°, {brackets[i][1]:.2f}°]" for i in names]
    return f"| {label} | {s['runs']} | {s['run_seconds']:.0f} | {s['wall']:.0f} | {s['load']:.1f} | " + " | ".join(cells) + " |"


def finals(out: Path) -> list[tuple[float, dict[str, float]]]:
    """Each run of the study in `out`: its friction angle [°] and the blocks' final displacements [m]."""
    records = [json.loads(p.read_text()) for p in (out / "runs").glob("*/record.json")]
    return sorted((r["values"]["value"], r["final"]) for r in records if "final" in r)


def plot(studies: dict[str, Path], names: dict[int, str], key_angles: dict[int, float], path: Path) -> None:
    """Per key block, the final displacement of every study run against its friction angle: where
    each kind of run puts the block's critical angle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(names), figsize=(5.2 * len(names), 3.8), squeeze=False)
    for ax, (bid, name) in zip(axes[0], names.items()):
        for (label, out), marker in zip(studies.items(), "osD^v"):
            pts = [(phi, f[f"block:{bid}"]) for phi, f in finals(out) if f"block:{bid}" in f]
            if pts:
                ax.plot(*zip(*pts), marker=marker, ms=5, lw=0.6, label=label)
        ax.axhline(CRITERION, color="k", lw=0.8, ls="--", label=f"criterion {CRITERION:g} m")
        if bid in key_angles:
            ax.axvline(key_angles[bid], color="grey", lw=0.8, ls=":", label="block theory")
        ax.set(yscale="log", xlabel="friction angle φ [°]",
               ylabel="displacement at the run's end [m]", title=name)
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--tolerance", type=float, default=0.5)
    p.add_argument("--damping-ratio", type=float, default=0.3,
                   help="contact.damping_ratio of the Newmark study (fraction of critical)")
    p.add_argument("--soft-stiffness", type=float, default=1e7,
                   help="joint stiffness of the soft-joint studies [Pa/m]; 0 leaves them out")
    p.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "nmm3d_static_stability")
    args = p.parse_args()
    load0 = os.getloadavg()[0]
    d = nmm3d.load(EXAMPLE).to_dict()
    half, _, crown = tunnel_profile(d)
    key = classify(nmm3d.keyblocks(EXAMPLE), half, crown)
    names = {b.id: f"{name} block {b.id}" for name, b in key.items()}
    dynamic = run_study(d, list(names), args.tolerance, args.work / "dynamic", CRITERION_TIME)
    print("dynamic", dynamic["run_seconds"], dynamic["wall"], flush=True)
    dd = nmm3d.load(EXAMPLE).to_dict()
    dd["analysis"]["integrator"] = "newmark"
    dd.setdefault("contact", {})["damping_ratio"] = args.damping_ratio
    damped = run_study(dd, list(names), args.tolerance, args.work / "damped", CRITERION_TIME)
    print("damped", damped["run_seconds"], damped["wall"], flush=True)
    static_ = run_study(static(nmm3d.load(EXAMPLE).to_dict()), list(names), args.tolerance, args.work / "static",
                        STATIC_TIME)
    print("static", static_["run_seconds"], static_["wall"], flush=True)
    k = args.soft_stiffness
    soft_rows, soft_runs = [], {}
    if k > 0:
        label = f"joints {k / 1e6:g} MPa/m, frictional start"
        soft_dyn = run_study(soft(k), list(names), args.tolerance, args.work / "soft_dynamic", CRITERION_TIME)
        print("soft dynamic", soft_dyn["run_seconds"], soft_dyn["wall"], flush=True)
        soft_static = run_study(static(soft(k)), list(names), args.tolerance, args.work / "soft_static", STATIC_TIME)
        print("soft static", soft_static["run_seconds"], soft_static["wall"], flush=True)
        soft_rows = [row(f"dynamic, {CRITERION_TIME:g} s per run, {label}", soft_dyn, names),
                     row(f"static, travel limit {TRAVEL_LIMIT:g} m, {label}", soft_static, names)]
        soft_runs = {f"dynamic, {label}": args.work / "soft_dynamic", f"static, {label}": args.work / "soft_static"}
    key_angles = {b.id: b.mode.critical_friction_angle for b in key.values()
                  if b.mode.critical_friction_angle is not None}
    plot({"dynamic (default integrator)": args.work / "dynamic",
          f"dynamic, Newmark + dashpots ξ = {args.damping_ratio:g}": args.work / "damped",
          "static, travel limit": args.work / "static", **soft_runs}, names, key_angles, FIGURE)
    head = " | ".join(names.values())
    write_page(PAGE, "Static stability check against the dynamic study: the tunnel's key blocks",
               "static_stability.py", load0, [
        f"`examples/tunnel_key_blocks.toml`, per-block critical friction (`nmm3d study`, bisection over 10–45° "
        f"to {args.tolerance:g}°; a block has failed when its centroid has moved {CRITERION:g} m). Dynamic: "
        f"{CRITERION_TIME:g} s of motion per run (as `docs/applications/tunnel-key-blocks.md`), with the default "
        "integrator (DDA's, which dissipates) and with `analysis.integrator = \"newmark\"` (which does not) and "
        f"contact dashpots at `contact.damping_ratio = {args.damping_ratio:g}` (`docs/theory/contact.md`, "
        "*Contact damping*). Static: "
        f"`analysis.kind = \"static\"`, Δt = {STATIC_DT:g} (a regulariser), pseudo-time limit {STATIC_TIME:g} s, "
        f"`analysis.static_travel_limit = {TRAVEL_LIMIT:g}` m: each run releases the blocks beyond it (no contact "
        "points on them), pins them where they crossed it and stops once the others are in equilibrium "
        "(`docs/user-guide.md`, *Static or dynamic*). "
        + (f"Then the same dynamic and static studies on joints of k_n = k_s = {k / 1e6:g} MPa/m (`--set "
           f"joint.joint.normal_stiffness={k:g}`, the shear stiffness following) from `analysis.initial_equilibrium "
           "= \"frictional\"`; each run's displacement counts from its settled state (`docs/studies.md`). "
           if k > 0 else "")
        + "The studies ran one after the other, two runs at a time each.",
        "",
        f"| runs | number | run seconds | study wall [s] | load at start | {head} |",
        "|---|---:|---:|---:|---:|" + "---|" * len(names),
        row(f"dynamic, {CRITERION_TIME:g} s per run", dynamic, names),
        row(f"dynamic, Newmark + dashpots ξ = {args.damping_ratio:g}, {CRITERION_TIME:g} s per run", damped, names),
        row(f"static, travel limit {TRAVEL_LIMIT:g} m", static_, names),
        *soft_rows,
        "",
        f"Static against dynamic: **{dynamic['run_seconds'] / static_['run_seconds']:.1f}×** less run time, "
        f"{dynamic['wall'] / static_['wall']:.1f}× less study wall time. Block theory (`nmm3d keyblocks`): "
        + ", ".join(f"{names[b.id]} {b.mode.critical_friction_angle:.1f}°" for b in key.values()
                    if b.mode.critical_friction_angle is not None)
        + f". Newmark with dashpots against the default dynamic runs: {damped['run_seconds'] / dynamic['run_seconds']:.2f}× "
        "the run time. Why the roof block's brackets differ: `docs/theory/contact.md` (*Joint elements*); "
        "on soft joints: *Travel from where the analysis starts, at the vertices* there.",
        "",
        "Every run of the studies, each key block's displacement at the run's end against the "
        "friction angle (a static run's block stops where it crossed the travel limit):",
        "",
        f"![final displacements against φ](images/{FIGURE.name})",
    ])


if __name__ == "__main__":
    main()
