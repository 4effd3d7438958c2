"""What a study shows while it runs: a bar on a terminal, one line per run in a log."""

from __future__ import annotations

import sys
from typing import Any, TextIO


class Progress:
    """Counts finished runs; ``expect`` raises the total as a search adds rounds."""

    def __init__(self, enabled: bool, stream: TextIO = sys.stderr) -> None:
        self.enabled = enabled
        self.stream = stream
        self.done = 0
        self.total = 0
        self.bar = None
        if enabled and stream.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=0, unit="run", file=stream, dynamic_ncols=True)

    def expect(self, n: int, what: str = "") -> None:
        self.total = self.done + n
        if self.bar is not None:
            self.bar.total = self.total
            self.bar.set_description(what)
            self.bar.refresh()

    def finished(self, record: dict[str, Any]) -> None:
        self.done += 1
        verdict = {True: "unstable", False: "stable", None: "undetermined"}[record["unstable"].get("any")]
        values = ", ".join(f"{k} = {v:.6g}" if isinstance(v, float) else f"{k} = {v}" for k, v in record["values"].items())
        how = "reused" if record.get("reused") else f"{record['wall_seconds']:.1f} s"
        if self.bar is not None:
            self.bar.set_postfix_str(f"{values}: {verdict}")
            self.bar.update(1)
        elif self.enabled:
            print(f"study: run {self.done}/{max(self.total, self.done)} ({values}): {record['status']}, {verdict} ({how})",
                  file=self.stream, flush=True)

    @property
    def shows_running(self) -> bool:
        """Whether running runs are shown (a bar on a terminal): only then are they looked at."""
        return self.bar is not None

    def running(self, runs: list[tuple[dict[str, Any], float | None]]) -> None:
        """Each running run's simulated time, on the bar (a terminal only)."""
        started = [(task, t) for task, t in runs if t is not None]
        if self.bar is None or not started:
            return
        parts = []
        for task, t in started[:4]:
            values = ", ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in task["values"].values())
            end = task["criterion"]["time"]
            parts.append(f"[{values}] t = {t:.3g}/{end:g} s")
        self.bar.set_postfix_str("running " + "; ".join(parts))

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
