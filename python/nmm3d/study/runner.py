"""One run of a study, as a worker executes it: scenario in, judged record out.

Everything a run needs travels in its task (a plain dictionary), so the function runs the same
in this process, in a local Dask worker or on another machine. The run writes its ordinary
outputs to its own folder; the record it returns says what the criterion made of them.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import time
from collections.abc import Collection
from pathlib import Path
from typing import Any

from nmm3d import _core
from nmm3d.result import read_columns

BLOCK_MONITOR = "_block_{}"  # name of the monitor a per-block criterion adds for block {id}
BLOCK_TARGET = "block:{}"    # the key of block {id} in a record's verdicts


def run_task(task: dict[str, Any]) -> dict[str, Any]:
    """Run one scenario and judge it; never raises for a failed run (the record says why)."""
    if task.get("threads"):
        os.environ.setdefault("RAYON_NUM_THREADS", str(task["threads"]))
    out = Path(task["out"])
    if out.exists():  # a run interrupted earlier: start it afresh
        shutil.rmtree(out)
    record: dict[str, Any] = {"id": task["id"], "values": task["values"], "overrides": task["overrides"]}
    t0 = time.perf_counter()
    try:
        text, monitors = _with_criterion_monitors(task)
        _core.run_json(text, task["label"], os.fspath(out), False)
        summary = json.loads((out / "summary.json").read_text())
        record.update(status=summary["status"], message=summary["message"], steps=summary["steps"],
                      time=summary["time"])
        # A static run stopped with the blocks it does not hold beyond `static_travel_limit` and
        # every other block in equilibrium has a verdict for each, as a completed one.
        settled = summary["status"] == "completed" or bool(summary.get("not_held"))
        record.update(judge(out, monitors, task["criterion"], settled, summary.get("not_held_monitors", [])))
    except Exception as e:  # noqa: BLE001 — a failed run is a row with its reason, never a crash of the study
        record = failed_record(task, str(e) if isinstance(e, _core.NmmError) else f"{type(e).__name__}: {e}")
    record["wall_seconds"] = time.perf_counter() - t0
    return record


def failed_record(task: dict[str, Any], message: str) -> dict[str, Any]:
    """The record of a run that produced no verdict."""
    return {"id": task["id"], "values": task["values"], "overrides": task["overrides"], "status": "failed",
            "message": message, "steps": 0, "time": 0.0, "unstable": {"any": None}, "detach": {}, "final": {},
            "displacement": None, "wall_seconds": 0.0}


def _with_criterion_monitors(task: dict[str, Any]) -> tuple[str, dict[str, str]]:
    """The scenario with displacement monitors for what the criterion judges, and their
    {target: monitor} map (targets: monitor names, or "block:<id>")."""
    crit = task["criterion"]
    scenario = json.loads(task["scenario"])
    monitors = scenario.setdefault("monitor", [])
    targets: dict[str, str] = {}
    for m in monitors:
        if m["name"] in crit["monitors"]:
            if "displacement" not in m["quantities"]:
                m["quantities"].append("displacement")
            targets[m["name"]] = m["name"]
    if crit["blocks"]:
        blocks = json.loads(_core.blocks_json(json.dumps(scenario), task["label"]))
        ids = [i for i, fixed in zip(blocks["id"], blocks["fixed"]) if not fixed]
        if crit["blocks"] != "all":
            ids = [i for i in crit["blocks"] if i in set(blocks["id"])]
        for i in ids:
            name = BLOCK_MONITOR.format(i)
            monitors.append({"name": name, "select": {"block": int(i)}, "quantities": ["displacement"]})
            targets[BLOCK_TARGET.format(i)] = name
    return _core.load_json(json.dumps(scenario), task["label"], []), targets


def judge(out: Path, targets: dict[str, str], criterion: dict[str, Any], completed: bool,
          released: Collection[str] = ()) -> dict[str, Any]:
    """Each target's |u| at the end, its first time beyond the threshold, and the verdicts; u
    is the displacement since the run's first record when its initial equilibrium converged —
    soft joints close by centimetres under the rock's weight (10 MPa/m: the thesis tunnel's roof
    key block 10–15 mm), which is no failure — and since the reference configuration otherwise
    (an unconverged settling may hold a block's sliding: 8 cm at 10° there).

    A completed run (or a static one that stopped with the blocks it does not hold beyond
    `analysis.static_travel_limit`, the others in equilibrium) is unstable where |u| at its end
    exceeds the threshold; any other run only where |u| had already exceeded it (otherwise it
    cannot tell: None). The monitors of the blocks such a static run did not hold (`released`:
    pinned where they crossed the limit, which may lie below the threshold) are unstable."""
    history = read_columns(out / "history.csv") if (out / "history.csv").is_file() else {}
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").is_file() else {}
    settled = (summary.get("initial_equilibrium") or {}).get("converged", False)
    limit = criterion["displacement"]
    final: dict[str, float] = {}
    detach: dict[str, float] = {}
    unstable: dict[str, bool | None] = {}
    t = history.get("time")
    for target, m in targets.items():
        cols = [history.get(f"{m}.displacement.{c}") for c in "xyz"]
        if t is None or len(t) == 0 or any(c is None for c in cols):
            unstable[target] = None
            continue
        cols = [c - c[0] for c in cols] if settled else cols
        mag = (cols[0] ** 2 + cols[1] ** 2 + cols[2] ** 2) ** 0.5
        final[target] = float(mag[-1])
        beyond = mag > limit
        if beyond.any():
            detach[target] = float(t[int(beyond.argmax())])
        unstable[target] = bool(mag[-1] > limit) if completed else (True if beyond.any() else None)
        if m in released:
            unstable[target] = True
    verdicts = list(unstable.values())
    unstable["any"] = True if any(v is True for v in verdicts) else (
        None if any(v is None for v in verdicts) or not verdicts else False)
    values = [v for v in final.values() if math.isfinite(v)]
    return {"unstable": unstable, "detach": detach, "final": final, "displacement": max(values) if values else None}


def block_id(target: str) -> int | None:
    """The block id of a per-block target, None for a monitor's."""
    head, _, tail = target.partition(":")
    return int(tail) if head == "block" and tail.isdigit() else None
