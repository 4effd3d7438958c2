"""A study from its scenario to its files: validate, plan, run on Dask, report."""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from nmm3d.scenario import Scenario, load
from nmm3d.study import monte_carlo, report, search, sweep
from nmm3d.study.execution import Pool
from nmm3d.study.plan import Plan
from nmm3d.study.progress import Progress
from nmm3d.study.result import StudyResult
from nmm3d.study.spec import StudySpec, parse

KINDS = {"critical_friction": search.search, "strength_reduction": search.search, "sweep": sweep.sweep,
         "monte_carlo": monte_carlo.monte_carlo}


class Study:
    """A study over many runs of one scenario (its ``[study]`` table, ``docs/studies.md``).

    >>> study = nmm3d.Study("examples/roof_wedge_study.toml", out="out/roof")   # doctest: +SKIP
    >>> result = study.run(workers=2)                                          # doctest: +SKIP
    >>> result.summary["critical_friction_angle"], result.to_pandas()          # doctest: +SKIP

    ``scenario`` is a path or a :class:`nmm3d.Scenario`; ``overrides`` are ``--set`` strings
    (``study.*`` keys included). Raises :class:`nmm3d.ScenarioError` for an invalid study.
    """

    def __init__(self, scenario: str | os.PathLike[str] | Scenario, out: str | os.PathLike[str],
                 overrides: list[str] | tuple[str, ...] = ()) -> None:
        if isinstance(scenario, Scenario):
            self.scenario = scenario.with_overrides(*overrides) if overrides else scenario
        else:
            self.scenario = load(scenario, overrides)
        self.out = Path(out)
        data = self.scenario.to_dict()
        self.spec: StudySpec = parse(data, self.scenario.label)
        data.pop("study")
        self._base = data

    def run(self, workers: int | None = None, scheduler: str | None = None, progress: bool = False) -> StudyResult:
        """Run (or resume) the study; ``workers`` local processes (default: the cores), or the
        Dask cluster at ``scheduler`` (e.g. ``"tcp://host:8786"``)."""
        # The model every run builds: refused here, once, as `nmm3d check` and `run` refuse it.
        Scenario(json.dumps(self._base), self.scenario.label).check()
        self.out.mkdir(parents=True, exist_ok=True)
        shown = Progress(progress)
        plan = Plan(self._base, self.scenario.label, self.out, self.spec)
        t0 = time.perf_counter()
        with Pool(workers, scheduler) as pool:
            try:
                outcome = KINDS[self.spec.kind](plan, _runner(pool, shown))
            finally:
                shown.close()
            execution = _execution(pool, scheduler, outcome["records"], time.perf_counter() - t0)
        report.write(self.out, self.spec, self.scenario.label, outcome, execution)
        return StudyResult(self.out)


def _runner(pool: Pool, shown: Progress) -> Callable[[list[dict[str, Any]]], list[dict[str, Any]]]:
    """Run a batch of tasks on the pool, showing them."""
    def run(tasks: list[dict[str, Any]]) -> list[dict[str, Any]]:
        shown.expect(len(tasks), _what(tasks))
        return pool.run(tasks, shown.finished, shown.running if shown.shows_running else None)

    return run


def _execution(pool: Pool, scheduler: str | None, records: list[dict[str, Any]], wall: float) -> dict[str, Any]:
    """What ran the study (kept out of study.json, which must not depend on it)."""
    fresh = [r for r in records if not r.get("reused")]
    return {"workers": pool.workers, "scheduler": scheduler or "local", "wall_seconds": wall, "runs": len(records),
            "reused_runs": len(records) - len(fresh), "run_wall_seconds": sum(r["wall_seconds"] for r in fresh)}


def _what(tasks: list[dict[str, Any]]) -> str:
    values = [t["values"].get("value") for t in tasks]
    if all(isinstance(v, float) for v in values) and values:
        return f"bracket [{min(values):.4g}, {max(values):.4g}]"
    return ""


def describe(result: StudyResult) -> str:
    """One line for the terminal."""
    s = result.summary
    if "probability_of_failure" in s:
        p = s["probability_of_failure"]
        ptxt = "n/a" if p is None else f"{p:.4f}"
        lo, hi = s["interval"]
        return f"{s['status']}: probability of failure {ptxt} ({100 * s['confidence']:.0f} % interval [{lo:.4f}, {hi:.4f}]), {s['runs']} runs"
    for key, unit in (("critical_friction_angle", "°"), ("factor_of_safety", "")):
        if key in s:
            v = s[key]
            lo, hi = s["bracket"]
            vtxt = f"{v:.4f}{unit} (bracket {lo:.4f}–{hi:.4f})" if v is not None else "—"
            blocks = s.get("blocks") or []
            per_block = "; ".join(f"block {b['id']}: {_num(b.get(key))}" for b in blocks)
            line = f"{s['status']}: {key.replace('_', ' ')} {vtxt}, {s['runs']} runs — {s['message']}"
            return line + (f"\n  per block: {per_block}" if per_block else "")
    return f"{s['status']}: {s['message']}"


def _num(v: Any) -> str:
    return "—" if v is None else f"{v:.4f}"
