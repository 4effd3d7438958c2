"""The layering of ARCHITECTURE.md, checked on the sources: no module of nmm3d-core uses a module
of a higher layer, and no two files of a crate import each other (directly or round a cycle).
Test code (`#[cfg(test)]` modules) and comments are not counted."""

from __future__ import annotations

import re
from collections import defaultdict
from pathlib import Path

from conftest import ROOT

CORE = ROOT / "crates" / "nmm3d-core" / "src"
CRATES = [CORE, ROOT / "crates" / "nmm3d-geom" / "src"]


def code(path: Path) -> str:
    text = path.read_text().split("#[cfg(test)]")[0]
    return "\n".join(line.split("//")[0] for line in text.splitlines())


def layers() -> dict[str, int]:
    table = (ROOT / "ARCHITECTURE.md").read_text().split("## Layers of `nmm3d-core`")[1]
    out = {}
    for number, modules in re.findall(r"^\| (\d+) \| ([^|]+) \|", table, flags=re.M):
        for m in re.findall(r"`(\w+)`", modules):
            out[m] = int(number)
    return out


def modules(root: Path) -> dict[str, Path]:
    """Module path (`contact::rules`) of every file; `mod.rs` and `lib.rs` name their module."""
    out = {}
    for f in root.rglob("*.rs"):
        parts = list(f.relative_to(root).with_suffix("").parts)
        if parts[-1] in ("mod", "lib"):
            parts = parts[:-1]
        out["::".join(parts)] = f
    return out


def imports(root: Path) -> dict[str, set[str]]:
    """For each file, the files it uses (through `crate::` or `super::` paths)."""
    files = modules(root)
    out = defaultdict(set)
    for me, f in files.items():
        parts = me.split("::") if me else []
        for kind, path in re.findall(r"\b(super|crate)::\{?([\w:]+)", code(f)):
            full = (parts[:-1] if kind == "super" else []) + path.split("::")
            for k in range(len(full), 0, -1):
                target = "::".join(full[:k])
                if target in files:
                    # A module's own declarations and re-exports of its children are not uses.
                    if target != me and not target.startswith(me + "::" if me else "\0"):
                        out[me].add(target)
                    break
    return out


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one file (Tarjan)."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in list(graph):
        if v not in index:
            visit(v)
    return found


def test_every_core_module_has_a_layer():
    top = {m.split("::")[0] for m in modules(CORE) if m}
    assert top == set(layers()), "ARCHITECTURE.md's table and the modules of nmm3d-core differ"


def test_no_module_uses_a_higher_layer():
    rank = layers()
    wrong = sorted({(a.split("::")[0], b.split("::")[0]) for a, bs in imports(CORE).items() for b in bs
                    if a and b and rank[b.split("::")[0]] > rank[a.split("::")[0]]})
    assert not wrong, f"modules using a higher layer (user, used): {wrong}"


def test_no_files_import_each_other():
    for root in CRATES:
        assert not cycles(imports(root)), f"{root}: files in an import cycle: {cycles(imports(root))}"


MAX_LINES = 450
"""Longest source file, test modules not counted: a file past it holds more than one concept."""


def source_lines(path: Path) -> int:
    return len(path.read_text().split("#[cfg(test)]")[0].splitlines())


def test_no_source_file_is_longer_than_the_bound():
    crates = ROOT / "crates"
    long = {str(f.relative_to(ROOT)): n for f in crates.glob("*/src/**/*.rs") if (n := source_lines(f)) >= MAX_LINES}
    assert not long, f"files of {MAX_LINES} lines or more (split them by concept): {long}"


def test_the_checks_can_fail():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []
    assert source_lines(ROOT / "crates" / "nmm3d-geom" / "src" / "contact.rs") < len(
        (ROOT / "crates" / "nmm3d-geom" / "src" / "contact.rs").read_text().splitlines())
