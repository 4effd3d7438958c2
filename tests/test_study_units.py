"""Studies, the parts without runs: the bracketing search, the sampling, the [study] table."""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np
import pytest

import nmm3d
from nmm3d.study.bisection import BracketSearch
from nmm3d.study.sampling import dip_and_direction, fisher_pole, scatter_plane, truncated_normal, wilson_interval
from nmm3d.study.spec import parse
from nmm3d.wedge import plane_normal


def drive(search: BracketSearch, verdict, targets=("any",)) -> dict:
    """Run a search against a known verdict(x) -> {target: unstable}; returns the observations."""
    obs: dict = {}
    points = search.first_points()
    while points:
        for x in points:
            obs[x] = verdict(x)
        points = search.next_points(list(targets), obs)
        assert len(obs) < 200
    return obs


@pytest.mark.parametrize("k", [1, 2, 5])
def test_search_brackets_a_friction_boundary_within_the_tolerance(k):
    s = BracketSearch(5.0, 60.0, 0.25, k, unstable_below=True)
    obs = drive(s, lambda x: {"any": x < 31.81})
    b = s.bracket("any", obs)
    assert b.status == "converged"
    assert b.unstable < 31.81 < b.stable and b.stable - b.unstable <= 0.25
    assert abs(b.value - 31.81) <= 0.125 + 1e-12
    # k-section: fewer rounds than plain bisection once k > 1
    assert len(obs) <= 2 + k * math.ceil(math.log(55 / 0.25) / math.log(k + 1))


def test_search_for_a_factor_fails_above_the_boundary():
    s = BracketSearch(0.5, 3.0, 0.01, 2, unstable_below=False)
    obs = drive(s, lambda f: {"any": f > 1.4142})
    b = s.bracket("any", obs)
    assert b.status == "converged" and b.stable < 1.4142 < b.unstable
    assert b.as_dict()["bracket"] == [b.stable, b.unstable]


def test_every_target_gets_its_own_boundary():
    crit = {"block:3": 20.0, "block:7": 35.0}
    verdict = lambda x: {"any": x < 35.0, **{t: x < c for t, c in crit.items()}}  # noqa: E731
    s = BracketSearch(5.0, 60.0, 0.5, 2, unstable_below=True)
    obs = drive(s, verdict, targets=("any", *crit))
    for t, c in crit.items():
        b = s.bracket(t, obs)
        assert b.status == "converged" and b.unstable < c < b.stable, (t, b)


def test_the_points_do_not_depend_on_anything_but_the_outcomes():
    a, b = (drive(BracketSearch(5.0, 60.0, 0.25, 2, True), lambda x: {"any": x < 40.0}) for _ in range(2))
    assert list(a) == list(b)


def test_boundaries_outside_the_range_and_undecided_runs_are_reported():
    s = BracketSearch(5.0, 60.0, 0.25, 2, True)
    assert s.bracket("any", drive(s, lambda x: {"any": False})).status == "stable_in_range"
    s = BracketSearch(5.0, 60.0, 0.25, 2, True)
    assert s.bracket("any", drive(s, lambda x: {"any": True})).status == "unstable_in_range"
    # every run inside the bracket fails without a verdict: the search gives the target up
    s = BracketSearch(5.0, 60.0, 0.25, 2, True)
    obs = drive(s, lambda x: {"any": True if x == 5.0 else False if x == 60.0 else None})
    assert s.bracket("any", obs).status == "undetermined" and len(obs) == 4


def test_a_non_monotone_target_is_flagged():
    s = BracketSearch(0.0, 10.0, 0.1, 1, True)
    obs = {0.0: {"any": True}, 10.0: {"any": False}, 5.0: {"any": False}, 7.0: {"any": True}}
    b = s.bracket("any", obs)
    assert b.non_monotone and b.unstable == 0.0 and b.stable == 5.0


def test_fisher_poles_have_the_mean_resultant_of_the_distribution():
    rng = np.random.default_rng(1)
    mean = plane_normal(50.0, 130.0)
    for kappa in (5.0, 40.0):
        cos = np.array([fisher_pole(mean, kappa, rng) @ mean for _ in range(4000)])
        expected = 1.0 / math.tanh(kappa) - 1.0 / kappa  # E[cos θ] = coth κ − 1/κ
        assert cos.mean() == pytest.approx(expected, abs=4 * cos.std() / math.sqrt(len(cos)))
        assert np.all(cos <= 1.0 + 1e-12)


def test_scattered_planes_stay_planes_and_round_trip_their_orientation():
    assert dip_and_direction(plane_normal(50.0, 130.0)) == pytest.approx((50.0, 130.0))
    assert dip_and_direction(-plane_normal(50.0, 130.0)) == pytest.approx((50.0, 130.0))
    rng = np.random.default_rng(2)
    dips = [scatter_plane(50.0, 130.0, 1e6, rng) for _ in range(10)]
    assert all(abs(d - 50.0) < 0.5 and abs(dd - 130.0) < 0.5 for d, dd in dips)


def test_friction_scatter_gives_the_normal_law_probability_of_falling_below_a_critical_angle():
    rng = np.random.default_rng(5)
    phi = np.array([truncated_normal(32.5, 3.0, 0.0, 89.9, rng) for _ in range(20000)])
    exact = NormalDist(32.5, 3.0).cdf(31.81)  # the tetrahedral wedge's φ_c: P(failure) = Φ((φ_c − μ)/σ)
    p = float(np.mean(phi < 31.81))
    assert p == pytest.approx(exact, abs=4 * math.sqrt(exact * (1 - exact) / len(phi)))
    assert phi.std() == pytest.approx(3.0, rel=0.03)


def test_wilson_interval_covers_the_proportion():
    lo, hi = wilson_interval(10, 100, 0.95)
    assert lo < 0.1 < hi and lo == pytest.approx(0.0552, abs=1e-3) and hi == pytest.approx(0.1744, abs=1e-3)
    lo, hi = wilson_interval(0, 20, 0.95)
    assert lo == 0.0 and 0.0 < hi < 0.2


SCENARIO = {
    "material": [{"name": "rock", "density": 2500.0, "young": 1e9, "poisson": 0.25}],
    "joint": [{"name": "j", "friction_angle": 30.0}],
    "joint_set": [{"dip": 50.0, "dip_direction": 130.0, "spacing": 1.0, "joint": "j"}],
    "body": [{"name": "cube", "material": "rock", "joint": "j", "shape": {"box": {"min": [0, 0, 0], "max": [2, 2, 2]}}}],
    "monitor": [{"name": "m", "select": {"point": [0.1, 0.1, 0.1]}, "quantities": ["velocity"]}],
}


def study(**table) -> nmm3d.Scenario:
    return nmm3d.Scenario.from_dict({**SCENARIO, "study": table})


def problems(**table) -> str:
    with pytest.raises(nmm3d.ScenarioError) as e:
        parse(study(**table).to_dict(), "s.toml")
    return str(e.value)


def test_a_valid_study_table_is_typed_with_defaults():
    spec = parse(study(kind="critical_friction", criterion={"monitor": "m", "displacement": 0.05, "time": 1.0}).to_dict(),
                 "s.toml")
    assert spec.range == (5.0, 60.0) and spec.tolerance == 0.25 and spec.joints == ("j",)
    assert spec.criterion.monitors == ("m",) and not spec.criterion.per_block


def test_study_errors_name_the_key():
    assert "study.criterion.monitor: there is no monitor named 'wedge'" in problems(
        kind="critical_friction", criterion={"monitor": "wedge", "displacement": 0.05, "time": 1.0})
    assert "study.kind" in problems(kind="bisect", criterion={"monitor": "m", "displacement": 0.05})
    assert "study.range" in problems(kind="critical_friction", range=[60.0, 5.0],
                                     criterion={"monitor": "m", "displacement": 0.05})
    assert "study.criterion.displacement" in problems(kind="sweep", parameters={"joint.j.friction_angle": [1.0]},
                                                      criterion={"monitor": "m", "displacement": -1.0})
    assert "study.joints" in problems(kind="critical_friction", joints=["nope"],
                                      criterion={"monitor": "m", "displacement": 0.05})
    assert "study.orientation.0.joint_set" in problems(kind="monte_carlo", samples=3,
                                                       orientation=[{"joint_set": 4, "kappa": 10.0}],
                                                       criterion={"blocks": "all", "displacement": 0.05})
    assert "study.bogus: unknown key" in problems(kind="sweep", bogus=1, parameters={"joint.j.friction_angle": [1.0]},
                                                  criterion={"monitor": "m", "displacement": 0.05})


def test_monte_carlo_samples_every_scattered_entry_reproducibly(tmp_path):
    from nmm3d.study.monte_carlo import draw
    from nmm3d.study.plan import Plan

    table = {"kind": "monte_carlo", "samples": 50, "seed": 4, "criterion": {"blocks": "all", "displacement": 0.05},
             "orientation": [{"joint_set": 0, "kappa": 30.0}], "spacing": [{"joint_set": 0, "sd": 0.2}],
             "strength": [{"joint": "j", "friction_angle_sd": 2.0, "cohesion_sd": 1e4}]}
    data = study(**table).to_dict()
    spec = parse(data, "s.toml")
    data.pop("study")
    plan = Plan(data, "s.toml", tmp_path, spec)
    samples = [draw(plan, np.random.default_rng(4)) for _ in range(2)]
    assert samples[0] == samples[1]  # same seed, same sample
    rng = np.random.default_rng(4)
    many = [draw(plan, rng) for _ in range(400)]
    keys = {"joint_set.0.dip", "joint_set.0.dip_direction", "joint_set.0.spacing", "joint.j.friction_angle",
            "joint.j.cohesion"}
    assert all(set(s) == keys for s in many)
    spacing = np.array([s["joint_set.0.spacing"] for s in many])
    assert spacing.min() > 0.0 and spacing.mean() == pytest.approx(1.0, abs=0.05)
    assert min(s["joint.j.cohesion"] for s in many) >= 0.0
    # poles within a few Fisher spreads of the mean: the angular scatter of κ = 30 is about 15°
    poles = np.array([plane_normal(s["joint_set.0.dip"], s["joint_set.0.dip_direction"]) for s in many])
    angles = np.degrees(np.arccos(np.clip(poles @ plane_normal(50.0, 130.0), -1, 1)))
    assert 8.0 < float(np.mean(angles)) < 20.0 and float(np.max(angles)) < 60.0
    # every sample is a valid scenario: the overrides go through the core's validation
    run = plan.task({"sample": 0, **many[0]}, [f"{k}={v!r}" for k, v in many[0].items()])
    assert run["id"] and "joint_set.0.dip=" in " ".join(run["overrides"])


def test_a_monitor_follows_a_block_by_id_and_a_wrong_id_is_named(tmp_path, cube):
    cube["monitor"] = [{"name": "b", "select": {"block": 0}, "quantities": ["displacement"]}]
    r = nmm3d.Scenario.from_dict(cube).run(out=tmp_path / "ok")
    assert r.summary["final"]["b.displacement.z"] == pytest.approx(-0.5 * 10.0 * 0.1**2, rel=1e-6)
    cube["monitor"][0]["select"] = {"block": 7}
    with pytest.raises(nmm3d.ScenarioError, match=r"monitor\.b\.select\.block: there is no block 7"):
        nmm3d.Scenario.from_dict(cube).run(out=tmp_path / "bad")


def test_the_progress_bar_shows_runs_the_bracket_and_each_running_run():
    import io

    from nmm3d.study.progress import Progress

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    screen = Terminal()
    shown = Progress(True, screen)
    assert shown.shows_running and not Progress(True, io.StringIO()).shows_running  # logs: no polling
    shown.expect(2, "bracket [20, 45]")
    task = {"values": {"value": 32.5}, "criterion": {"time": 1.0}}
    shown.running([(task, 0.42), (task, None)])
    shown.finished({"values": {"value": 32.5}, "unstable": {"any": True}, "status": "completed", "wall_seconds": 1.0})
    shown.close()
    text = screen.getvalue()
    assert "bracket [20, 45]" in text and "1/2" in text
    assert "[32.5] t = 0.42/1 s" in text and "value = 32.5: unstable" in text
    log = io.StringIO()
    lines = Progress(True, log)
    lines.expect(1)
    lines.finished({"values": {"value": 32.5}, "unstable": {"any": False}, "status": "completed", "wall_seconds": 2.0})
    assert log.getvalue() == "study: run 1/1 (value = 32.5): completed, stable (2.0 s)\n"


def test_the_criterion_counts_the_displacement_since_a_converged_initial_equilibrium(tmp_path):
    """A block that settled 15 mm in a converged initial equilibrium (soft joints closing under
    the rock's weight: the first record) and then rests is stable at a 1 cm threshold; one that
    moves 15 mm after the start is not. Had the settling not converged, its 15 mm may be a slide:
    counted from the reference configuration."""
    import json

    from nmm3d.study.runner import judge

    rows = ["time,rests.displacement.x,rests.displacement.y,rests.displacement.z,"
            "goes.displacement.x,goes.displacement.y,goes.displacement.z",
            "0.0,0.0,0.0,-0.015,0.0,0.0,0.0",
            "1.0,0.0,0.0,-0.0151,0.0,0.0,-0.015"]
    (tmp_path / "history.csv").write_text("\n".join(rows) + "\n")
    crit, targets = {"displacement": 0.01, "time": 1.0}, {"rests": "rests", "goes": "goes"}
    for converged, rests in [(True, False), (False, True)]:
        (tmp_path / "summary.json").write_text(json.dumps({"initial_equilibrium": {"converged": converged}}))
        v = judge(tmp_path, targets, crit, completed=True)
        assert v["unstable"] == {"rests": rests, "goes": True, "any": True}, (converged, v)
        assert v["detach"]["goes"] == 1.0, v
    assert v["final"]["rests"] == pytest.approx(0.0151), v
