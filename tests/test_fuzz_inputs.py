"""Property test of the input path (issue 13): a valid scenario mutated at random — a value
replaced by any JSON value (NaN, ±inf, huge, tiny, negative, strings, lists, tables, null), a
key removed, an unknown key added — is either loaded or refused with `ScenarioError`; a loaded
one is cut (`blocks`) and judged (`keyblocks`) or refused with an `NmmError`. Never another
exception, never a panic. Seeded (derandomised): the same cases on every run.
"""

from __future__ import annotations

import copy
import math
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import nmm3d

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from reliability import scenario_paths as paths  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
BASES = {name: nmm3d.load(EXAMPLES / name).to_dict()
         for name in ("incline.toml", "goodman_tunnel.toml", "bolted_block.toml", "newmark_sliding_block.toml",
                      "staged_incline.toml")}

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**20, 10**20),
                    st.sampled_from([0.0, -1.0, 1e-300, 5e-324, 1e300, 4294967295, -0.0]))
scalars = st.one_of(numbers, st.booleans(), st.none(), st.text(max_size=8))
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                         st.dictionaries(st.text(max_size=6), inner, max_size=3)),
                      max_leaves=8)




@st.composite
def mutated(draw):
    name = draw(st.sampled_from(sorted(BASES)))
    d = copy.deepcopy(BASES[name])
    for _ in range(draw(st.integers(1, 3))):
        candidates = [p for p in paths(d) if p]
        path = draw(st.sampled_from(candidates))
        parent = d
        for k in path[:-1]:
            parent = parent[k]
        action = draw(st.sampled_from(["replace", "replace", "remove", "unknown"]))
        if action == "replace":
            parent[path[-1]] = draw(values)
        elif action == "remove" and isinstance(parent, dict):
            del parent[path[-1]]
        elif isinstance(parent, dict):
            parent["zz_" + draw(st.text(min_size=1, max_size=5))] = draw(values)
    return name, d




@settings(max_examples=400, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(mutated())
def test_a_mutated_scenario_is_loaded_or_refused_by_name(case):
    name, d = case
    try:
        scenario = nmm3d.Scenario.from_dict(d)
    except nmm3d.ScenarioError as e:
        assert str(e).strip(), name
        return
    try:
        scenario.blocks()
        nmm3d.keyblocks(scenario)
    except nmm3d.NmmError:
        pass


SET_KEYS = st.sampled_from(["joint.face.friction_angle", "joint.face.cohesion", "analysis.dt", "analysis.kind",
                            "material.rock.young", "water.table", "seismic.coefficient", "bolt.b1.stiffness",
                            "body.cube.fixed", "cover.size", "excavation.0.name", "joint.nope.friction_angle",
                            "", ".", "joint..x", "stage.hold.duration"])


@st.composite
def mutated_stages(draw):
    """The staged incline with its stages' keys, names and `set` tables mutated."""
    d = copy.deepcopy(BASES["staged_incline.toml"])
    for _ in range(draw(st.integers(1, 3))):
        stage = draw(st.sampled_from(d["stage"]))
        action = draw(st.sampled_from(["set", "set", "value", "install", "excavate"]))
        if action == "set":
            if not isinstance(stage.get("set"), dict):
                stage["set"] = {}
            stage["set"][draw(st.one_of(SET_KEYS, st.text(max_size=12)))] = draw(values)
        elif action == "value":
            stage[draw(st.sampled_from(["name", "duration", "equilibrium", "set"]))] = draw(values)
        else:
            stage[action] = draw(st.one_of(values, st.lists(st.sampled_from(["b1", "hold", "x", ""]), max_size=3)))
    return d


@settings(max_examples=200, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(mutated_stages())
def test_a_mutated_stage_is_loaded_or_refused_by_name(d):
    try:
        nmm3d.Scenario.from_dict(d)
    except nmm3d.ScenarioError as e:
        assert str(e).strip()


def test_the_fuzzer_mutates():
    """The strategy reaches refusals and loads alike (it is not a no-op)."""
    import random

    refused = loaded = 0
    rng = random.Random(1)
    for _ in range(40):
        d = copy.deepcopy(BASES["incline.toml"])
        path = rng.choice([p for p in paths(d) if p])
        parent = d
        for k in path[:-1]:
            parent = parent[k]
        parent[path[-1]] = rng.choice([math.nan, -1.0, "x", [], {}, None, 1e300])
        try:
            nmm3d.Scenario.from_dict(d)
            loaded += 1
        except nmm3d.ScenarioError:
            refused += 1
    assert refused > 5 and loaded > 0
