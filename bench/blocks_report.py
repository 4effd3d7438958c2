"""Block reports of the thesis rock-mass examples; writes docs/blocks.md and docs/images/.

Run: python bench/blocks_report.py
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

import nmm3d
from nmm3d.stereonet import orientations, plot_stereonet

ROOT = Path(__file__).resolve().parent.parent
CASES = [
    ("tunnel_key_blocks.toml", "Tunnel key blocks (thesis Part 5)",
     "Thesis: 12 blocks, 277.45 m³ of rock, 25.65 m³ excavated (joint positions not published).",
     {"body": "rock mass", "blocks": 12, "volume": 277.4533, "excavated": 25.6507}),
    ("rock_slope.toml", "Rock slope (thesis Part 5)",
     "Thesis: 45 potentially sliding blocks, mean 1.230 m³, smallest 0.416 m³, largest 2.769 m³.",
     {"body": "layer", "blocks": 45, "volume": 45 * 1.22995, "mean": 1.22995, "smallest": 0.4155,
      "largest": 2.7687}),
]


def against_thesis(b: dict, report: dict, thesis: dict) -> list[str]:
    """The blocks of the thesis's body (the rock mass, the slope's layer) against its numbers."""
    v = b["volume"][b["body"] == thesis["body"]]
    ours = {"blocks": int(len(v)), "volume": v.sum(), "mean": v.mean(), "smallest": v.min(), "largest": v.max(),
            "excavated": report["excavated_volume"]}
    fmt = lambda key, x: f"{x:d}" if key == "blocks" else f"{x:.4f}"  # noqa: E731
    rows = [f"| {key} | {fmt(key, ours[key])} | {fmt(key, thesis[key])} | {100 * (ours[key] / thesis[key] - 1):+.1f} % |"
            for key in ("blocks", "volume", "mean", "smallest", "largest", "excavated") if key in thesis]
    return [f"Body `{thesis['body']}` against the thesis (volumes in m³):", "",
            "| | nmm3d | thesis | difference |", "|---|---:|---:|---:|", *rows, ""]


def section(example: str, title: str, thesis: str, numbers: dict, tmp: Path) -> list[str]:
    scenario = nmm3d.load(ROOT / "examples" / example)
    r = scenario.write_blocks(tmp / example)
    b = scenario.blocks()
    image = ROOT / "docs" / "images" / example.replace(".toml", "_stereonet.png")
    plot_stereonet(scenario.to_dict(), image, title=title)
    lines = [f"## {title}", "", f"`nmm3d blocks examples/{example} --out DIR`. {thesis}", "",
             "| blocks | non-convex | convex pieces | total volume [m³] | excavated [m³] | slivers merged / dropped | cutting [s] |",
             "|---:|---:|---:|---:|---:|---|---:|",
             f"| {r['blocks']} | {r['non_convex_blocks']} | {r['pieces']} | {r['total_volume']:.4f} | "
             f"{r['excavated_volume']:.4f} | {r['slivers_merged']} / {r['slivers_dropped']} | {r['cutting_seconds']:.3f} |", ""]
    lines += against_thesis(b, r, numbers)
    lines += ["Joints: " + "; ".join(label for label, _, _ in orientations(scenario.to_dict())) + ".", "",
              f"![stereonet](images/{image.name})", ""]
    for body in sorted(set(b["body"].tolist())):
        sel = b["body"] == body
        v = b["volume"][sel]
        lines.append(f"Body `{body}`: {sel.sum()} blocks, volume {v.sum():.4f} m³, mean {v.mean():.4f}, "
                     f"smallest {v.min():.4g} (id {int(b['id'][sel][np.argmin(v)])}), largest {v.max():.4f} m³.")
    lines += ["", "| id | body | volume [m³] | centroid [m] |", "|---:|---|---:|---|"]
    for i in range(len(b["id"])):
        lines.append(f"| {int(b['id'][i])} | {b['body'][i]} | {b['volume'][i]:.4f} | "
                     f"({b['centroid_x'][i]:.3f}, {b['centroid_y'][i]:.3f}, {b['centroid_z'][i]:.3f}) |")
    return lines + [""]


def main() -> None:
    (ROOT / "docs" / "images").mkdir(parents=True, exist_ok=True)
    lines = ["# Block reports", "", "Produced by `python bench/blocks_report.py` (do not edit by hand).", ""]
    with tempfile.TemporaryDirectory() as tmp:
        for case in CASES:
            lines += section(*case, Path(tmp))
    (ROOT / "docs" / "blocks.md").write_text("\n".join(lines))
    print("wrote docs/blocks.md")


if __name__ == "__main__":
    main()
