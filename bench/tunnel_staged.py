"""The thesis tunnel excavated after in-situ equilibrium (staged analysis); writes
docs/applications/tunnel-staged.md and its pictures.

Run: python bench/tunnel_staged.py [--duration 2] [--work DIR] [--reuse-runs]

Three runs of the thesis tunnel's rock mass (`examples/tunnel_key_blocks*.toml`), the roof and
side-wall key blocks (ids 21 and 24, the same in every run: a staged model numbers its rock as
the unstaged one) monitored:

1. excavated at 30 m depth after in-situ equilibrium, φ = 8° (`tunnel_key_blocks_staged.toml`:
   stage "in-situ" with the tunnel's rock in place, stage "excavate" removes it);
2. the same at φ = 59° (the thesis's rock);
3. without in-situ stress, the tunnel open from the start, φ = 8° (`tunnel_key_blocks.toml`:
   what the thesis and the key-block application page run);
4. as 2, the excavation stage static (`set = { "analysis.kind" = "static" }`, 200 iterations):
   the redistribution without the dynamics of an instantaneous excavation.

The load average is recorded; each run's own wall time is in its summary.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
from pathlib import Path

import numpy as np

import nmm3d

ROOT = Path(__file__).resolve().parent.parent
STAGED = ROOT / "examples" / "tunnel_key_blocks_staged.toml"
BARE = ROOT / "examples" / "tunnel_key_blocks.toml"
PAGE = ROOT / "docs" / "applications" / "tunnel-staged.md"
IMAGES = ROOT / "docs" / "images"
KEY = {"roof": 21, "wall": 24}
#: The tunnel's cross-section the stress picture shows: MEs with centroid x in this band [m].
SLICE = (3.5, 4.5)
#: The run whose excavation stage is static.
STATIC = "staged, static excavation, φ = 59°"


def runs(duration: float) -> dict[str, tuple[Path, list[str]]]:
    """Name → (scenario, overrides) of each run."""
    monitors = [f'monitor.{n}_key_block.quantities=["displacement", "velocity"]' for n in KEY]
    return {
        "staged, φ = 8°": (STAGED, [f"stage.excavate.duration={duration}", *monitors]),
        "staged, φ = 59°": (STAGED, [f"stage.excavate.duration={duration}", "joint.joint.friction_angle=59", *monitors]),
        "no in-situ stress, φ = 8°": (BARE, [f"analysis.duration={duration}", "joint.joint.friction_angle=8",
                                             "analysis.output_interval=0.05", *monitors]),
        STATIC: (STAGED, ["joint.joint.friction_angle=59", *monitors]),
    }


def run(name: str, spec: tuple[Path, list[str]], out: Path, reuse: bool) -> nmm3d.Result:
    if reuse and (out / "summary.json").exists():
        return nmm3d.Result(out)
    shutil.rmtree(out, ignore_errors=True)
    print(f"running {name} …", flush=True)
    path, overrides = spec
    s = nmm3d.load(path, overrides)
    d = s.to_dict()
    d.pop("expect", None)
    if name == STATIC:
        d["stage"][1].update(duration=200.0, set={"analysis.kind": "static", "analysis.dt": 1.0,
                                                  "analysis.equilibrium_tolerance": 1e-5})
    return nmm3d.Scenario.from_dict(d).run(out=out)


def excavated_at(r: nmm3d.Result) -> float:
    stages = r.summary.get("stages") or []
    return stages[0]["end_time"] if stages else 0.0


def key_block_rows(results: dict[str, nmm3d.Result]) -> list[str]:
    rows = []
    for name, r in results.items():
        h, t0 = r.history, excavated_at(r)
        cells: list[str] = []
        for n in KEY:
            u = np.stack([h[f"{n}_key_block.displacement.{c}"] for c in "xyz"], axis=1)
            v = np.stack([h[f"{n}_key_block.velocity.{c}"] for c in "xyz"], axis=1)
            after = h["time"] >= t0
            du = np.linalg.norm(u[-1] - u[np.argmax(after)])
            cells += [f"{du:.3g}", f"{np.linalg.norm(v[after], axis=1).max():.3g}"]
        crown = h["crown.displacement.z"]
        s = r.summary
        rows.append(f"| {name} | " + " | ".join(cells) + f" | {1e3 * (crown[-1] - crown[np.argmax(h['time'] >= t0)]):.3f}"
                    f" | {s['steps']} | {s['step_cuts']} | {s['wall_seconds']:.0f} |")
    return rows


def histories(results: dict[str, nmm3d.Result], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
    for ax, n in zip(axes, KEY):
        for (name, r), style in zip(results.items(), ["-", "--", ":", "-."]):
            if name == STATIC:
                continue
            h, t0 = r.history, excavated_at(r)
            u = np.stack([h[f"{n}_key_block.displacement.{c}"] for c in "xyz"], axis=1)
            after = h["time"] >= t0
            d = np.linalg.norm(u[after] - u[np.argmax(after)], axis=1)
            ax.semilogy(h["time"][after] - t0, np.maximum(d, 1e-7), style, label=name)
        ax.set_title(f"{n} key block (block {KEY[n]})")
        ax.set_xlabel("time since the excavation [s]")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("centroid displacement [m]")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def frame_at(r: nmm3d.Result, t: float) -> Path:
    import xml.etree.ElementTree as ET

    sets = ET.parse(r.directory / "result.pvd").getroot().findall("./Collection/DataSet")
    blocks = [s for s in sets if s.get("part", "0") == "0"]
    best = min(blocks, key=lambda s: abs(float(s.get("timestep")) - t))
    return r.directory / best.get("file")


def major_stress(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Centroids (y, z) of the MEs in the slice and their most compressive principal stress [MPa]."""
    import pyvista

    mesh = pyvista.read(path)
    c = np.asarray(mesh.cell_centers().points)
    s = np.asarray(mesh.cell_data["stress"]).reshape(-1, 6)
    keep = (c[:, 0] > SLICE[0]) & (c[:, 0] < SLICE[1])
    m = np.zeros((keep.sum(), 3, 3))
    for (i, j), k in {(0, 0): 0, (1, 1): 1, (2, 2): 2, (0, 1): 3, (1, 2): 4, (0, 2): 5}.items():
        m[:, i, j] = m[:, j, i] = s[keep, k]
    return c[keep][:, 1:], np.linalg.eigvalsh(m)[:, 0] / 1e6


def stress_picture(r: nmm3d.Result, path: Path) -> tuple[float, float]:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t0 = excavated_at(r)
    before, after = major_stress(frame_at(r, t0)), major_stress(frame_at(r, r.summary["time"]))
    # A few thin MEs at joint corners carry peaks tens of times the field's; the colours show the field.
    lo = float(np.percentile(np.concatenate([before[1], after[1]]), 2))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), sharey=True)
    for ax, (yz, s), title in zip(axes, (before, after), (f"before (t = {t0:g} s)", f"after (t = {r.summary['time']:g} s)")):
        sc = ax.scatter(yz[:, 0], yz[:, 1], c=s, s=9, cmap="viridis", vmin=lo, vmax=0.0)
        ax.set_facecolor("0.85")
        ax.set_aspect("equal")
        ax.set_title(f"most compressive principal stress σ₃, {title}", fontsize=8)
        ax.set_xlabel("y [m]")
    axes[0].set_ylabel("z [m]")
    fig.colorbar(sc, ax=axes, label="σ₃ [MPa] (compression negative; 2 % of MEs beyond the scale)", shrink=0.8)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    near = lambda yz: (np.abs(yz[:, 0]) < 0.5) & (yz[:, 1] > 1.0) & (yz[:, 1] < 1.6)
    return float(before[1][near(before[0])].mean()), float(after[1][near(after[0])].mean())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--duration", type=float, default=2.0, help="simulated time after the excavation [s]")
    ap.add_argument("--work", type=Path, default=Path("/tmp/nmm3d_tunnel_staged"))
    ap.add_argument("--reuse-runs", action="store_true", help="take the runs already in --work")
    args = ap.parse_args()
    load = os.getloadavg()
    results = {}
    for k, (name, spec) in enumerate(runs(args.duration).items()):
        results[name] = run(name, spec, args.work / f"run{k}", args.reuse_runs)
    IMAGES.mkdir(parents=True, exist_ok=True)
    histories(results, IMAGES / "tunnel_staged_histories.png")
    crown = stress_picture(results["staged, φ = 8°"], IMAGES / "tunnel_staged_stress.png")
    write(results, crown, load, args)


def moved(r: nmm3d.Result, block: str, within: float | None = None) -> float:
    """How far a key block's centroid moved after the excavation (within `within` s of it, or by
    the end) [m]."""
    h, t0 = r.history, excavated_at(r)
    u = np.stack([h[f"{block}_key_block.displacement.{c}"] for c in "xyz"], axis=1)
    end = -1 if within is None else int(np.searchsorted(h["time"], t0 + within))
    return float(np.linalg.norm(u[end] - u[np.argmax(h["time"] >= t0)]))


def reading(results: dict[str, nmm3d.Result]) -> list[str]:
    s8, s59, bare, st = (results[k] for k in results)
    ratio = st.summary["unbalanced_force_ratio"]
    return [
        f"Reading it. The roof block, wedged between joints the in-situ stress presses together, is clamped: at φ = 8° "
        f"it moves {1e3 * moved(s8, 'roof', 0.1):.1f} mm in the first 0.1 s and {1e3 * moved(s8, 'roof'):.1f} mm by "
        "the end, where without in-situ stress it falls "
        f"{moved(bare, 'roof'):.2f} m — the stress the excavation redistributes holds it, which limit equilibrium "
        "under gravity alone cannot see. The wall block, a thin slab at the wall's surface, is thrown out at φ = 8° "
        f"({moved(s8, 'wall'):.2f} m) and at φ = 59° too ({moved(s59, 'wall'):.2f} m): the excavation here is "
        "instantaneous — one step releases the tractions the tunnel's rock carried — and the elastic energy set "
        "free in the rock and in the joints' springs kicks a small block at the surface off, as a blast would. "
        f"Excavated by a static stage instead, the same block moves {1e3 * moved(st, 'wall'):.1f} mm at φ = 59° "
        f"(status `{st.summary['status']}` after {st.summary['stages'][1]['end_step'] - st.summary['stages'][1]['start_step']} "
        f"iterations, unbalanced-force ratio {ratio:.2g}: contact states near the wall keep changing). A gradual "
        "release of the excavation's tractions, as 3DEC and FLAC relax an excavation, is not built yet "
        "([../theory/stages.md](../theory/stages.md#limits)).",
    ]


def write(results: dict[str, nmm3d.Result], crown: tuple[float, float], load, args) -> None:
    staged = results["staged, φ = 8°"].summary
    lines = [
        "# The thesis tunnel excavated after in-situ equilibrium",
        "",
        f"Produced by `python bench/tunnel_staged.py --duration {args.duration:g}` (nmm3d {nmm3d.__version__}, "
        f"{platform.machine()}, {os.cpu_count()} cores, load average {load[0]:.2f} at the start"
        + (", runs already in `--work` reused" if args.reuse_runs else "") + "). Do not edit by hand.",
        "",
        "The thesis tunnel's rock mass ([tunnel-key-blocks.md](tunnel-key-blocks.md): three joint sets and three local "
        "joints around a horseshoe tunnel along x, five faces held) placed at 30 m depth: 1.157 MPa of overburden on its "
        "top face and a lithostatic in-situ stress, the same in every direction. A staged analysis "
        "([../theory/stages.md](../theory/stages.md), `examples/tunnel_key_blocks_staged.toml`): stage \"in-situ\" holds "
        "the tunnel's rock in place, bonded to the rock around it, from the locked initial equilibrium for "
        f"{staged['stages'][0]['end_time']:g} s; stage \"excavate\" removes it at once and the rock mass moves for "
        f"{args.duration:g} s. The key blocks are the roof block 21 (0.22 m³, limit-equilibrium φ_c = 22.6°) and the "
        "side-wall block 24 (0.041 m³, φ_c = 28°); without in-situ stress both fall at φ = 8°.",
        "",
        "| run | roof block: displacement after the excavation [m] | roof: largest speed [m/s] | wall block: displacement [m] "
        "| wall: largest speed [m/s] | crown settlement since the excavation [mm] | steps | step cuts | wall time [s] |",
        "|---|---|---|---|---|---|---|---|---|",
        *key_block_rows(results),
        "",
        "![key-block histories](../images/tunnel_staged_histories.png)",
        "",
        "The excavation takes away the tractions the tunnel's rock put on the rock around it; the stress flows round the "
        f"opening. Above the crown (|y| < 0.5 m, z = 1–1.6 m, x = {SLICE[0]:g}–{SLICE[1]:g} m) the most compressive "
        f"principal stress goes from {crown[0]:.2f} MPa before the excavation to {crown[1]:.2f} MPa at the end:",
        "",
        "![stress before and after](../images/tunnel_staged_stress.png)",
        "",
        *reading(results),
        "",
        "Regenerate: `python bench/tunnel_staged.py` (each run's wall time above; `--reuse-runs` redraws from the runs "
        "in `--work`).",
        "",
    ]
    PAGE.write_text("\n".join(lines))
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
