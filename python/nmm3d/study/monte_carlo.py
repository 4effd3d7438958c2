"""Monte-Carlo studies: seeded samples of joint orientation, spacing and strength.

Sample i draws, in a fixed order, a Fisher-scattered pole for each ``[[study.orientation]]``,
a spacing for each ``[[study.spacing]]`` and strengths for each ``[[study.strength]]`` from one
generator seeded by ``study.seed``; the samples are drawn before any run, so they do not
depend on how the runs are scheduled. The probability of failure is the share of unstable
runs among those that could be judged, with Wilson's interval.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nmm3d.study.plan import Plan, set_value
from nmm3d.study.sampling import scatter_plane, truncated_normal, wilson_interval


def draw(plan: Plan, rng: np.random.Generator) -> dict[str, Any]:
    """One sample as {--set key: value}."""
    spec, sc = plan.spec, plan.scenario
    values: dict[str, Any] = {}
    for o in spec.orientation:
        entry = sc[o.entry][o.index]
        dip, dd = scatter_plane(entry["dip"], entry["dip_direction"], o.kappa, rng)
        values[f"{o.entry}.{o.index}.dip"] = round(dip, 6)
        values[f"{o.entry}.{o.index}.dip_direction"] = round(dd, 6)
    for s in spec.spacing:
        mean = sc["joint_set"][s.index]["spacing"]
        values[f"joint_set.{s.index}.spacing"] = truncated_normal(mean, s.sd, 0.05 * mean, np.inf, rng)
    for s in spec.strength:
        j = plan.joint(s.joint)
        key = f"joint.{s.joint}"
        values[f"{key}.friction_angle"] = truncated_normal(j.get("friction_angle", 0.0), s.friction_angle_sd, 0.0, 89.9, rng)
        if s.cohesion_sd:
            values[f"{key}.cohesion"] = truncated_normal(j.get("cohesion", 0.0), s.cohesion_sd, 0.0, np.inf, rng)
        if s.tensile_strength_sd:
            values[f"{key}.tensile_strength"] = truncated_normal(j.get("tensile_strength", 0.0), s.tensile_strength_sd,
                                                                 0.0, np.inf, rng)
    return values


def monte_carlo(plan: Plan, run: Any) -> dict[str, Any]:
    rng = np.random.default_rng(plan.spec.seed)
    samples = [draw(plan, rng) for _ in range(plan.spec.samples)]
    tasks = [plan.task({"sample": i, **v}, [set_value(k, x) for k, x in v.items()]) for i, v in enumerate(samples)]
    records = run(tasks)
    verdicts = [r["unstable"].get("any") for r in records]
    judged = [v for v in verdicts if v is not None]
    failures = sum(judged)
    low, high = wilson_interval(failures, len(judged), plan.spec.confidence)
    p = failures / len(judged) if judged else None
    result = {"status": "completed" if judged else "failed",
              "message": f"{failures} of {len(judged)} judged samples failed ({len(verdicts) - len(judged)} undetermined)",
              "probability_of_failure": p, "interval": [low, high], "confidence": plan.spec.confidence,
              "samples": len(records), "judged": len(judged), "failures": failures}
    return {"result": result, "records": records}
