"""The ``[study]`` table, typed and validated (``docs/studies.md``).

The Rust core keeps the table as given; every key is checked here and a problem is raised as
:class:`nmm3d.ScenarioError` naming the file, the key path and the reason (CLI exit 2), like
every other scenario error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from nmm3d import _core

KINDS = ("critical_friction", "strength_reduction", "sweep", "monte_carlo")
DEFAULT_RANGES = {"critical_friction": (5.0, 60.0), "strength_reduction": (0.5, 3.0)}
KEYS = {"kind", "criterion", "joints", "range", "tolerance", "points_per_round", "max_runs", "parameters", "samples",
        "seed", "confidence", "orientation", "spacing", "strength"}
DEFAULT_TOLERANCES = {"critical_friction": 0.25, "strength_reduction": 0.01}


@dataclass(frozen=True)
class Criterion:
    """When a run counts as unstable: a displacement beyond ``displacement`` at ``time``."""

    displacement: float               #: threshold on |u| since the run's start [m]
    time: float                       #: the run's duration; |u| is taken at its end [s]
    monitors: tuple[str, ...] = ()    #: monitors judged (unstable if any exceeds)
    blocks: tuple[int, ...] | str = ()  #: per-block criterion: "all" (every moving block) or ids

    @property
    def per_block(self) -> bool:
        return self.blocks == "all" or bool(self.blocks)


@dataclass(frozen=True)
class Orientation:
    """Fisher scatter of one joint set's or joint plane's pole (Monte-Carlo)."""

    entry: str      #: "joint_set" or "joint_plane"
    index: int
    kappa: float    #: Fisher concentration (larger = tighter) [-]


@dataclass(frozen=True)
class Spacing:
    """Normal scatter of a joint set's spacing, truncated to positive values (Monte-Carlo)."""

    index: int
    sd: float       #: standard deviation [m]


@dataclass(frozen=True)
class Strength:
    """Normal scatter of a joint's strength about its scenario value (Monte-Carlo)."""

    joint: str
    friction_angle_sd: float = 0.0    #: [deg], truncated to 0..89.9
    cohesion_sd: float = 0.0          #: [Pa], truncated at 0
    tensile_strength_sd: float = 0.0  #: [Pa], truncated at 0


@dataclass(frozen=True)
class StudySpec:
    """A validated ``[study]`` table."""

    kind: str
    criterion: Criterion
    joints: tuple[str, ...]                       #: joints whose strength is varied
    range: tuple[float, float] = (0.0, 0.0)       #: search interval (deg, or factor F)
    tolerance: float = 0.0                        #: final bracket width (same unit as range)
    points_per_round: int = 2                     #: runs per search round (k-section)
    max_runs: int = 60                            #: cap on the runs of a search
    parameters: dict[str, list[Any]] = field(default_factory=dict)  #: sweep: key → values
    samples: int = 0                              #: Monte-Carlo samples
    seed: int = 0                                 #: Monte-Carlo seed
    confidence: float = 0.95                      #: level of the probability's interval
    orientation: tuple[Orientation, ...] = ()
    spacing: tuple[Spacing, ...] = ()
    strength: tuple[Strength, ...] = ()


class _Checker:
    """Collects problems with their key paths; raises them together."""

    def __init__(self, label: str) -> None:
        self.label = label
        self.problems: list[str] = []

    def fail(self, path: str, reason: str) -> None:
        self.problems.append(f"{self.label}: {path}: {reason}")

    def number(self, table: dict, key: str, path: str, default: float | None = None, positive: bool = False) -> float:
        v = table.get(key, default)
        if v is None:
            self.fail(f"{path}.{key}", "missing (a number is needed)")
            return math.nan
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            self.fail(f"{path}.{key}", f"must be a finite number, got {v!r}")
            return math.nan
        if positive and v <= 0:
            self.fail(f"{path}.{key}", f"must be positive, got {v!r}")
        return float(v)

    def integer(self, table: dict, key: str, path: str, default: int | None = None, least: int = 0) -> int:
        v = table.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int):
            self.fail(f"{path}.{key}", f"must be an integer, got {v!r}")
            return least
        if v < least:
            self.fail(f"{path}.{key}", f"must be at least {least}, got {v}")
        return v

    def unknown(self, table: dict, allowed: set[str], path: str) -> None:
        for k in table:
            if k not in allowed:
                self.fail(f"{path}.{k}", f"unknown key (known: {', '.join(sorted(allowed))})")

    def raise_if_any(self) -> None:
        if self.problems:
            raise _core.ScenarioError("\n".join(self.problems))


def parse(scenario: dict[str, Any], label: str) -> StudySpec:
    """Validate the ``study`` table of a canonical scenario dictionary."""
    c = _Checker(label)
    table = scenario.get("study")
    if not isinstance(table, dict):
        raise _core.ScenarioError(f"{label}: study: the scenario has no [study] table")
    kind = table.get("kind")
    if kind not in KINDS:
        c.fail("study.kind", f"must be one of {', '.join(KINDS)}, got {kind!r}")
        c.raise_if_any()
    args: dict[str, Any] = {"kind": kind}
    args["criterion"] = _criterion(c, table.get("criterion"), scenario)
    args["joints"] = _joints(c, table, scenario)
    if kind in DEFAULT_RANGES:
        args.update(_search(c, table, kind))
    elif kind == "sweep":
        args["parameters"] = _parameters(c, table.get("parameters"))
    else:
        args.update(_monte_carlo(c, table, scenario))
    c.unknown(table, KEYS, "study")  # keys of the other kinds are ignored: --set study.kind switches
    c.raise_if_any()
    return StudySpec(**args)


def _criterion(c: _Checker, t: Any, scenario: dict) -> Criterion:
    path = "study.criterion"
    if not isinstance(t, dict):
        c.fail(path, "missing: e.g. criterion = { monitor = \"wedge\", displacement = 0.05, time = 1.0 }")
        return Criterion(math.nan, math.nan)
    c.unknown(t, {"monitor", "blocks", "displacement", "time"}, path)
    d = c.number(t, "displacement", path, positive=True)
    stages = scenario.get("stage") or []
    length = sum(s["duration"] for s in stages) if stages else scenario.get("analysis", {}).get("duration")
    time = c.number(t, "time", path, default=length, positive=True)
    names = {m["name"] for m in scenario.get("monitor", [])}
    monitors = t.get("monitor", ())
    monitors = (monitors,) if isinstance(monitors, str) else tuple(monitors)
    for m in monitors:
        if m not in names:
            c.fail(f"{path}.monitor", f"there is no monitor named {m!r} (monitors: {', '.join(sorted(names)) or 'none'})")
    blocks = t.get("blocks", [])
    if isinstance(blocks, str):
        if blocks != "all":
            c.fail(f"{path}.blocks", f"must be \"all\" or a list of block ids, got {blocks!r}")
    elif isinstance(blocks, list) and all(isinstance(b, int) and not isinstance(b, bool) and b >= 0 for b in blocks):
        blocks = tuple(blocks)
    else:
        c.fail(f"{path}.blocks", f"must be \"all\" or a list of block ids, got {blocks!r}")
    if not monitors and not blocks:
        c.fail(path, "name a monitor (monitor = \"name\") or the blocks judged (blocks = \"all\")")
    return Criterion(d, time, monitors, blocks if isinstance(blocks, (str, tuple)) else ())


def _joints(c: _Checker, table: dict, scenario: dict) -> tuple[str, ...]:
    names = [j["name"] for j in scenario.get("joint", [])]
    joints = table.get("joints", names)
    if not isinstance(joints, list) or not all(isinstance(j, str) for j in joints):
        c.fail("study.joints", f"must be a list of joint names, got {joints!r}")
        return ()
    for j in joints:
        if j not in names:
            c.fail("study.joints", f"there is no joint named {j!r} (joints: {', '.join(names) or 'none'})")
    if table.get("kind") in DEFAULT_RANGES and not joints:
        c.fail("study.joints", "the scenario has no [[joint]] whose strength could be varied")
    return tuple(joints)


def _search(c: _Checker, table: dict, kind: str) -> dict[str, Any]:
    r = table.get("range", list(DEFAULT_RANGES[kind]))
    if not (isinstance(r, list) and len(r) == 2 and all(isinstance(x, (int, float)) and math.isfinite(x) for x in r)
            and r[0] < r[1]):
        c.fail("study.range", f"must be [low, high] with low < high, got {r!r}")
        r = list(DEFAULT_RANGES[kind])
    lo, hi = float(r[0]), float(r[1])
    if kind == "critical_friction" and not (0.0 <= lo and hi < 90.0):
        c.fail("study.range", f"friction angles must lie in [0, 90) degrees, got {r!r}")
    if kind == "strength_reduction" and lo <= 0.0:
        c.fail("study.range", f"factors must be positive, got {r!r}")
    tol = c.number(table, "tolerance", "study", DEFAULT_TOLERANCES[kind], positive=True)
    return {"range": (lo, hi), "tolerance": tol,
            "points_per_round": c.integer(table, "points_per_round", "study", 2, least=1),
            "max_runs": c.integer(table, "max_runs", "study", 60, least=2)}


def _parameters(c: _Checker, t: Any) -> dict[str, list[Any]]:
    if not isinstance(t, dict) or not t:
        c.fail("study.parameters", "a table of --set keys to lists of values, e.g. "
               "parameters = { \"joint.j.friction_angle\" = [25.0, 30.0] }")
        return {}
    out: dict[str, list[Any]] = {}
    for k, v in t.items():
        if not isinstance(v, list) or not v:
            c.fail(f"study.parameters.{k}", f"must be a non-empty list of values, got {v!r}")
            continue
        out[k] = v
    return out


def _monte_carlo(c: _Checker, table: dict, scenario: dict) -> dict[str, Any]:
    args: dict[str, Any] = {
        "samples": c.integer(table, "samples", "study", least=1),
        "seed": c.integer(table, "seed", "study", 0),
        "confidence": c.number(table, "confidence", "study", 0.95, positive=True),
    }
    if not 0.0 < args["confidence"] < 1.0:
        c.fail("study.confidence", f"must lie in (0, 1), got {args['confidence']}")
    orient = []
    for i, o in enumerate(_list(c, table, "orientation")):
        p = f"study.orientation.{i}"
        c.unknown(o, {"joint_set", "joint_plane", "kappa"}, p)
        entry = "joint_set" if "joint_set" in o else "joint_plane"
        index = _index(c, o, entry, p, scenario)
        planes = scenario.get(entry, [])
        if index < len(planes) and planes[index].get("dip") is None:
            c.fail(f"{p}.{entry}", f"{entry} {index} is given by a normal; give dip and dip_direction to scatter it")
        orient.append(Orientation(entry, index, c.number(o, "kappa", p, positive=True)))
    spacing = []
    for i, s in enumerate(_list(c, table, "spacing")):
        p = f"study.spacing.{i}"
        c.unknown(s, {"joint_set", "sd"}, p)
        spacing.append(Spacing(_index(c, s, "joint_set", p, scenario), c.number(s, "sd", p, positive=True)))
    strength = []
    names = {j["name"] for j in scenario.get("joint", [])}
    for i, s in enumerate(_list(c, table, "strength")):
        p = f"study.strength.{i}"
        keys = ("friction_angle_sd", "cohesion_sd", "tensile_strength_sd")
        c.unknown(s, {"joint", *keys}, p)
        if s.get("joint") not in names:
            c.fail(f"{p}.joint", f"there is no joint named {s.get('joint')!r}")
        sds = {k: c.number(s, k, p, 0.0) for k in keys}
        strength.append(Strength(str(s.get("joint")), **sds))
    if not (orient or spacing or strength):
        c.fail("study", "a monte_carlo study needs at least one of [[study.orientation]], [[study.spacing]], "
               "[[study.strength]]")
    args.update(orientation=tuple(orient), spacing=tuple(spacing), strength=tuple(strength))
    return args


def _list(c: _Checker, table: dict, key: str) -> list[dict]:
    v = table.get(key, [])
    if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
        c.fail(f"study.{key}", f"must be an array of tables, got {v!r}")
        return []
    return v


def _index(c: _Checker, t: dict, entry: str, path: str, scenario: dict) -> int:
    n = len(scenario.get(entry, []))
    i = t.get(entry)
    if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n:
        c.fail(f"{path}.{entry}", f"must be the index of a [[{entry}]] (the scenario has {n}), got {i!r}")
        return 0
    return i
