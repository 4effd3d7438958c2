"""Every row of docs/reliability.md as a regression test: the expected exit status, a message,
and never a Python traceback (the cases live in bench/reliability.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from reliability import _cases, run_case  # noqa: E402

CASES = _cases()


@pytest.mark.parametrize("case", CASES, ids=[f"{c.group}: {c.what}" for c in CASES])
def test_bad_input_or_condition_ends_cleanly(case):
    r = run_case(case)
    assert not r["traceback"], r
    assert r["exit"] == case.expect, r
    if case.expect != 0:
        assert r["message"], "a failure says why"


def test_a_killed_run_resumes_to_the_same_bytes():
    """SIGKILL mid-run, then `--resume`: the history and diagnostics of the uninterrupted run,
    byte for byte (the full campaign: `bench/reliability.py --kills 14`, docs/reliability.md)."""
    from reliability import kills

    k = kills(2, seed=3)
    assert all(r["exit"] == 0 for r in k["rows"]), k["rows"]
    assert all(r["same"] for r in k["rows"]), k["rows"]


def test_a_full_disk_ends_with_a_summary_that_says_so():
    """A run into a 200 kB file system: exit 1, `summary.json` says `failed` and why, and no
    partial file is left holding the space; `nmm3d blocks` into a 40 kB one: exit 1 and a
    message, not a traceback (needs the right to mount a tmpfs)."""
    from reliability import full_disk

    f = full_disk()
    if f is None:
        pytest.skip("cannot mount a tmpfs here")
    r, b = f["run"], f["blocks"]
    assert r["exit"] == 1 and not r["traceback"], r
    assert r["status"] == "failed" and "No space left" in r["message"], r
    assert not r["partial"], r
    # The stereonet `nmm3d blocks` draws (Python writes it) on a full disk: a message, exit 1.
    assert b["exit"] == 1 and not b["traceback"] and "No space left" in b["message"], b
