"""Sweeps: one run for each combination of the listed values (the product of the lists)."""

from __future__ import annotations

import itertools
from typing import Any

from nmm3d.study.plan import Plan, set_value


def sweep(plan: Plan, run: Any) -> dict[str, Any]:
    keys = list(plan.spec.parameters)
    combos = list(itertools.product(*(plan.spec.parameters[k] for k in keys)))
    tasks = [plan.task(dict(zip(keys, combo)), [set_value(k, v) for k, v in zip(keys, combo)]) for combo in combos]
    records = run(tasks)
    verdicts = [r["unstable"].get("any") for r in records]
    result = {"status": "completed", "message": f"{len(records)} runs",
              "runs": len(records), "unstable_runs": sum(v is True for v in verdicts),
              "undetermined_runs": sum(v is None for v in verdicts)}
    return {"result": result, "records": records}
