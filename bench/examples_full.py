"""Every example at full size, to its end, as a user runs it; writes docs/examples-full.md.

Run: python bench/examples_full.py [--timeout SECONDS]

Each `examples/*.toml` runs the `nmm3d` command line in a fresh directory (the suite runs the
heavy ones coarsened, `tests/test_examples.py`). The table gives each run's status, simulated
time, steps, step cuts by reason, deepest contact overlap, overlaps found late, the energy
balance (the largest error over the run relative to the largest account; static runs have no
accounts) and the wall time, with the machine's load. A run that does not complete is a row
with its message, not a crash of the script.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"
PAGE = ROOT / "docs" / "examples-full.md"


def run(example: Path, timeout: float) -> dict:
    """One example in a fresh directory: its summary's numbers, or why there are none."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        t0 = time.perf_counter()
        try:
            proc = subprocess.run([sys.executable, "-m", "nmm3d", "run", str(example), "--out", str(out), "--quiet"],
                                  capture_output=True, text=True, timeout=timeout)
            code = proc.returncode
        except subprocess.TimeoutExpired:
            return {"status": f"not finished in {timeout:.0f} s", "wall": time.perf_counter() - t0}
        wall = time.perf_counter() - t0
        summary = out / "summary.json"
        if not summary.exists():
            return {"status": f"exit {code}, no summary", "wall": wall, "message": proc.stderr.strip()[-200:]}
        s = json.loads(summary.read_text())
    energy = s.get("energy") or {}
    return {
        "status": s["status"],
        "time": s["time"],
        "steps": s["steps"],
        "cuts": (s.get("step_diagnostics") or {}).get("cuts_by_reason") or {},
        "overlap": s.get("max_penetration", 0.0),
        "missed": s.get("missed_overlaps", 0),
        "balance": energy.get("max_error_ratio"),
        "gain": energy.get("max_gain_ratio"),
        "warning": energy.get("warning"),
        "wall": wall,
        "message": s.get("message", ""),
    }


def cell(text: str) -> str:
    """`text` as one Markdown table cell (a message may hold newlines or bars)."""
    return " ".join(text.split()).replace("|", "\\|")


def row(name: str, r: dict) -> str:
    if "steps" not in r:
        return f"| {name} | {r['status']} | | | | | | | | {r['wall']:.0f} | {cell(r.get('message', ''))} |"
    cuts = ", ".join(f"{v} {k}" for k, v in sorted(r["cuts"].items())) or "0"
    balance = "–" if r["balance"] is None else f"{r['balance']:.1e}"
    gain = "–" if r["gain"] is None else f"{r['gain']:.1e}"
    if r["warning"]:
        balance += " (warning)"
    return (f"| {name} | {r['status']} | {r['time']:g} | {r['steps']} | {cuts} | {1e3 * r['overlap']:.3g} | "
            f"{r['missed']} | {balance} | {gain} | {r['wall']:.0f} | {cell(r['message'])} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--timeout", type=float, default=1800.0, help="seconds per example")
    args = parser.parse_args()
    load0 = os.getloadavg()[0]
    rows = []
    for example in sorted(EXAMPLES.glob("*.toml")):
        r = run(example, args.timeout)
        rows.append(row(example.stem, r))
        print(rows[-1], flush=True)
    load1 = os.getloadavg()[0]
    PAGE.write_text("\n".join([
        "# Every example at full size",
        "",
        "`python bench/examples_full.py` — each `examples/*.toml` run to its end by the `nmm3d` command",
        "line, as a user runs it (the suite runs the heavy ones coarsened). *Overlap*: the deepest",
        "contact overlap [mm]; *late*: overlaps found deeper than a detection lets one arise, or",
        "whose push would give the blocks energy (`missed_overlaps`); *balance*: the largest energy",
        "balance error over the run relative to the",
        "largest account ([theory/energy.md](theory/energy.md); static runs have none); *gain*: the",
        "largest kinetic and strain energy held beyond what the loads and the start gave, relative",
        "to the same account (`max_gain_ratio`, energy from nowhere that the balance books as negative",
        "dissipation, [theory/energy.md](theory/energy.md#energy-from-nowhere-the-gain)); step cuts by",
        "their reason in `cuts.csv`.",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores, load {load0:.1f} before and {load1:.1f} after.",
        "",
        "| example | status | simulated [s] | steps | step cuts | overlap [mm] | late | balance | gain | wall [s] | message |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
    ]))


if __name__ == "__main__":
    main()
