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
