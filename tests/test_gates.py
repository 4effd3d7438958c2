"""Gates every change passes: one Rust style (rustfmt), no clippy warnings, and type stubs that
match the native module (a stale stub misleads every editor and type checker)."""

from __future__ import annotations

import ast
import inspect
import shutil
import subprocess

import pytest

from conftest import ROOT
from nmm3d import _core


def cargo(*args: str) -> subprocess.CompletedProcess:
    if shutil.which("cargo") is None:
        pytest.fail("cargo is needed by the test suite (README: Quick start)")
    return subprocess.run(["cargo", *args], cwd=ROOT, capture_output=True, text=True, timeout=1800)


def test_rust_is_formatted():
    r = cargo("fmt", "--all", "--check")
    assert r.returncode == 0, "run `cargo fmt --all`:\n" + r.stdout[-3000:] + r.stderr[-2000:]


def test_clippy_has_no_warnings():
    r = cargo("clippy", "--release", "--workspace", "--all-targets", "--", "-D", "warnings")
    assert r.returncode == 0, r.stderr[-5000:]


def stub_functions() -> dict[str, list[tuple[str, bool]]]:
    """Each function of `_core.pyi`: its parameters and whether each has a default."""
    tree = ast.parse((ROOT / "python" / "nmm3d" / "_core.pyi").read_text())
    out = {}
    for f in tree.body:
        if isinstance(f, ast.FunctionDef):
            args = f.args.args
            first_default = len(args) - len(f.args.defaults)
            out[f.name] = [(a.arg, k >= first_default) for k, a in enumerate(args)]
    return out


def test_the_stubs_match_the_native_module():
    native = {}
    for name, obj in vars(_core).items():
        if callable(obj) and not isinstance(obj, type) and not name.startswith("_"):
            params = inspect.signature(obj).parameters.values()
            native[name] = [(p.name, p.default is not inspect.Parameter.empty) for p in params]
    assert stub_functions() == native
    errors = {n for n, o in vars(_core).items() if isinstance(o, type) and issubclass(o, Exception)}
    text = (ROOT / "python" / "nmm3d" / "_core.pyi").read_text()
    assert all(f"class {e}(" in text for e in errors), errors
