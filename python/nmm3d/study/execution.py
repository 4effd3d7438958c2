"""Where a study's runs execute: a Dask cluster, local or remote.

A local cluster is one process per worker with one task at a time each (a run is
compute-bound and already uses threads inside), and the cores shared out among the workers'
Rust thread pools. ``scheduler`` connects to a running cluster instead (``dask scheduler`` /
``dask worker``, docs/studies.md). Finished runs are kept as ``runs/<id>/record.json`` by this
process, so a study started again reuses them, whatever machine ran them.
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from nmm3d.study.runner import failed_record, run_task

RECORD = "record.json"
POLL_SECONDS = 0.5  #: how often the running runs are looked at [s]


class Pool:
    """A Dask client for the study; use as a context manager."""

    def __init__(self, workers: int | None = None, scheduler: str | None = None) -> None:
        self.scheduler = scheduler
        self.workers = workers or os.cpu_count() or 1
        self.threads: int | None = None  #: Rust threads per local worker (None: the cluster's own)
        self._cluster = None
        self._client = None

    def __enter__(self) -> "Pool":
        from distributed import Client, LocalCluster

        if self.scheduler:
            self._client = Client(self.scheduler)
            self.workers = max(1, len(self._client.scheduler_info().get("workers", {})))
            self.threads = None
        else:
            self.threads = max(1, (os.cpu_count() or 1) // self.workers)
            self._cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                         dashboard_address=None, silence_logs=logging.ERROR,
                                         env={"RAYON_NUM_THREADS": str(self.threads)})
            self._client = Client(self._cluster)
        return self

    def __exit__(self, *exc: object) -> None:
        if self._client is not None:
            self._client.close()
        if self._cluster is not None:
            self._cluster.close()

    def run(self, tasks: list[dict[str, Any]], on_done: Callable[[dict[str, Any]], None],
            on_tick: Callable[[list[tuple[dict[str, Any], float | None]]], None] | None = None) -> list[dict[str, Any]]:
        """Run the tasks not already finished (in ``task["out"]/record.json``); records in task
        order. ``on_done(record)`` as each finishes; ``on_tick([(task, simulated time)])`` for the
        running ones, about every ``POLL_SECONDS``."""
        records: dict[str, dict[str, Any]] = {}
        todo: dict[str, dict[str, Any]] = {}
        for task in tasks:
            old = load_record(task)
            if old is not None:
                old["reused"] = True
                records[task["id"]] = old
                on_done(old)
            else:
                todo.setdefault(task["id"], dict(task, threads=self.threads))
        by_key = {f"nmm3d-run-{t['id']}": t for t in todo.values()}
        pending = [self._client.submit(run_task, t, key=k, pure=False) for k, t in by_key.items()]
        while pending:
            done = [f for f in pending if f.done()]
            pending = [f for f in pending if not f.done()]
            for future in done:
                record = self._collect(future, by_key[future.key])
                records[record["id"]] = record
                on_done(record)
            if pending and on_tick is not None:
                # the first few pending futures are the running ones (submission order)
                on_tick([(by_key[f.key], simulated_time(by_key[f.key])) for f in pending[: 2 * self.workers]])
            if pending and not done:
                time.sleep(POLL_SECONDS)
        return [records[t["id"]] for t in tasks]

    @staticmethod
    def _collect(future: Any, task: dict[str, Any]) -> dict[str, Any]:
        try:
            record = future.result()
        except Exception as e:  # noqa: BLE001 — e.g. the worker process died (out of memory)
            record = failed_record(task, f"the run was lost with its worker: {type(e).__name__}: {e}")
        record["reused"] = False
        if record["status"] != "failed" or record["steps"] > 0:
            save_record(Path(task["out"]), record)  # a run lost with nothing to show is tried again
        return record


def simulated_time(task: dict[str, Any]) -> float | None:
    """How far a running run has got: the last time in its history.csv, which a run rewrites
    every few seconds (None before the first rewrite, or where the run's folder is not shared)."""
    try:
        with open(Path(task["out"]) / "history.csv", "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 4096))
            last = f.read().decode(errors="replace").strip().splitlines()[-1]
        return float(last.split(",", 1)[0])
    except (OSError, IndexError, ValueError):
        return None


def load_record(task: dict[str, Any]) -> dict[str, Any] | None:
    """The record of a finished run with this task's id, if there is one."""
    path = Path(task["out"]) / RECORD
    try:
        record = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return record if record.get("id") == task["id"] else None


def save_record(folder: Path, record: dict[str, Any]) -> None:
    """Write the record atomically: its presence means the run finished."""
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder / f".{RECORD}.partial"
    tmp.write_text(json.dumps(record, indent=1, sort_keys=True))
    os.replace(tmp, folder / RECORD)
