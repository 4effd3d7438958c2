"""Critical friction angle and factor of safety by strength reduction: a bracketing search.

``critical_friction``: every named joint at friction angle φ; unstable below φ_c.
``strength_reduction``: tan φ, cohesion and tensile strength of the named joints divided by F
(Dawson, Roth & Drescher 1999; 3DEC's "factor of safety" by strength reduction); unstable above
F = FS. With one target per failing block under a per-block criterion, each block gets its own
critical value, and the study's value is that of the first block to go.
"""

from __future__ import annotations

from typing import Any

from nmm3d.study.bisection import BracketSearch, Outcome
from nmm3d.study.plan import Plan, friction_overrides, reduction_overrides
from nmm3d.study.runner import block_id


def search(plan: Plan, run: Any) -> dict[str, Any]:
    """Run the search; ``run(tasks)`` executes tasks and returns their records."""
    spec = plan.spec
    friction = spec.kind == "critical_friction"
    lo, hi = spec.range
    finder = BracketSearch(lo, hi, spec.tolerance, spec.points_per_round, unstable_below=friction)
    observations: dict[float, Outcome] = {}
    records: list[dict[str, Any]] = []
    points = finder.first_points()
    while points and len(records) < spec.max_runs:
        points = points[: spec.max_runs - len(records)]
        tasks = [_task(plan, x, friction) for x in points]
        for x, record in zip(points, run(tasks)):
            observations[x] = record["unstable"]
            records.append(record)
        points = finder.next_points(_targets(observations), observations)
    capped = bool(points)
    any_ = finder.bracket("any", observations)
    name = "critical_friction_angle" if friction else "factor_of_safety"
    result: dict[str, Any] = {name: any_.value, "bracket": any_.as_dict()["bracket"], "search_status": any_.status,
                              "non_monotone": any_.non_monotone}
    targets = _targets(observations)[1:]
    blocks = [_entry(finder.bracket(t, observations), t, records, name) for t in targets if block_id(t) is not None]
    monitors = [_entry(finder.bracket(t, observations), t, records, name) for t in targets if block_id(t) is None]
    if blocks:
        result["blocks"] = blocks
    if len(monitors) > 1:
        result["monitors"] = monitors
    result["status"], result["message"] = _verdict(any_.status, capped, name, lo, hi, friction)
    return {"result": result, "records": sorted(records, key=lambda r: r["values"]["value"])}


def _task(plan: Plan, x: float, friction: bool) -> dict[str, Any]:
    overrides = friction_overrides(plan.spec.joints, x) if friction else reduction_overrides(plan, x)
    return plan.task({"value": x}, overrides)


def _targets(observations: dict[float, Outcome]) -> list[str]:
    """"any", then every monitor and block that was unstable in some run."""
    seen = {t for o in observations.values() for t, v in o.items() if v and t != "any"}
    return ["any", *sorted(seen, key=lambda t: (block_id(t) is not None, block_id(t) or 0, t))]


def _entry(b: Any, target: str, records: list[dict[str, Any]], name: str) -> dict[str, Any]:
    """A target's critical value, and when it went in the most unstable run that moved it."""
    moved = [r for r in records if target in r.get("detach", {})]
    first = min(moved, key=lambda r: r["detach"][target]) if moved else None
    key = ("id", block_id(target)) if block_id(target) is not None else ("monitor", target)
    entry = {key[0]: key[1], name: b.value, **b.as_dict()}
    entry.pop("value")
    if first is not None:
        entry["detach_time"] = first["detach"][target]
        entry["detach_time_at"] = first["values"]["value"]
    return entry


def _verdict(status: str, capped: bool, name: str, lo: float, hi: float, friction: bool) -> tuple[str, str]:
    what = "critical friction angle" if friction else "factor of safety"
    if status == "converged":
        return "completed", f"{what} found within the tolerance"
    if status == "stable_in_range":
        bound = f"below {lo}°" if friction else f"above {hi}"
        return "out_of_range", f"stable over the whole range: the {what} is {bound}"
    if status == "unstable_in_range":
        bound = f"above {hi}°" if friction else f"below {lo}"
        return "out_of_range", f"unstable over the whole range: the {what} is {bound}"
    if capped:
        return "incomplete", "study.max_runs reached before the bracket was within the tolerance"
    return "failed", "runs inside the bracket failed without telling stable from unstable (see study.csv)"
