"""Results of a run, read back from its output directory."""

from __future__ import annotations

import csv
import json
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from nmm3d.summary import RunSummary


class Result:
    """The outputs in ``directory``: summary, monitored history, blocks.

    ``history`` maps ``time``, ``step`` and every ``<monitor>.<quantity>.<component>`` column of
    ``history.csv`` to a numpy array.
    """

    def __init__(self, directory: Path) -> None:
        self.directory = Path(directory)

    @cached_property
    def summary(self) -> dict[str, Any]:
        """Contents of ``summary.json``."""
        return json.loads((self.directory / "summary.json").read_text())

    @cached_property
    def run_summary(self) -> RunSummary:
        """``summary.json`` as a typed :class:`~nmm3d.summary.RunSummary`."""
        return RunSummary.from_dict(self.summary)

    @property
    def status(self) -> str:
        """``"completed"``, ``"failed"``, ``"interrupted"`` (Ctrl-C) or ``"not_converged"`` (a
        static run that reached its duration or ``max_steps`` before equilibrium)."""
        return str(self.summary["status"])

    @property
    def completed(self) -> bool:
        """Whether the run completed."""
        return self.status == "completed"

    @cached_property
    def history(self) -> dict[str, np.ndarray]:
        """Columns of ``history.csv`` as float arrays."""
        return read_columns(self.directory / "history.csv")

    @cached_property
    def blocks(self) -> dict[str, np.ndarray]:
        """Columns of ``blocks.csv`` (``body`` as strings, ``fixed`` as booleans)."""
        return read_columns(self.directory / "blocks.csv")

    def __repr__(self) -> str:
        return f"Result({str(self.directory)!r}, status={self.status!r}, steps={self.summary['steps']})"


def read_columns(path: Path) -> dict[str, np.ndarray]:
    """A CSV file as a dict of numpy arrays (numeric where every value parses)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    out: dict[str, np.ndarray] = {}
    for k, name in enumerate(header):
        col = [r[k] for r in body]
        if name == "fixed":
            out[name] = np.array([c == "true" for c in col], dtype=bool)
            continue
        try:
            out[name] = np.array(col, dtype=float)
        except ValueError:
            out[name] = np.array(col, dtype=str)
    return out
