"""Key blocks of the examples by block theory, and block theory against NMM studies; writes
docs/keyblocks-results.md and the pictures in docs/images/.

Run: python bench/keyblocks_report.py [--no-studies]
(the NMM critical-friction studies of the wedges take a few minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import nmm3d

ROOT = Path(__file__).resolve().parent.parent
CASES = [
    ("goodman_tunnel.toml", [], "Goodman & Shi's tunnel: JP 101 in the roof, JP 100 in the south wall"),
    ("rock_slope.toml", [], "thesis rock slope as given (joints at 26.4°)"),
    ("tunnel_key_blocks.toml", [], "thesis tunnel geometry (joint positions not published)"),
    ("two_wedges.toml", [], "two tetrahedral wedges, 50/130 + 50/230 and 40/130 + 40/230"),
    ("tetrahedral_wedge.toml", [], "tetrahedral wedge 50/130 + 50/230"),
    ("sliding_wedge.toml", [], "the 3DEC sliding wedge, 40/130 + 60/220 on 10 MPa/m joints"),
    ("incline.toml", [], "cube on a 30° plane"),
    ("roof_wedge.toml", ['keyblocks.free_sides=["-z"]'], "roof wedge, its base the free face"),
]
#: (example, block id or None for the monitored block, study overrides)
STUDIES = [("tetrahedral_wedge.toml", None, []), ("sliding_wedge.toml", None, []), ("two_wedges.toml", 1, []), ("two_wedges.toml", 4, []),
           ("goodman_tunnel.toml", 20, []), ("goodman_tunnel.toml", 10, [])]


def case(example: str, overrides: list[str], title: str, images: bool) -> list[str]:
    t = time.perf_counter()
    kb = nmm3d.keyblocks(nmm3d.load(ROOT / "examples" / example, overrides))
    seconds = time.perf_counter() - t
    key = kb.key_blocks()
    flags = " ".join(f"`--set '{o}'`" for o in overrides)
    lines = [f"## `{example}` — {title}", "",
             f"`nmm3d keyblocks examples/{example} --out DIR` {flags}: {len(kb.blocks)} blocks with a free face, "
             f"{sum(b.removable for b in kb.blocks)} removable, {len(key)} key blocks ({seconds:.2f} s).", ""]
    if key:
        lines += ["| id | JP | mode | FS | φc [°] | volume [m³] | trend / plunge [°] | sliding on | may rotate |",
                  "|---:|---|---|---:|---:|---:|---|---|---|"]
        for b in key[:12]:
            m, (tr, pl) = b.mode, b.trend_plunge()
            lines.append(f"| {b.id} | {b.joint_pyramid} | {m.mode} | {m.factor_of_safety:.3f} | "
                         f"{m.critical_friction_angle:.3f} | {b.volume:.4g} | {tr:.1f} / {pl:.1f} | "
                         f"{' + '.join(b.planes[k].label for k in m.planes) or '–'} | "
                         f"{'yes' if b.rotation_warning else ''} |")
        if len(key) > 12:
            lines.append(f"| … | | {len(key) - 12} more | | | | | | |")
        lines.append("")
    if images:
        from nmm3d.key_block_plots import plot_blocks, plot_key_stereonet

        stem = "keyblocks_" + example.removesuffix(".toml")
        plot_blocks(kb, ROOT / "docs" / "images" / f"{stem}.png")
        plot_key_stereonet(kb, ROOT / "docs" / "images" / f"{stem}_stereonet.png")
        lines += [f"![{example}](images/{stem}.png) ![stereonet](images/{stem}_stereonet.png)", ""]
    return lines


def studies(tmp: Path) -> list[str]:
    lines = ["## Block theory against the NMM", "",
             "The critical friction angle of each key block by limit equilibrium (`nmm3d keyblocks`) and by "
             "an NMM critical-friction study (`nmm3d study`: bisection on the friction angle, each run judged "
             "by the block's displacement), on the same scenario file.", "",
             "| example | block | limit equilibrium φc [°] | NMM study bracket [°] | NMM midpoint − LE [°] |",
             "|---|---:|---:|---|---:|"]
    done: dict[str, dict] = {}
    for example, block, overrides in STUDIES:
        if example not in done:
            out = tmp / example
            subprocess.run([sys.executable, "-m", "nmm3d", "study", str(ROOT / "examples" / example), "--out",
                            str(out), "--quiet", *[a for o in overrides for a in ("--set", o)]], check=True)
            done[example] = json.loads((out / "study.json").read_text())
        s = done[example]
        kb = nmm3d.keyblocks(ROOT / "examples" / example)
        b = kb.key_blocks()[0] if block is None else next(x for x in kb.blocks if x.id == block)
        bracket = s["bracket"] if block is None else next(x for x in s["blocks"] if x["id"] == block)["bracket"]
        le = b.mode.critical_friction_angle
        rotates = " (may rotate: the weight line leaves its base)" if b.rotation_warning else ""
        if bracket is None or None in bracket:
            unstable, stable = (bracket or [None, None])
            verdict = (f"unstable at every angle tried, up to {unstable:g}°" if unstable is not None else
                       f"stable at every angle tried, down to {stable:g}°" if stable is not None else "undetermined")
            lines.append(f"| `{example}` | {b.id}{rotates} | {le:.3f} | {verdict} | – |")
            continue
        lo, hi = bracket
        lines.append(f"| `{example}` | {b.id}{rotates} | {le:.3f} | [{lo:.2f}, {hi:.2f}] | {(lo + hi) / 2 - le:+.2f} |")
    return lines + ["", "The study's tolerance is the bracket's width; the NMM angle agrees with limit "
                    "equilibrium to within it wherever translational theory applies. Where the key-block "
                    "analysis flags a block that may rotate (its weight line leaves the face it slides on), "
                    "the NMM may find it failing at friction angles where translation alone would hold it: "
                    "Goodman's roof block, hanging on one steep joint, fails the study's criterion at every "
                    "friction angle tried (the wall block, flagged too, does not).", ""]


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--no-studies", action="store_true")
    args = p.parse_args()
    lines = ["# Key blocks of the examples", "",
             "Produced by `python bench/keyblocks_report.py` (do not edit by hand). What the columns mean: "
             "[keyblocks.md](keyblocks.md).", ""]
    for example, overrides, title in CASES:
        lines += case(example, overrides, title, images=example in ("goodman_tunnel.toml", "rock_slope.toml"))
    if not args.no_studies:
        with tempfile.TemporaryDirectory() as tmp:
            lines += studies(Path(tmp))
    (ROOT / "docs" / "keyblocks-results.md").write_text("\n".join(lines))
    print("wrote docs/keyblocks-results.md")


if __name__ == "__main__":
    main()
