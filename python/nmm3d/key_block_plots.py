"""Pictures of a key-block analysis: the blocks in 3-D coloured by factor of safety, and the key
blocks' movement directions on the joints' stereonet."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from nmm3d.stereonet import draw_joints, orientations, project

if TYPE_CHECKING:
    from nmm3d.key_blocks import KeyBlocks

#: Factors of safety at and above this are drawn in the colour of a safe block.
FS_COLOUR_MAX = 2.0


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_blocks(result: "KeyBlocks", path: Path) -> Path:
    """3-D view: every block face in grey, key blocks coloured by factor of safety with arrows
    along their movement, labelled by block id."""
    plt = _pyplot()
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    key = {b.id: b for b in result.key_blocks()}
    cmap = plt.get_cmap("RdYlGn")
    fig = plt.figure(figsize=(8, 6.5))
    ax = fig.add_subplot(projection="3d")
    grey, coloured, colours = [], [], []
    for f in result.surfaces["faces"]:
        poly = np.asarray(f["vertices"], float)
        b = key.get(f["block"])
        if b is None:
            grey.append(poly)
        else:
            coloured.append(poly)
            colours.append(cmap(min(b.mode.factor_of_safety, FS_COLOUR_MAX) / FS_COLOUR_MAX))
    ax.add_collection3d(Poly3DCollection(grey, facecolors=(0.7, 0.7, 0.7, 0.08), edgecolors=(0.3, 0.3, 0.3, 0.2),
                                         linewidths=0.3))
    if coloured:
        ax.add_collection3d(Poly3DCollection(coloured, facecolors=colours, edgecolors="black", linewidths=0.4,
                                             alpha=0.85))
    size = _frame(ax, result.surfaces["bounds"])
    for b in key.values():
        d = b.mode.direction * 0.08 * size
        ax.quiver(*b.centroid, *d, color="black", linewidth=1.2)
        ax.text(*(b.centroid + 1.2 * d), f"{b.id}", fontsize=8)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0.0, FS_COLOUR_MAX))
    fig.colorbar(sm, ax=ax, shrink=0.6, label="factor of safety (key blocks)")
    ax.set_title(f"{len(key)} key blocks of {len(result.blocks)} blocks with a free face", fontsize=10)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return Path(path)


def _frame(ax, bounds) -> float:
    if bounds is None:  # no block left (an excavation took everything)
        return 1.0
    lo, hi = np.asarray(bounds["min"], float), np.asarray(bounds["max"], float)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(np.maximum(hi - lo, 0.05 * float(np.max(hi - lo)))))
    ax.set_xlabel("x (East) [m]")
    ax.set_ylabel("y (North) [m]")
    ax.set_zlabel("z (Up) [m]")
    return float(np.linalg.norm(hi - lo))


def plot_key_stereonet(result: "KeyBlocks", path: Path) -> Path:
    """The joints' great circles with the key blocks' movement directions (lower hemisphere; an
    upward direction plotted as its opposite, hollow), blocks moving alike labelled together."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    draw_joints(ax, result.scenario, "key-block movement directions (lower hemisphere, equal area)")
    groups: dict[tuple[int, int], list] = {}
    for b in result.key_blocks():
        trend, plunge = b.trend_plunge()
        if not math.isnan(trend):
            groups.setdefault((round(trend) % 360, round(plunge)), []).append(b)
    for i, ((trend, plunge), blocks) in enumerate(sorted(groups.items())):
        up = plunge < 0
        x, y = project((trend + 180.0) % 360.0 if up else trend, abs(plunge))
        ax.plot(x, y, "^", ms=8, mfc="none" if up else "black", mec="black")
        fs = [b.mode.factor_of_safety for b in blocks]
        ids = ", ".join(str(b.id) for b in blocks[:6]) + (" …" if len(blocks) > 6 else "")
        text = f"{ids}: FS {min(fs):.2f}" + (f"–{max(fs):.2f}" if max(fs) > min(fs) + 5e-3 else "")
        ax.annotate(text, (x, y), fontsize=7, xytext=(5, 6 - 11 * (i % 3)), textcoords="offset points")
    if orientations(result.scenario):
        ax.legend(loc="lower left", fontsize=7, bbox_to_anchor=(-0.05, -0.08))
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return Path(path)
