"""A study's files: ``study.json`` (the answer; the same whatever ran it), ``study.csv`` (one row
per run, with wall times), ``execution.json`` (workers, wall time, reused runs) and PNG plots."""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from nmm3d.study.runner import block_id
from nmm3d.study.spec import StudySpec

UNITS = {"critical_friction": "friction angle φ [deg]", "strength_reduction": "strength reduction factor F [-]"}


def row(record: dict[str, Any], out: Path) -> dict[str, Any]:
    """The deterministic part of a run's record, as the study reports it."""
    verdict = record["unstable"].get("any")
    failed = sorted(block_id(t) for t, v in record["unstable"].items() if v and block_id(t) is not None)
    return {"id": record["id"], **record["values"], "status": record["status"],
            "unstable": verdict, "displacement": record.get("displacement"), "failed_blocks": failed,
            "detach_times": record.get("detach", {}), "message": record["message"],
            "folder": os.path.relpath(Path(out) / "runs" / record["id"], out)}


def write(out: Path, spec: StudySpec, label: str, outcome: dict[str, Any], execution: dict[str, Any]) -> dict[str, Any]:
    rows = [row(r, out) for r in outcome["records"]]
    study = {"kind": spec.kind, "scenario": Path(label).name, **outcome["result"],
             "criterion": {"displacement": spec.criterion.displacement, "time": spec.criterion.time,
                           "monitors": list(spec.criterion.monitors),
                           "blocks": spec.criterion.blocks if isinstance(spec.criterion.blocks, str)
                           else list(spec.criterion.blocks)},
             "joints": list(spec.joints), "runs": len(rows), "rows": rows}
    if spec.kind in UNITS:
        study.update(range=list(spec.range), tolerance=spec.tolerance, points_per_round=spec.points_per_round)
    _atomic(out / "study.json", json.dumps(study, indent=1, sort_keys=False, default=_plain))
    _csv(out / "study.csv", rows, outcome["records"])
    _atomic(out / "execution.json", json.dumps(execution, indent=1))
    plot(out, spec, study)
    return study


def _plain(v: Any) -> Any:
    if hasattr(v, "item"):
        return v.item()
    raise TypeError(f"not JSON: {v!r}")


def _atomic(path: Path, text: str) -> None:
    tmp = path.with_name(f".{path.name}.partial")
    tmp.write_text(text)
    os.replace(tmp, path)


def _csv(path: Path, rows: list[dict[str, Any]], records: list[dict[str, Any]]) -> None:
    varied = [k for k in rows[0] if k not in _FIXED] if rows else []
    header = ["run", *varied, "status", "unstable", "displacement", "failed_blocks", "wall_seconds", "reused", "folder",
              "message"]
    tmp = path.with_name(f".{path.name}.partial")
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for i, (r, rec) in enumerate(zip(rows, records)):
            verdict = "" if r["unstable"] is None else str(r["unstable"]).lower()
            w.writerow([i, *(r[k] for k in varied), r["status"], verdict,
                        "" if r["displacement"] is None else repr(r["displacement"]),
                        " ".join(map(str, r["failed_blocks"])), f"{rec['wall_seconds']:.3f}",
                        str(rec.get("reused", False)).lower(), r["folder"], r["message"]])
    os.replace(tmp, path)


_FIXED = {"id", "status", "unstable", "displacement", "failed_blocks", "detach_times", "message", "folder"}


def plot(out: Path, spec: StudySpec, study: dict[str, Any]) -> None:
    """``study.png`` (and ``blocks.png`` for a per-block search)."""
    from matplotlib.figure import Figure  # here, not at import: matplotlib takes 0.3 s to load

    rows = study["rows"]
    fig = Figure(figsize=(7.0, 4.5))
    ax = fig.subplots()
    limit = spec.criterion.displacement
    floor = limit * 1e-6
    if spec.kind == "monte_carlo":
        d = [max(r["displacement"], floor) for r in rows if r["displacement"] is not None]
        bins = np.geomspace(min(d + [floor]), max(d + [limit * 10]), 30)
        ax.hist(d, bins=bins, color="0.6", edgecolor="k")
        ax.set_xscale("log")
        ax.axvline(limit, color="r", ls="--", label=f"criterion {limit:g} m")
        ax.set_xlabel(f"|u| at t = {spec.criterion.time:g} s [m]")
        ax.set_ylabel("samples [-]")
        p, (lo, hi) = study["probability_of_failure"], study["interval"]
        ptxt = "n/a" if p is None else f"{p:.3f}"
        ax.set_title(f"Monte-Carlo: P(failure) = {ptxt}, {100 * study['confidence']:.0f} % interval [{lo:.3f}, {hi:.3f}]")
    else:
        key = "value" if spec.kind in UNITS else next(iter(spec.parameters))
        xs = [r[key] for r in rows]
        numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
        xpos = xs if numeric else list(range(len(xs)))
        for verdict, colour, name in ((True, "tab:red", "unstable"), (False, "tab:blue", "stable"),
                                      (None, "0.5", "undetermined")):
            sel = [(x, max(r["displacement"] or floor, floor)) for x, r in zip(xpos, rows) if r["unstable"] is verdict]
            if sel:
                ax.scatter(*zip(*sel), color=colour, label=name, zorder=3)
        if numeric and len(xs) > 1:
            order = np.argsort(xpos)
            ax.plot(np.asarray(xpos)[order], [max(rows[i]["displacement"] or floor, floor) for i in order], color="0.7")
        ax.set_yscale("log")
        ax.axhline(limit, color="r", ls="--", label=f"criterion {limit:g} m")
        ax.set_ylabel(f"|u| at t = {spec.criterion.time:g} s [m]")
        ax.set_xlabel(UNITS.get(spec.kind, key))
        if not numeric:
            ax.set_xticks(xpos, [str(x) for x in xs], rotation=45, ha="right")
        ax.set_title(_title(spec, study))
        bracket = study.get("bracket")
        if bracket and None not in bracket:
            ax.axvspan(*bracket, color="gold", alpha=0.4, label="final bracket")
    ax.legend(loc="best", fontsize="small")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "study.png", dpi=110)
    if study.get("blocks"):
        _blocks_plot(out, spec, study)


def _title(spec: StudySpec, study: dict[str, Any]) -> str:
    if spec.kind == "critical_friction":
        v = study.get("critical_friction_angle")
        return "critical friction angle " + ("outside the range" if v is None else f"{v:.3f}°")
    if spec.kind == "strength_reduction":
        v = study.get("factor_of_safety")
        return "factor of safety " + ("outside the range" if v is None else f"{v:.3f}")
    return f"sweep: {study['unstable_runs']} of {study['runs']} runs unstable"


def _blocks_plot(out: Path, spec: StudySpec, study: dict[str, Any]) -> None:
    name = "critical_friction_angle" if spec.kind == "critical_friction" else "factor_of_safety"
    blocks = [b for b in study["blocks"] if b.get(name) is not None]
    if not blocks:
        return
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 0.4 * len(blocks) + 1.5))
    ax = fig.subplots()
    ax.barh([str(b["id"]) for b in blocks], [b[name] for b in blocks], color="tab:orange")
    ax.set_xlabel(UNITS[spec.kind])
    ax.set_ylabel("block id")
    ax.set_title(f"{name.replace('_', ' ')} of each block that fails in the range")
    ax.grid(True, axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "blocks.png", dpi=110)
