"""Plots of monitored histories (matplotlib, headless)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from nmm3d.result import Result


def plot_history(directory: str | Path, out: str | Path | None = None) -> Path:
    """Draw every monitored quantity against time, one panel per monitor and quantity.

    Writes ``history.png`` in ``directory`` unless ``out`` is given; returns the path.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = Result(Path(directory))
    hist = result.history
    groups: dict[str, list[str]] = defaultdict(list)
    for col in hist:
        if col not in ("time", "step"):
            monitor, quantity, _component = col.rsplit(".", 2)
            groups[f"{monitor}.{quantity}"].append(col)
    n = max(len(groups), 1)
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.6 * n), sharex=True, squeeze=False)
    for ax, (title, cols) in zip(axes[:, 0], sorted(groups.items())):
        for col in cols:
            ax.plot(hist["time"], hist[col], label=col.rsplit(".", 1)[1])
        ax.set_title(title, fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    fig.tight_layout()
    path = Path(out) if out is not None else Path(directory) / "history.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
