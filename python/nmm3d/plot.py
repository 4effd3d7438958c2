"""Plots of monitored histories (matplotlib, headless)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from nmm3d.result import Result, read_columns
from nmm3d.units import unit


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
        u = unit(cols[0])
        ax.set_ylabel(f"{title.rsplit('.', 1)[1]} [{u}]" if u else title.rsplit(".", 1)[1])
        ax.legend(fontsize=8, loc="best")
    return _finish(fig, axes, result, Path(out) if out is not None else Path(directory) / "history.png")


ENERGY_COLUMNS = ("kinetic_energy", "elastic_energy", "external_work", "contact_energy",
                  "friction_dissipation", "numerical_dissipation", "energy_error")


def plot_diagnostics(directory: str | Path, out: str | Path | None = None) -> Path:
    """Draw the time step and its cuts, the unbalanced force ratio and (dynamic runs) the energy
    accounts of ``diagnostics.csv`` against time.

    Writes ``diagnostics.png`` in ``directory`` unless ``out`` is given; returns the path.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    result = Result(Path(directory))
    d = read_columns(Path(directory) / "diagnostics.csv")
    energy = [c for c in ENERGY_COLUMNS if c in d and np.any(d[c] != 0.0)]
    n = 3 if energy else 2
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.6 * n), sharex=True, squeeze=False)
    ax = axes[0, 0]
    ax.semilogy(d["time"], d["dt"], lw=1, label="Δt")
    cut = d["cuts"] > 0
    ax.semilogy(d["time"][cut], d["dt"][cut], "rx", ms=4, label="step after cuts")
    ax.set_ylabel("Δt [s]")
    ax.set_title("time step", fontsize=10)
    ax.legend(fontsize=8, loc="best")
    ax = axes[1, 0]
    ax.semilogy(d["time"], np.maximum(d["unbalanced_force_ratio"], 1e-300), lw=1)
    ax.set_ylabel("unbalanced force ratio [–]")
    ax.set_title("unbalanced force / largest applied force", fontsize=10)
    if energy:
        ax = axes[2, 0]
        for c in energy:
            ax.plot(d["time"], d[c], lw=1, label=c.removesuffix("_energy"))
        ax.set_ylabel("energy [J]")
        ax.set_title("energy accounts", fontsize=10)
        ax.legend(fontsize=8, loc="best")
    return _finish(fig, axes, result, Path(out) if out is not None else Path(directory) / "diagnostics.png")


def _finish(fig, axes, result: Result, path: Path) -> Path:
    """Grid, time axis and the run's title on every figure; save and close."""
    import matplotlib.pyplot as plt

    for a in axes[:, 0]:
        a.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(_run_title(result), fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def _run_title(result: Result) -> str:
    s = result.summary if (result.directory / "summary.json").is_file() else {}
    name = result.directory.name
    return f"{name}: {s['status']}, {s['steps']} steps, t = {s['time']:.4g} s" if s else f"{name} (running)"
