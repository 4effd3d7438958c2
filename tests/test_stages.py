"""Staged analysis ([[stage]]): the state carried across stages against closed forms — a joint
weakened mid-run, a bolt installed in displaced rock, a prop excavated from under a block, the
in-situ stress an excavation releases (a column, and Lamé's circular tunnel) — and the checks
of the stage keys.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d import analytic

INCLINE = EXAMPLES / "staged_incline.toml"
G = 10.0
SLIDE = G * (math.sin(math.radians(30)) - math.tan(math.radians(24)) * math.cos(math.radians(30)))

#: Cover, material and joint of the small models below.
ROCK = """[cover]
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 1.0e9
poisson = 0.25

[[joint]]
name = "j"
friction_angle = 30.0
"""

#: A 2 m column of the rock, on its joint.
COLUMN = """[[body]]
name = "column"
material = "rock"
joint = "j"
shape = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 2.0] } }
"""

HEAD = """
[analysis]
dt = 0.002
gravity = [0.0, 0.0, -10.0]
output_interval = 0.05
initial_equilibrium = true
max_displacement_ratio = 0.01

""" + ROCK + """

[[body]]
name = "base"
material = "rock"
fixed = true
shape = { box = { min = [-1.0, -1.0, -1.0], max = [2.0, 2.0, 0.0] } }

""" + COLUMN + """

[[excavation]]
name = "prop"
shape = { box = { min = [-0.5, -0.5, 0.0], max = [1.5, 1.5, 1.0] } }

[[monitor]]
name = "top"
select = { point = [0.5, 0.5, 1.5] }
quantities = ["displacement"]
"""

PROP = HEAD + """
[[stage]]
name = "in-place"
duration = 0.2

[[stage]]
name = "remove"
duration = 0.3
excavate = ["prop"]
"""


def at(r: nmm3d.Result, key: str, t: float) -> float:
    return float(np.interp(t, r.history["time"], r.history[key]))


def test_a_weakened_joint_lets_the_cube_slide_at_the_closed_form_rate(tmp_path):
    r = nmm3d.load(INCLINE, ["stage.bolt.duration=0.002"]).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    assert abs(at(r, "cube.velocity.x", 0.2)) < 1e-4, "held at 40°"
    # Along the dip (cos 30°, -sin 30°) after 0.5 s at 24°.
    v = SLIDE * 0.5
    assert at(r, "cube.velocity.x", 0.7) == pytest.approx(v * math.cos(math.radians(30)), rel=0.01)
    assert at(r, "cube.velocity.z", 0.7) == pytest.approx(-v * 0.5, rel=0.01)


def test_an_installed_bolt_starts_unstressed_and_brakes_the_cube_as_a_spring(tmp_path):
    r = nmm3d.load(INCLINE).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    t, f = r.history["time"], r.history["b1.axial_force.value"]
    assert np.isnan(f[t < 0.7 + 1e-9]).all(), "absent before its stage"
    m, k = 2500.0, 1.0e5
    w, v1 = math.sqrt(k / m), SLIDE * 0.5
    first = np.argmax(t > 0.7 + 1e-9)
    dt = t[first] - 0.7
    # Unstressed at installation: one step's stretch, not the 0.14 m slid before.
    assert f[first] == pytest.approx(k * (m * SLIDE / k * (1 - math.cos(w * dt)) + v1 / w * math.sin(w * dt)), rel=0.02)
    stop = math.atan2(-v1 / w, m * SLIDE / k) % math.pi / w  # x'(t) = 0
    for dt in np.linspace(0.05, 0.95 * stop, 5):
        x = m * SLIDE / k * (1 - math.cos(w * dt)) + v1 / w * math.sin(w * dt)
        assert at(r, "b1.elongation.value", 0.7 + dt) == pytest.approx(x, rel=0.01)
    # Stopped and held by static friction: the bolt keeps its stretch.
    assert abs(r.history["cube.velocity.x"][-1]) < 1e-3
    assert r.history["b1.axial_force.value"][-1] == pytest.approx(k * r.history["b1.elongation.value"][-1])


def test_removing_a_prop_lets_the_block_on_it_fall_freely(tmp_path):
    path = tmp_path / "prop.toml"
    path.write_text(PROP)
    r = nmm3d.load(path).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    assert abs(at(r, "top.displacement.z", 0.2)) < 1e-4, "resting on its bonded prop (tens of micrometres)"
    for t in (0.3, 0.4, 0.5):
        assert at(r, "top.displacement.z", t) - at(r, "top.displacement.z", 0.2) == pytest.approx(
            -0.5 * G * (t - 0.2) ** 2, rel=1e-4)
    rows = list(csv.DictReader(open(r.directory / "stages.csv")))
    assert [(x["stage"], x["status"], x["blocks"]) for x in rows] == [("in-place", "completed", "3"),
                                                                      ("remove", "completed", "2")]
    assert [s["end_time"] for s in r.summary["stages"]] == pytest.approx([0.2, 0.5])
    assert r.run_summary.stages[1].start_step == r.run_summary.stages[0].end_step


REBOUND = """
[analysis]
kind = "static"
dt = 1.0
max_displacement_ratio = 1.0
equilibrium_tolerance = 1e-9
gravity = [0.0, 0.0, 0.0]

""" + ROCK + """

[[body]]
name = "floor"
material = "rock"
fixed = true
shape = { box = { min = [-0.5, -0.5, -1.0], max = [1.5, 1.5, 0.0] } }

[[body]]
name = "roof"
material = "rock"
fixed = true
shape = { box = { min = [-0.5, -0.5, 2.0], max = [1.5, 1.5, 3.0] } }

""" + COLUMN + """

[[excavation]]
name = "upper"
shape = { box = { min = [-0.5, -0.5, 1.0], max = [1.5, 1.5, 2.0] } }

[in_situ_stress]
stress = [0.0, 0.0, -1.0e6, 0.0, 0.0, 0.0]

[[monitor]]
name = "top"
select = { point = [0.5, 0.5, 1.0] }
location = "point"
quantities = ["displacement"]

[[monitor]]
name = "bottom"
select = { point = [0.5, 0.5, 1e-6] }
location = "point"
quantities = ["displacement", "stress"]

[[stage]]
name = "in-situ"
duration = 10.0

[[stage]]
name = "excavate"
duration = 50.0
excavate = ["upper"]
"""


def test_excavating_the_upper_half_of_a_stressed_column_releases_its_stress(tmp_path):
    """A column squeezed between floor and roof at σ_zz = −1 MPa: once its upper half is
    excavated the lower half stands free, stress-free, longer by σL/E = 1 mm."""
    path = tmp_path / "rebound.toml"
    path.write_text(REBOUND)
    r = nmm3d.load(path).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    h = r.history
    before = int(np.searchsorted(h["time"], r.summary["stages"][0]["end_time"], side="right")) - 1
    assert h["bottom.stress.zz"][before] == pytest.approx(-1e6, rel=1e-9)
    assert abs(h["top.displacement.z"][before]) < 1e-12, "the plug holds it in place"
    assert h["top.displacement.z"][-1] - h["bottom.displacement.z"][-1] == pytest.approx(1e-3, rel=1e-4)
    assert abs(h["bottom.stress.zz"][-1]) < 1.0


def test_a_circular_tunnel_excavated_in_hydrostatic_stress_moves_in_as_lame_says(tmp_path):
    """examples/staged_tunnel_lame.toml coarsened (cover 0.2 m; docs/verification.md (u) has the
    convergence to 0.1 and 0.05 m)."""
    r = nmm3d.load(EXAMPLES / "staged_tunnel_lame.toml", ["cover.size=0.2"]).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    before = int(np.searchsorted(r.history["time"], r.summary["stages"][0]["end_time"], side="right")) - 1
    for radius, tol in ((1.0, 0.05), (2.0, 0.02), (4.0, 0.02)):
        u = r.history[f"r{str(radius).replace('.', '_')}.displacement.x"]
        exact = analytic.lame_excavation(radius, 1.0, 5.0, 1e7, 1e10, 0.25)[0]
        assert u[-1] - u[before] == pytest.approx(exact, rel=tol)


def stage_problem(text: str, match: str, tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(nmm3d.ScenarioError, match=match):
        nmm3d.load(path)


@pytest.mark.parametrize("stage, match", [
    ('name = "a"\nduration = 0.0', r"stage\.a\.duration"),
    ('name = "a"\nduration = 1.0\nexcavate = ["tunnel"]', r"stage\.a\.excavate.*no excavation named 'tunnel'"),
    ('name = "a"\nduration = 1.0\ninstall = ["b9"]', r"stage\.a\.install.*no bolt"),
    ('name = "a"\nduration = 1.0\nset = { "body.column.fixed" = true }', r"stage\.a\.set\.body\.column\.fixed.*only"),
    ('name = "a"\nduration = 1.0\nset = { "joint.j.friction_angle" = -5.0 }', r"joint\.j\.friction_angle.*stage\.a\.set"),
    ('name = "a"\nduration = 1.0\nset = { "joint.k.friction_angle" = 5.0 }', r"stage\.a\.set\.joint\.k.*no joint named 'k'"),
])
def test_stage_inputs_are_checked(stage, match, tmp_path):
    stage_problem(HEAD + "\n[[stage]]\n" + stage + "\n", match, tmp_path)


def test_an_excavation_is_removed_by_one_stage_and_stage_names_are_unique(tmp_path):
    two = '\n[[stage]]\nname = "a"\nduration = 1.0\nexcavate = ["prop"]\n'
    stage_problem(HEAD + two + two.replace('"a"', '"b"'), r"stage\.b\.excavate.*earlier stage", tmp_path)
    stage_problem(HEAD + two + two, r"stage\.a.*twice", tmp_path)


def test_a_staged_run_cannot_be_resumed(tmp_path):
    path = tmp_path / "prop.toml"
    path.write_text(PROP)
    nmm3d.load(path, ["stage.remove.duration=0.01"]).run(out=tmp_path / "run")
    with pytest.raises(nmm3d.ScenarioError, match="cannot be resumed"):
        nmm3d.load(path).run(out=tmp_path / "run", resume=True)


def test_a_bolt_in_rock_its_own_stage_excavates_stops_the_run_there(tmp_path):
    """Its head lies in the prop the same stage removes: the stage's model cannot be built. The
    input error names the bolt; the outputs of the stages before stand, the summary says failed."""
    bolt = '\n[[bolt]]\nname = "b1"\nhead = [0.5, 0.5, 0.5]\nanchor = [0.5, 0.5, -0.5]\nstiffness = 1e6\n'
    path = tmp_path / "prop.toml"
    path.write_text(HEAD + bolt + PROP[len(HEAD):].replace('excavate = ["prop"]', 'excavate = ["prop"]\ninstall = ["b1"]'))
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1"):
        nmm3d.load(path).check()  # `check` builds every stage's model, as the run will
    with pytest.raises(nmm3d.ScenarioError, match="bolt.b1"):
        nmm3d.load(path).run(out=tmp_path / "run")
    r = nmm3d.Result(tmp_path / "run")
    assert r.status == "failed"
    assert r.history["time"][-1] == pytest.approx(0.2)


def test_a_study_ends_a_staged_runs_last_stage_at_the_criterion_time():
    from nmm3d.study.plan import run_length

    d = nmm3d.load(INCLINE).to_dict()
    s = nmm3d.Scenario.from_dict(d, run_length(d, 1.0))
    assert [st["duration"] for st in s.to_dict()["stage"]] == pytest.approx([0.2, 0.5, 0.3])
    assert run_length({"analysis": {}}, 2.0) == ["analysis.duration=2.0"]


def test_an_earthquake_coefficient_set_by_a_stage_starts_the_slide(tmp_path):
    """The cube held at 40° until a stage sets k_h = 0.3 towards +x (down the dip): it slides at
    g[(sin 30° + k cos 30°) − tan 40° (cos 30° − k sin 30°)] from that stage on."""
    # Under k_h the resultant sits 0.42 m ahead of the base's centre (of 0.5): the cube rides on
    # the front quarter of its base, and the points there decide its rocking. The 0.5 m cover
    # puts one row of them there (1.4 % slow); 0.25 m is within 0.1 % (meshed base alike).
    d = nmm3d.load(INCLINE, ["cover.size=0.25"]).to_dict()
    d["stage"], d["bolt"] = d["stage"][:2], []
    d["stage"][1]["set"] = {"seismic.coefficient": [0.3, 0.0, 0.0]}
    r = nmm3d.Scenario.from_dict(d).run(out=tmp_path / "run")
    assert r.completed, r.summary["message"]
    c, s, k = math.cos(math.radians(30)), math.sin(math.radians(30)), 0.3
    a = G * ((s + k * c) - math.tan(math.radians(40)) * (c - k * s))
    assert abs(at(r, "cube.velocity.x", 0.2)) < 1e-4
    assert at(r, "cube.velocity.x", 0.7) == pytest.approx(a * 0.5 * c, rel=0.01)
