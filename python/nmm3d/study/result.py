"""A study's outcome, read back from its folder."""

from __future__ import annotations

import json
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from nmm3d.result import read_columns


class StudyResult:
    """``study.json`` as ``summary`` and ``study.csv`` as ``table`` (numpy columns;
    :meth:`to_pandas` for a DataFrame)."""

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory)

    @cached_property
    def summary(self) -> dict[str, Any]:
        return json.loads((self.directory / "study.json").read_text())

    @property
    def kind(self) -> str:
        return str(self.summary["kind"])

    @property
    def status(self) -> str:
        """"completed", "out_of_range", "incomplete" or "failed"."""
        return str(self.summary["status"])

    @property
    def value(self) -> float | None:
        """The study's number: critical friction angle, factor of safety or probability of failure."""
        for key in ("critical_friction_angle", "factor_of_safety", "probability_of_failure"):
            if key in self.summary:
                return self.summary[key]
        return None

    @cached_property
    def table(self) -> dict[str, np.ndarray]:
        return read_columns(self.directory / "study.csv")

    def to_pandas(self) -> Any:
        """``study.csv`` as a pandas DataFrame (pandas must be installed)."""
        import pandas as pd

        return pd.read_csv(self.directory / "study.csv")

    def __repr__(self) -> str:
        return f"StudyResult({str(self.directory)!r}, kind={self.kind!r}, status={self.status!r}, value={self.value!r})"
