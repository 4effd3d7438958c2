"""The typed run summary: the Python dataclasses mirror the Rust structs that write
``summary.json``, read real runs' summaries whole, and every field is documented."""

from __future__ import annotations

import dataclasses
import re
import typing

import pytest

import nmm3d
from conftest import EXAMPLES, ROOT
from nmm3d import summary as typed
from nmm3d.result import read_columns

RUST = ROOT / "crates" / "nmm3d-core" / "src" / "output" / "summary.rs"


def rust_structs() -> dict[str, list[str]]:
    """Each struct of the Rust summary: its fields as named in ``summary.json``."""
    out = {}
    for name, body in re.findall(r"pub struct (\w+) \{(.*?)\n\}", RUST.read_text(), re.S):
        fields = []
        rename = None
        for line in body.splitlines():
            if m := re.search(r'rename = "(\w+)"', line):
                rename = m.group(1)
            if m := re.match(r"\s*pub (\w+):", line):
                fields.append(rename or m.group(1))
                rename = None
        out[name] = fields
    return out


def python_fields(cls: type) -> list[str]:
    return [typed.json_name(f.name) for f in dataclasses.fields(cls)]


def test_the_dataclasses_mirror_the_rust_structs():
    structs = rust_structs()
    assert len(structs) == 10, structs.keys()
    for name, fields in structs.items():
        assert python_fields(getattr(typed, name)) == fields, name
    variants = re.search(r"pub enum Status \{(.*?)\n\}", RUST.read_text(), re.S).group(1)
    names = [re.sub(r"(?<!^)([A-Z])", r"_\1", v).lower() for v in re.findall(r"^\s*(\w+),", variants, re.M)]
    assert list(typing.get_args(typed.Status)) == names


def test_every_summary_field_is_documented():
    guide = (ROOT / "docs" / "user-guide.md").read_text()
    missing = [f for f in python_fields(typed.RunSummary) if f"`{f}`" not in guide]
    assert not missing, f"summary.json fields the user guide does not name: {missing}"


def test_a_contact_run_reads_whole(tmp_path):
    """The incline (contacts, friction, an initial equilibrium, [[expect]]): every key of its
    summary.json becomes a typed field, and the typed values are the file's."""
    s = nmm3d.load(EXAMPLES / "incline.toml", ["analysis.duration=0.05"])
    result = s.run(out=tmp_path / "incline")
    r = result.run_summary
    assert isinstance(r, nmm3d.RunSummary) and r.status == "completed" and r.steps == result.summary["steps"]
    assert isinstance(r.energy, typed.EnergySummary) and r.energy.kinetic == result.summary["energy"]["kinetic"]
    assert isinstance(r.initial_equilibrium, typed.InitialEquilibrium) and r.resumed_from is None
    assert r.checks and all(isinstance(c, typed.Check) and isinstance(c.passed, bool) for c in r.checks)
    assert sum(b.steps for b in r.step_diagnostics.dt_histogram) == r.steps
    assert r.step_diagnostics.dt_histogram[0].from_ == 0.0
    assert r.final["cube.velocity.x"] == result.history["cube.velocity.x"][-1]
    assert r.max_contact_points > 0 and r.stress_sign == "compression negative"


def test_a_static_run_has_no_energy(tmp_path):
    result = nmm3d.load(EXAMPLES / "cantilever.toml", ["cover.size=0.5"]).run(out=tmp_path / "beam")
    r = result.run_summary
    assert r.energy is None and r.initial_equilibrium is None
    assert isinstance(r.unbalanced_force_ratio, float) and r.factorizations >= 1


def test_a_key_the_dataclasses_do_not_know_is_named(tmp_path):
    result = nmm3d.load(EXAMPLES / "cantilever.toml", ["cover.size=0.5"]).run(out=tmp_path / "beam")
    data = dict(result.summary, surprise=1)
    with pytest.raises(ValueError, match="surprise"):
        nmm3d.RunSummary.from_dict(data)
    del data["surprise"], data["steps"]
    with pytest.raises(ValueError, match="steps"):
        nmm3d.RunSummary.from_dict(data)


def test_each_steps_iterations_and_factorisations_add_up_to_the_summarys(tmp_path):
    """`diagnostics.csv` says where a run's solves went, step by step: its open–close iterations
    and factorisations add up to the summary's counts (no initial equilibrium here, whose
    factorisations only the summary holds), and a step cut before it was taken factorised more
    often than its accepted trial iterated."""
    result = nmm3d.load(EXAMPLES / "goodman_tunnel.toml", ["analysis.duration=0.05"]).run(out=tmp_path / "gt")
    r, d = result.run_summary, read_columns(result.directory / "diagnostics.csv")
    assert r.initial_equilibrium is None
    assert sum(d["open_close_iterations"]) == r.open_close_iterations > r.steps
    assert sum(d["factorizations"]) == r.factorizations > 0
    assert min(d["open_close_iterations"]) >= 1 and max(d["factorizations"]) > 1
    for cuts, iterations, factorizations in zip(d["cuts"], d["open_close_iterations"], d["factorizations"]):
        if cuts > 0:
            assert factorizations > iterations
