"""Bad inputs and hostile conditions, as a user meets them; writes docs/reliability.md.

Run: python bench/reliability.py

Each case runs the installed `nmm3d` command line in a fresh temporary directory and records
its exit status, whether a Python traceback reached the user, the first line of its message
and its wall time. `tests/test_reliability.py` runs the same cases and requires the expected
exit status and no traceback, so every row of the table is a regression test.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import os
import platform
import random
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

CUBE = """
[analysis]
duration = 0.05
dt = 0.01
gravity = [0.0, 0.0, -10.0]

[cover]
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25

[[joint]]
name = "j"
friction_angle = 30.0

[[body]]
name = "cube"
material = "rock"
joint = "j"
shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] } }

[[monitor]]
name = "cube"
select = { body = "cube" }
quantities = ["displacement"]
"""

CUBE_ON_BASE = CUBE + """
[[body]]
name = "base"
material = "rock"
fixed = true
shape = { box = { min = [-1.0, -1.0, -1.0], max = [2.0, 2.0, 0.0] } }
"""
SET = '\n[[joint_set]]\ndip = 30.0\ndip_direction = 90.0\nspacing = 0.25\njoint = "j"\n'
# An excavation around the whole cube: nothing is left.
ALL_GONE = CUBE + '\n[[excavation]]\nshape = { box = { min = [-1.0, -1.0, -1.0], max = [2.0, 2.0, 2.0] } }\n'
OK, FAILED, INPUT = 0, 1, 2


@dataclass
class Case:
    """One thing tried: `args` after `nmm3d` ({s}: the scenario file, {d}: the work directory)."""

    group: str
    what: str
    args: list[str]
    expect: int
    scenario: str = CUBE
    prepare: Callable[[Path], None] = field(default=lambda d: None)


def _used(d: Path) -> None:
    subprocess.run([sys.executable, "-m", "nmm3d", "run", str(d / "s.toml"), "--out", str(d / "out"), "--quiet"],
                   check=True, capture_output=True)


def _locked(d: Path) -> None:
    (d / "out").mkdir()
    (d / "out" / ".nmm3d.lock").write_text(str(os.getpid()))


def _frame_taken(d: Path) -> None:
    (d / "out" / "frames" / "blocks_00001.vtu").mkdir(parents=True)


def _fifo(d: Path) -> None:
    os.mkfifo(d / "fifo.toml")


def _bad_history(d: Path) -> None:
    _used(d)
    (d / "out" / "history.csv").write_bytes(b"time,step,cube.displacement.x\xff\n0,0,1\n")


def _cases() -> list[Case]:
    run = ["run", "{s}", "--out", "{d}/out", "--quiet"]
    check = ["check", "{s}"]
    return [
        Case("non-finite", "density = nan", [*check, "--set", "material.rock.density=nan"], INPUT),
        Case("non-finite", "cover origin [nan, 0, 0]", [*run, "--set", "cover.origin=[nan, 0.0, 0.0]"], INPUT),
        Case("non-finite", "gravity [0, 0, -inf]", [*run, "--set", "analysis.gravity=[0.0, 0.0, -inf]"], INPUT),
        Case("non-finite", "body velocity [0, nan, 0]", [*run, "--set", "body.cube.velocity=[0.0, nan, 0.0]"], INPUT),
        Case("huge / tiny", "cover.size = 1e-4 (10¹² cells)", [*run, "--set", "cover.size=1e-4"], INPUT),
        Case("huge / tiny", "cover.size = 5e-324", [*run, "--set", "cover.size=5e-324"], INPUT),
        Case("huge / tiny", "max_memory = 1 kB", [*check, "--set", "analysis.max_memory=1e3"], INPUT),
        Case("spacing extremes", "joint spacing 1e-12 m", [*run, "--set", "joint_set.0.spacing=1e-12"], INPUT, CUBE + SET),
        Case("spacing extremes", "joint spacing 5e-324 m", [*run, "--set", "joint_set.0.spacing=5e-324"], INPUT,
             CUBE + SET),
        Case("spacing extremes", "joint spacing 1e-6 m", ["blocks", "{s}", "--out", "{d}/b", "--set",
                                                         "joint_set.0.spacing=1e-6"], INPUT, CUBE + SET),
        Case("spacing extremes", "joint spacing 0 m", [*check, "--set", "joint_set.0.spacing=0"], INPUT, CUBE + SET),
        Case("huge / tiny", "tunnel of 4 294 967 295 segments",
             ["check", str(EXAMPLES / "tunnel_key_blocks.toml"), "--set", "excavation.0.shape.tunnel.segments=4294967295"],
             INPUT),
        Case("empty bodies", "a box with min = max", [*check, "--set", "body.cube.shape.box.max=[0.0, 0.0, 0.0]"],
             INPUT),
        Case("empty bodies", "an excavation that removes everything: check", check, INPUT, ALL_GONE),
        Case("empty bodies", "an excavation that removes everything: blocks", ["blocks", "{s}", "--out", "{d}/b"],
             INPUT, ALL_GONE),
        Case("empty bodies", "an excavation that removes everything: run", run, INPUT, ALL_GONE),
        Case("empty bodies", "an excavation that removes everything: a staged run", run, INPUT,
             ALL_GONE + '\n[[stage]]\nname = "only"\nduration = 0.01\n'),
        Case("paths", "scenario file missing", ["check", "{d}/missing.toml"], INPUT),
        Case("paths", "a directory as the scenario", ["check", "{d}"], INPUT),
        Case("paths", "a FIFO as the scenario (would hang)", ["check", "{d}/fifo.toml"], INPUT, prepare=_fifo),
        Case("paths", "--out ''", ["run", "{s}", "--out", ""], INPUT),
        Case("paths", "--out of an earlier run, no --overwrite", run, INPUT, prepare=_used),
        Case("paths", "--out of an earlier run, --overwrite", [*run, "--overwrite"], OK, prepare=_used),
        Case("paths", "--out that cannot be created (/proc)", ["run", "{s}", "--out", "/proc/nmm3d-out", "--quiet"],
             FAILED),
        Case("concurrency", "--out being written by a live process", run, INPUT, prepare=_locked),
        Case("full disk", "a frame that cannot be written mid-run", run, FAILED, prepare=_frame_taken),
        Case("plot inputs", "plot of a directory without history.csv", ["plot", "{d}"], INPUT),
        Case("plot inputs", "plot of a non-UTF-8 history.csv", ["plot", "{d}/out"], INPUT, prepare=_bad_history),
        Case("plot inputs", "plot into a folder that does not exist yet",
             ["plot", "{d}/out", "--out", "{d}/new/dir/h.png"], OK, prepare=_used),
        Case("check agrees with run", "a monitor point in no block (found once the blocks are cut)",
             [*check, "--set", "monitor.cube.select={ point = [5.0, 5.0, 5.0] }"], INPUT),
        Case("check agrees with run", "two bodies overlapping (found by the first contact detection)",
             [*check, "--set", "body.cube.shape.box.min=[0.0, 0.0, -0.2]"], INPUT, CUBE_ON_BASE),
        Case("divergence", "10⁵ g with no room to cut the step",
             [*run, "--set", "analysis.min_dt_ratio=1", "--set", "analysis.divergence_ratio=2", "--set",
              "analysis.gravity=[0.0, 0.0, -1.0e6]"], FAILED),
        Case("divergence", "static run short of equilibrium",
             ["run", str(EXAMPLES / "cantilever.toml"), "--out", "{d}/out", "--quiet", "--set", "analysis.max_steps=2",
              "--set", "cover.size=0.5"], FAILED),
    ]


def run_case(c: Case) -> dict:
    """Run one case in a fresh directory: exit status, traceback, first message line, seconds."""
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        (d / "s.toml").write_text(c.scenario)
        c.prepare(d)
        args = [a.replace("{s}", str(d / "s.toml")).replace("{d}", str(d)) for a in c.args]
        t0 = time.perf_counter()
        r = subprocess.run([sys.executable, "-m", "nmm3d", *args], capture_output=True, text=True, timeout=120)
        seconds = time.perf_counter() - t0
    lines = [ln for ln in r.stderr.splitlines() if ln.strip() and not ln.lstrip().startswith(("usage:", "["))]
    message = next((ln for ln in lines if ln.startswith("nmm3d")), lines[0] if lines else "")
    if message.endswith("invalid input:"):  # the problems follow, one per line
        message = lines[lines.index(message) + 1]
    message = message.replace(str(d), "DIR").replace(str(ROOT) + "/", "")
    return {"exit": r.returncode, "traceback": "Traceback" in r.stderr, "message": message, "seconds": seconds}


#: The examples the agreement campaign mutates.
AGREEMENT_BASES = ("incline.toml", "goodman_tunnel.toml", "bolted_block.toml", "staged_incline.toml",
                   "rock_slope.toml", "tunnel_key_blocks.toml", "sliding_wedge.toml", "roof_wedge.toml")
AGREEMENT_VALUES = [math.nan, math.inf, -math.inf, 0.0, -1.0, 1e-300, 5e-324, 1e300, 4294967295, "x", [], {}, None,
                    True, [math.nan, 0, 0], 1e-9, 1e9, [0, 0]]


def mutate(d: dict, rng: random.Random) -> dict:
    """One or two values replaced, scaled or removed anywhere in the scenario."""
    d = copy.deepcopy(d)
    for _ in range(rng.randint(1, 2)):
        where = [p for p in scenario_paths(d) if p]
        path = rng.choice(where)
        parent = d
        for k in path[:-1]:
            parent = parent[k]
        old, action = parent[path[-1]], rng.choice(["replace", "replace", "scale", "remove"])
        if action == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            parent[path[-1]] = old * rng.choice([1e-6, 1e-3, -1.0, 10.0, 1e3, 1e6, 1.0 + 1e-12])
        elif action == "remove" and isinstance(parent, dict):
            del parent[path[-1]]
        else:
            parent[path[-1]] = copy.deepcopy(rng.choice(AGREEMENT_VALUES))
    return d


def scenario_paths(node, prefix=()):
    """Every path to a value in a nested dict/list (the mutation sites of a scenario)."""
    yield prefix
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for k, v in items:
        yield from scenario_paths(v, prefix + (k,))


def agreement(n: int, seed: int) -> dict:
    """`n` mutated examples through load, check, blocks, keyblocks and a two-step run: where
    `check` and `run` disagree, and any exception but nmm3d's own errors."""
    import nmm3d

    bases = {b: nmm3d.load(EXAMPLES / b).to_dict() for b in AGREEMENT_BASES}
    rng, counts, findings = random.Random(seed), {"loaded": 0, "refused by check": 0, "ran": 0}, []
    for i in range(n):
        name = rng.choice(AGREEMENT_BASES)
        phase = "load"
        try:
            s = nmm3d.Scenario.from_dict(mutate(bases[name], rng))
            counts["loaded"] += 1
            phase = "check"
            try:
                s.check()
                refused = None
            except nmm3d.ScenarioError as e:
                refused, counts["refused by check"] = str(e), counts["refused by check"] + 1
            phase = "blocks"
            s.blocks()
            nmm3d.keyblocks(s)
            phase = "run"
            short = s.with_overrides(f"analysis.duration={2 * s.to_dict()['analysis']['dt']}", "analysis.max_steps=5",
                                     "analysis.output_interval=0")
            with tempfile.TemporaryDirectory() as tmp:
                try:
                    short.run(out=Path(tmp) / "o")
                    counts["ran"] += 1
                    if refused:
                        findings.append(f"{name}: check refused, run ran: {refused[:120]}")
                except nmm3d.ScenarioError as e:
                    if not refused:
                        findings.append(f"{name}: check passed, run refused: {str(e)[:120]}")
        except (nmm3d.ScenarioError, nmm3d.NmmError) as e:
            if not str(e).strip():
                findings.append(f"{name}: {phase}: an error without a message")
        except Exception as e:  # noqa: BLE001 — the campaign's point is to find these
            findings.append(f"{name}: {phase}: {type(e).__name__}: {str(e)[:120]}")
    return {"cases": n, "seed": seed, "counts": counts, "findings": findings}


KILLED = EXAMPLES / "dominos.toml"
KILL_SETS = ["analysis.duration=1.0", "analysis.checkpoint_interval=0.1"]


def kills(n: int, seed: int) -> dict:
    """`n` runs of the dominos killed (SIGKILL, as the machine or a user's `kill -9` does) at
    seeded moments and resumed (`--resume`) until they complete, against one uninterrupted run:
    whether `history.csv` and `diagnostics.csv` are the same bytes."""
    import signal

    rng, rows = random.Random(seed), []
    cmd = [sys.executable, "-m", "nmm3d", "run", str(KILLED), "--quiet", *sum((["--set", x] for x in KILL_SETS), [])]
    with tempfile.TemporaryDirectory() as tmp:
        clock = time.perf_counter()
        subprocess.run([*cmd, "--out", f"{tmp}/whole"], check=True, capture_output=True)
        whole = time.perf_counter() - clock
        same = lambda d, f: (Path(d) / f).read_bytes() == (Path(tmp) / "whole" / f).read_bytes()  # noqa: E731
        for k in range(n):
            out, at = f"{tmp}/k{k}", rng.uniform(0.1, 0.9) * whole
            p = subprocess.Popen([*cmd, "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(at)
            p.send_signal(signal.SIGKILL)
            p.wait()
            step = None
            if (Path(out) / "checkpoint.json").exists():
                step = json.loads((Path(out) / "checkpoint.json").read_text())["state"]["motion"]["step"]
            again = subprocess.run([*cmd, "--out", out, *(["--resume"] if step is not None else ["--overwrite"])],
                                   capture_output=True, text=True)
            rows.append({"at": at, "step": step, "exit": again.returncode,
                         "same": again.returncode == 0 and same(out, "history.csv") and same(out, "diagnostics.csv")})
    return {"n": n, "seed": seed, "whole": whole, "rows": rows}


def full_disk() -> dict | None:
    """A run and `nmm3d blocks` (its stereonet a picture Python writes) into a 200 kB and a 40 kB
    file system (tmpfs; `None` without the right to mount one): exit status, traceback, what the
    run's `summary.json` says, and the partial files left."""
    out = {}
    for what, size, args in (("run", "200k", ["run", str(EXAMPLES / "incline.toml"), "--quiet"]),
                             ("blocks", "40k", ["blocks", str(EXAMPLES / "rock_slope.toml")])):
        with tempfile.TemporaryDirectory() as tmp:
            mnt = Path(tmp) / "tiny"
            mnt.mkdir()
            if subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(mnt)],
                              capture_output=True).returncode != 0:
                return None
            try:
                r = subprocess.run([sys.executable, "-m", "nmm3d", *args, "--out", str(mnt / "out")],
                                   capture_output=True, text=True)
                path = mnt / "out" / "summary.json"
                summary = json.loads(path.read_text()) if path.exists() else {}
                out[what] = {"exit": r.returncode, "traceback": "Traceback" in r.stderr, "status": summary.get("status"),
                             "message": summary.get("message", "") or r.stderr.strip().splitlines()[-1],
                             "partial": sorted(p.name for p in mnt.rglob(".*.partial"))}
            finally:
                subprocess.run(["umount", str(mnt)], capture_output=True)
    return out


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--agreement", type=int, default=300, help="mutated scenarios of the agreement campaign")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--kills", type=int, default=14, help="runs killed and resumed")
    args = p.parse_args()
    rows = [(c, run_case(c)) for c in _cases()]
    out = [
        "# Reliability: bad inputs and hostile conditions",
        "",
        "`python bench/reliability.py` — each row runs the `nmm3d` command line in a fresh directory;",
        "`tests/test_reliability.py` runs the same cases and requires the expected exit status and no",
        "traceback. Exit status: 0 done, 1 the run failed (its `summary.json` says why where the disk",
        "allows), 2 invalid input (the message names file, key path and reason).",
        f"Machine: {platform.machine()}, {os.cpu_count()} cores.",
        "",
        "| class | tried | exit | expected | traceback | seconds | message (first line) |",
        "|---|---|---|---|---|---|---|",
    ]
    for c, r in rows:
        msg = r["message"].replace("|", "\\|")[:160]
        out.append(f"| {c.group} | {c.what} | {r['exit']} | {c.expect} | {'yes' if r['traceback'] else 'no'} "
                   f"| {r['seconds']:.2f} | {msg} |")
    a = agreement(args.agreement, args.seed)
    out += ["", "## `check` and `run` agree", "",
            f"`python bench/reliability.py --agreement {a['cases']} --seed {a['seed']}`: {a['cases']} examples "
            f"({', '.join(AGREEMENT_BASES)}) with one or two values anywhere replaced by NaN, ±inf, 0, −1, 1e±300, "
            "5e-324, 2³²−1, strings, lists, tables, null or booleans, scaled by 10⁻⁶…10⁶, or removed, each through "
            "load, `check`, `blocks`, `keyblocks` and a two-step run: "
            f"{a['counts']['loaded']} loaded, {a['counts']['refused by check']} of those refused by `check` (a model no "
            f"run could start: a monitor, bolt or load in no block, bodies overlapping), {a['counts']['ran']} ran. "
            f"Disagreements and unexpected exceptions: **{len(a['findings'])}**"
            + ("." if not a["findings"] else ":"), *[f"* {x}" for x in a["findings"]]]
    k = kills(args.kills, args.seed)
    identical = sum(r["same"] for r in k["rows"])
    out += ["", "## Killed and resumed", "",
            f"`python bench/reliability.py --kills {k['n']} --seed {k['seed']}`: `examples/dominos.toml` for 1 s "
            f"({', '.join(KILL_SETS)}; {k['whole']:.1f} s uninterrupted) killed with SIGKILL {k['n']} times at seeded "
            "moments, each resumed with `--resume` from its last checkpoint (run again with `--overwrite` where "
            f"none was written yet): **{identical} of {k['n']}** ended with `history.csv` and `diagnostics.csv` the "
            "same bytes as the uninterrupted run's.", "",
            "| killed at [s] | checkpoint step | exit of the resumed run | identical |", "|---:|---:|---:|---|",
            *[f"| {r['at']:.2f} | {r['step'] if r['step'] is not None else 'none'} | {r['exit']} | "
              f"{'yes' if r['same'] else 'no'} |" for r in k["rows"]]]
    f = full_disk()
    out += ["", "## A full disk", ""]
    if f is None:
        out.append("Not measured here: mounting a small file system needs privileges this machine did not give.")
    else:
        r, b = f["run"], f["blocks"]
        out += ["`examples/incline.toml` run into a 200 kB tmpfs, which fills while its frames are written: "
                f"exit {r['exit']}, traceback {'yes' if r['traceback'] else 'no'}; `summary.json` says "
                f"`{r['status']}`: {r['message']}; partial files left: {', '.join(r['partial']) or 'none'} "
                "(a write that fails removes its partial file, so the summary finds the room it needs). "
                "`nmm3d blocks examples/rock_slope.toml` into a 40 kB tmpfs, full before its stereonet: "
                f"exit {b['exit']}, traceback {'yes' if b['traceback'] else 'no'}: {b['message']}"]
    (ROOT / "docs" / "reliability.md").write_text("\n".join(out) + "\n")
    bad = [c.what for c, r in rows if r["exit"] != c.expect or r["traceback"]] + a["findings"]
    bad += [f"killed at {r['at']:.2f} s: not identical" for r in k["rows"] if not r["same"]]
    print(f"{len(rows)} cases, {len(bad)} unexpected: {bad}")


if __name__ == "__main__":
    main()
