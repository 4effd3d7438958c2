"""Degenerate cuts at any scale and position (issue 13, item 4): the suite's subset of
`bench/degenerate_cuts.py` (the full 10 000 cases: docs/cutting-degenerate.md). Planes through
a box's corners and edges, on its faces or 1e-8 … 1e-14 of its size off them, pairs as close or
as near parallel, sets on the faces, two sets as near, planes on the faces of an excavated hole; boxes of 1 mm to 1 km, at the origin and at (1e6, 4e6,
1e3) m: nothing refused, the blocks fill the box, and the shifted box is cut alike (up to
which neighbour takes a sliver).
"""

from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
import degenerate_cuts as dc  # noqa: E402


@pytest.mark.parametrize("seed", range(4))
def test_degenerate_cuts_fill_the_box_and_survive_a_shift_to_survey_coordinates(seed):
    rng = random.Random(1000 + seed)
    for _ in range(40):
        r = dc.run_case(rng)
        label = f"{r['kind']}, size {r['size']:.3e} m"
        assert not r["origin"]["error"] and not r["far"]["error"], (label, r["origin"]["error"], r["far"]["error"])
        assert r["origin"]["fill"] < 1e-12, (label, r["origin"]["fill"])
        assert r["far"]["fill"] < dc.resolution(r["size"]), (label, r["far"]["fill"])
        # The same blocks, a sliver below cutting.sliver_ratio merged into another neighbour, or an
        # offset finer than the shifted coordinates carry (another geometry there).
        assert dc.verdict(r) in ("same", "sliver", "unresolved"), (label, len(r["origin"]["volumes"]), len(r["far"]["volumes"]),
                                                     dc.agrees(r)[1])
