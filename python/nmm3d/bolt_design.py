"""Designing a bolt pattern with the key-block module (Hoek, *Practical Rock Engineering*,
ch. 10): over each face given, bolts at a common spacing, the widest spacing at which every key
block reaches the target factor of safety with the bolts' passive support (``nmm3d keyblocks``
counts them as a run has them: an anchored bolt's yield force, a grouted bar's axial capacity at
each joint of the block it crosses)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: Spacings tried, widest first [m].
SPACINGS = (2.0, 1.5, 1.25, 1.0, 0.75, 0.6, 0.5, 0.4, 0.3, 0.25)


@dataclass
class BoltDesign:
    """The pattern found and what it does."""

    spacing: float                   #: [m]
    patterns: list[dict[str, Any]]   #: ``[[bolt_pattern]]`` entries, one per face
    bare: dict[int, float]           #: key block id → factor of safety without bolts
    supported: dict[int, float]      #: key block id → with the pattern
    tried: list[tuple[float, float]] = field(default_factory=list)  #: (spacing, lowest FS)


def pattern(face: dict[str, Any], spacing: float) -> dict[str, Any]:
    """A ``[[bolt_pattern]]`` over ``face`` — its ``start`` a corner, ``along`` and ``across``
    its sides [m], the other keys those of a pattern — with bolts ``spacing`` apart, centred on
    the face."""
    p = {k: v for k, v in face.items() if k not in ("start", "along", "across")}
    start = np.asarray(face["start"], float)
    steps, counts = [], []
    for side in (face["along"], face.get("across", [0.0, 0.0, 0.0])):
        side = np.asarray(side, float)
        length = float(np.linalg.norm(side))
        n = int(math.floor(length / spacing + 1e-9)) + 1
        unit = side / length if length > 0 else np.zeros(3)
        start = start + unit * 0.5 * (length - (n - 1) * spacing)
        steps.append((unit * spacing).tolist())
        counts.append(n)
    p.update(start=start.tolist(), along=steps[0], across=steps[1], count=counts)
    return p


def design_bolt_pattern(scenario: Any, faces: list[dict[str, Any]], target: float = 1.5,
                        spacings: tuple[float, ...] = SPACINGS) -> BoltDesign:
    """The widest of ``spacings`` at which every key block of ``scenario`` (a
    :class:`nmm3d.Scenario` or a TOML path) has a factor of safety ≥ ``target`` with bolts over
    ``faces`` (see :func:`pattern`). ``ValueError`` names the blocks below the target at the
    closest spacing when none does."""
    from nmm3d.key_blocks import keyblocks
    from nmm3d.scenario import Scenario, load

    base = (scenario if isinstance(scenario, Scenario) else load(scenario)).to_dict()
    bare = {b.id: b.mode.factor_of_safety for b in keyblocks(Scenario.from_dict(base)).key_blocks()}
    if not bare:
        raise ValueError("the scenario has no key block: nothing to bolt")
    tried, supported = [], {}
    for s in spacings:
        d = dict(base, bolt_pattern=[*base.get("bolt_pattern", []), *(pattern(f, s) for f in faces)])
        fs = {b.id: b.mode.factor_of_safety for b in keyblocks(Scenario.from_dict(d)).blocks if b.id in bare}
        supported = fs
        tried.append((s, min(fs.values())))
        if min(fs.values()) >= target:
            return BoltDesign(s, [pattern(f, s) for f in faces], bare, fs, tried)
    short = ", ".join(f"block {k} (FS {v:.2f})" for k, v in sorted(supported.items()) if v < target)
    raise ValueError(f"no spacing down to {spacings[-1]} m brings every key block to FS {target}: {short}")
