"""Studies over many runs: critical friction angle, factor of safety by strength reduction,
sweeps and Monte-Carlo, run in parallel on Dask (``docs/studies.md``)."""

from nmm3d.study.driver import Study
from nmm3d.study.result import StudyResult

__all__ = ["Study", "StudyResult"]
