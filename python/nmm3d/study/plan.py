"""The runs of a study: each one the study's scenario with a few ``--set`` overrides.

A run is identified by a hash of its effective scenario (after the overrides, with the
criterion it is judged by), so the same run asked twice, or again after an interruption, is
found in ``runs/<id>/`` and not repeated.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nmm3d import _core
from nmm3d.study.spec import StudySpec


@dataclass
class Plan:
    """What every run of one study shares."""

    scenario: dict[str, Any]      #: canonical scenario without its study table
    label: str                    #: file name used in messages
    out: Path                     #: the study's folder
    spec: StudySpec

    @property
    def criterion(self) -> dict[str, Any]:
        c = self.spec.criterion
        return {"displacement": c.displacement, "time": c.time, "monitors": list(c.monitors),
                "blocks": c.blocks if isinstance(c.blocks, str) else list(c.blocks)}

    def task(self, values: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
        """A run with these overrides (``values``: what the study varied, for its table)."""
        text = json.dumps(self.scenario)
        every = [*overrides, *run_length(self.scenario, self.spec.criterion.time)]
        effective = _core.load_json(text, self.label, every)
        key = json.dumps({"scenario": json.loads(effective), "criterion": self.criterion}, sort_keys=True)
        run_id = hashlib.sha256(key.encode()).hexdigest()[:16]
        return {"id": run_id, "values": values, "overrides": every, "scenario": effective, "label": self.label,
                "criterion": self.criterion, "out": str(self.out / "runs" / run_id)}

    def joint(self, name: str) -> dict[str, Any]:
        return next(j for j in self.scenario.get("joint", []) if j["name"] == name)


def run_length(scenario: dict[str, Any], time: float) -> list[str]:
    """The overrides that make a run of ``scenario`` end at ``time`` [s]: its duration, or, for a
    staged analysis, its last stage's (the earlier stages run as given)."""
    stages = scenario.get("stage") or []
    if not stages:
        return [f"analysis.duration={_toml(time)}"]
    before = sum(float(s["duration"]) for s in stages[:-1])
    return [f"stage.{stages[-1]['name']}.duration={_toml(time - before)}"]


def _toml(v: Any) -> str:
    """A value as the right-hand side of a ``--set``."""
    if isinstance(v, float):
        return repr(v)
    return json.dumps(v)


def set_value(key: str, value: Any) -> str:
    return f"{key}={_toml(value)}"


def friction_overrides(joints: tuple[str, ...], angle: float) -> list[str]:
    """Every named joint at this friction angle [deg]."""
    return [set_value(f"joint.{j}.friction_angle", float(angle)) for j in joints]


def reduction_overrides(plan: Plan, factor: float) -> list[str]:
    """tan φ, cohesion and tensile strength of the named joints divided by ``factor``."""
    out = []
    for j in plan.spec.joints:
        base = plan.joint(j)
        phi = math.degrees(math.atan(math.tan(math.radians(base.get("friction_angle", 0.0))) / factor))
        out += [set_value(f"joint.{j}.friction_angle", phi),
                set_value(f"joint.{j}.cohesion", base.get("cohesion", 0.0) / factor),
                set_value(f"joint.{j}.tensile_strength", base.get("tensile_strength", 0.0) / factor)]
    return out
