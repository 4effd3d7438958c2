"""nmm3d: the three-dimensional numerical manifold method for jointed rock.

>>> import nmm3d
>>> model = nmm3d.load("examples/free_fall.toml")          # doctest: +SKIP
>>> result = model.run(out="out/free_fall")                 # doctest: +SKIP
>>> result.history["cube.displacement.z"][-1]               # doctest: +SKIP
-5.0
"""

import os as _os

# mimalloc (the Rust side's allocator) hands freed pages back to the system 10 ms after they
# are freed; a run then takes them again and the kernel zeroes each anew (zeroing was a quarter
# of a static solve of 10^5 MEs in `perf`). Kept until the process ends: the median of five
# such runs fell from 1.37 to 1.19 s, for a peak about a sixth higher (docs/theory/solver.md).
# Read when `_core` loads, and only if the user has not chosen otherwise.
_os.environ.setdefault("MIMALLOC_PURGE_DELAY", "-1")
# Nor does it ask for transparent huge pages: the kernel then zeroes (and at times first
# compacts) 2 MB at each first touch. Alternating runs of the 10^5-ME solve: 1.43-1.54 s
# (median 1.50) without, 1.51-2.28 s (median 1.55) with; 10^6 MEs 19.0 s against 20.5-24.2 s;
# a pile of 300 touching blocks (factorisation-bound) the same (docs/theory/solver.md).
_os.environ.setdefault("MIMALLOC_ALLOW_THP", "0")

from nmm3d._core import InternalError, NmmError, OutputError, RunError, ScenarioError, __version__
from nmm3d.bolt_design import BoltDesign, design_bolt_pattern
from nmm3d.key_blocks import KeyBlocks, keyblocks
from nmm3d.result import Result
from nmm3d.scenario import Scenario, load
from nmm3d.study import Study, StudyResult
from nmm3d.summary import RunSummary

__all__ = [
    "BoltDesign",
    "InternalError",
    "KeyBlocks",
    "NmmError",
    "OutputError",
    "Result",
    "RunError",
    "RunSummary",
    "Scenario",
    "ScenarioError",
    "Study",
    "StudyResult",
    "__version__",
    "design_bolt_pattern",
    "keyblocks",
    "load",
]
