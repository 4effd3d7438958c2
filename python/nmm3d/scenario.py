"""Scenarios: loaded from TOML files or built from dictionaries, validated by the Rust core."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Iterable

import numpy as np

from nmm3d import _core
from nmm3d.result import Result


class Scenario:
    """A validated scenario (the public contract, ``docs/scenario.md``).

    Build one with :func:`load` or :meth:`Scenario.from_dict`; both validate in Rust and raise
    :class:`nmm3d.ScenarioError` naming the key path and the reason.
    """

    def __init__(self, canonical_json: str, label: str) -> None:
        self._json = canonical_json
        self.label = label

    @classmethod
    def from_dict(cls, data: dict[str, Any], overrides: Iterable[str] = ()) -> "Scenario":
        """Validate a scenario given as a dictionary shaped like the TOML file."""
        text = json.dumps(data)
        return cls(_core.load_json(text, "<dict>", list(overrides)), "<dict>")

    def to_dict(self) -> dict[str, Any]:
        """The scenario with every default filled in."""
        return json.loads(self._json)

    def with_overrides(self, *overrides: str) -> "Scenario":
        """A copy with ``KEY=VALUE`` overrides applied (as ``--set`` on the command line)."""
        return Scenario(_core.load_json(self._json, self.label, list(overrides)), self.label)

    def run(self, out: str | os.PathLike[str], progress: bool = False, resume: bool = False) -> Result:
        """Run and write the outputs to ``out``; returns the :class:`Result`.

        A run that fails numerically still returns a result with ``status == "failed"`` and
        valid outputs up to the last good step. The GIL is released while computing. Ctrl-C
        stops the run after the current step: the outputs and ``summary.json`` (``status ==
        "interrupted"``) are written, then ``KeyboardInterrupt`` is raised.

        ``resume=True`` continues the run whose ``checkpoint.json`` is in ``out`` (written when
        a run completes or is interrupted, and every ``analysis.checkpoint_interval`` seconds),
        exactly as if it had not stopped; only ``analysis.duration``, ``max_steps`` and
        ``checkpoint_interval`` may differ from the checkpoint's scenario.
        """
        _core.run_json(self._json, self.label, os.fspath(out), progress, resume)
        result = Result(Path(out))
        if result.status == "interrupted":
            raise KeyboardInterrupt(result.summary["message"])
        return result

    def blocks(self) -> dict[str, np.ndarray]:
        """The blocks this scenario makes, as arrays keyed like ``blocks.csv``."""
        table = json.loads(_core.blocks_json(self._json, self.label))
        out = {k: np.asarray(v) for k, v in table.items()}
        out["fixed"] = out["fixed"].astype(bool)
        return out

    def check(self) -> dict[str, Any]:
        """Build what a run builds before its first step (blocks, covers, monitors, bolts, loads,
        the first contact detection; every stage of a staged analysis) without running; raises
        the :class:`ScenarioError` a run would raise. Returns each stage's ``blocks`` and
        ``manifold_elements`` under ``"stages"``."""
        return json.loads(_core.check_json(self._json, self.label))

    def write_blocks(self, out: str | os.PathLike[str]) -> dict[str, Any]:
        """Write ``blocks.csv`` and ``blocks.vtu`` to ``out``; returns the report (count,
        volume statistics, smallest block, excavated volume)."""
        return json.loads(_core.blocks_json(self._json, self.label, os.fspath(out)))

    def __repr__(self) -> str:
        d = self.to_dict()
        name = d.get("scenario", {}).get("name") or self.label
        return f"Scenario({name!r}, bodies={len(d.get('body', []))})"


def load(path: str | os.PathLike[str], overrides: Iterable[str] = ()) -> Scenario:
    """Read and validate a TOML scenario file, with optional ``KEY=VALUE`` overrides."""
    return Scenario(_core.load_file(os.fspath(path), list(overrides)), os.fspath(path))
