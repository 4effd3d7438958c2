"""Verification: the 3DEC "Sliding Wedge" problem (Itasca, 3DEC Verification Problems; Hoek &
Bray 1977) — joints A 40/130 and B 60/220, k_n = k_s = 10 MPa/m, no cohesion.

The closed form is the vector method (`nmm3d.wedge`): critical friction angle 33.357°, sliding
along the line of intersection at a = g sin ψ (1 − FS). Issue "rock masses at the implicit
step": within 0.5° and 1° with the joints' own stiffness and with `auto`. On 10 MPa/m joints the
wedge closes by about 1 mm; before the contact facets were taken over the whole overlap (not only
within the support tolerance of the deepest corner) the wedge kept 1 % of its contact area and
slid at every angle.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.wedge import critical_friction_angle, wedge

PLANES = (40.0, 130.0), (60.0, 220.0)
G = 10.0
PHI_C = critical_friction_angle(*PLANES)
STIFFNESS = {"10 MPa/m": 1e7, "100 GPa/m": 1e11, "auto": None}


def load(stiffness: str, *overrides: str) -> nmm3d.Scenario:
    """The example with the joints' stiffness [Pa/m], or without it ("auto": the penalty of
    `[contact]`)."""
    data = nmm3d.load(EXAMPLES / "sliding_wedge.toml", ["analysis.output_interval=0.0", *overrides]).to_dict()
    joint = data["joint"][0]
    joint.pop("normal_stiffness"), joint.pop("shear_stiffness")
    if STIFFNESS[stiffness] is not None:
        joint["normal_stiffness"] = joint["shear_stiffness"] = STIFFNESS[stiffness]
    return nmm3d.Scenario.from_dict(data)


def displacement(result: nmm3d.RunResult) -> tuple[np.ndarray, np.ndarray]:
    h = result.history
    return h["time"], np.c_[[h[f"wedge.displacement.{c}"] for c in "xyz"]].T


def test_the_closed_form_is_3decs():
    assert PHI_C == pytest.approx(33.36, abs=0.005)


@pytest.mark.parametrize("stiffness", STIFFNESS)
def test_sliding_wedge_slides_along_the_line_of_intersection(stiffness, tmp_path):
    phi, T = 30.0, 0.6
    ref = wedge(*PLANES, phi, g=G)
    r = load(stiffness, "analysis.duration=0.6").run(out=tmp_path)
    assert r.completed, r.summary["message"]
    t, d = displacement(r)
    late = t >= T / 2  # after the joints' settlement
    s = d[late] @ ref.direction
    accel = 2.0 * np.polyfit(t[late], s, 2)[0]
    assert accel == pytest.approx(ref.acceleration, rel=0.01)
    step = d[-1] - d[late][0]
    off = math.degrees(math.acos(min(1.0, float(step @ ref.direction) / float(np.linalg.norm(step)))))
    assert off < 1.0, f"slides {off:.2f}° off the line of intersection"


@pytest.mark.parametrize("stiffness", ["10 MPa/m", "100 GPa/m", "auto"])
def test_sliding_wedge_rests_one_degree_above_the_critical_angle(stiffness, tmp_path):
    r = load(stiffness, f"joint.j.friction_angle={PHI_C + 1.0}", "analysis.duration=0.8").run(out=tmp_path)
    assert r.completed, r.summary["message"]
    t, d = displacement(r)
    late = d[t >= 0.4]
    assert float(np.linalg.norm(late[-1] - late[0])) < 1e-4, "still sliding after it settled"
    assert float(np.linalg.norm(d[-1])) < 0.01, "settled by more than the joints' elastic shear"


@pytest.mark.parametrize("stiffness", ["10 MPa/m", "auto"])
def test_sliding_wedge_critical_friction_angle_by_a_study(stiffness, tmp_path):
    s = nmm3d.Study(load(stiffness), tmp_path, ["study.tolerance=0.4"]).run(workers=2).summary
    assert s["status"] == "completed", s["message"]
    assert s["critical_friction_angle"] == pytest.approx(PHI_C, abs=0.5)


def test_on_one_mpa_per_m_joints_the_damped_wedge_slides_and_rests_as_the_vector_method(tmp_path):
    # Released onto joints this soft the wedge settles ~5 cm and swings on them for about a second
    # (period ≈ 0.5 s; settled by about 1.5 s): undamped, over these windows it slides 10 % fast at
    # 30° and still moves at φc + 1° (right only after the transient, the next test). A third of
    # critical damping on the contacts (`contact.damping_ratio`) takes the swing out.
    data = load("auto").to_dict()
    data["joint"][0].update(normal_stiffness=1e6, shear_stiffness=1e6)
    data["contact"] = {**data.get("contact", {}), "damping_ratio": 0.3}
    ref = wedge(*PLANES, 30.0, g=G)
    r = nmm3d.Scenario.from_dict({**data, "analysis": {**data["analysis"], "duration": 0.6}}).run(out=tmp_path / "a")
    t, d = displacement(r)
    late = t >= 0.3
    assert 2.0 * np.polyfit(t[late], d[late] @ ref.direction, 2)[0] == pytest.approx(ref.acceleration, rel=0.01)
    step = d[-1] - d[late][0]
    assert math.degrees(math.acos(min(1.0, float(step @ ref.direction) / float(np.linalg.norm(step))))) < 1.0
    data["joint"][0]["friction_angle"] = PHI_C + 1.0
    r = nmm3d.Scenario.from_dict({**data, "analysis": {**data["analysis"], "duration": 2.4}}).run(out=tmp_path / "b")
    t, d = displacement(r)
    late = d[t >= 1.2]
    assert float(np.linalg.norm(late[-1] - late[0])) < 1e-4, "still moving after it settled"


def test_undamped_wedge_on_one_mpa_per_m_joints_is_right_after_its_transient(tmp_path):
    # Released from its locked equilibrium (springs as stiff in shear as in compression hold the
    # weight nearly straight up, steeper than friction allows on joints dipping 40° and 60°) the
    # wedge slips until friction holds it, ~45 mm on springs this soft, and swings on them. That
    # transient lasts as long as √(m/k): √10 times the 0.3 s of 10 MPa/m joints. Measured after
    # it, undamped, the wedge slides at the vector method's acceleration and rests 1° above the
    # critical angle.
    stretch = math.sqrt(10.0)
    data = load("auto").to_dict()
    data["joint"][0].update(normal_stiffness=1e6, shear_stiffness=1e6)
    ref = wedge(*PLANES, 30.0, g=G)
    end = 0.6 * stretch
    r = nmm3d.Scenario.from_dict({**data, "analysis": {**data["analysis"], "duration": end}}).run(out=tmp_path / "a")
    t, d = displacement(r)
    late = t >= end / 2
    assert 2.0 * np.polyfit(t[late], d[late] @ ref.direction, 2)[0] == pytest.approx(ref.acceleration, rel=0.01)
    step = d[-1] - d[late][0]
    assert math.degrees(math.acos(min(1.0, float(step @ ref.direction) / float(np.linalg.norm(step))))) < 1.0
    data["joint"][0]["friction_angle"] = PHI_C + 1.0
    end = 0.8 * stretch
    r = nmm3d.Scenario.from_dict({**data, "analysis": {**data["analysis"], "duration": end}}).run(out=tmp_path / "b")
    t, d = displacement(r)
    size = np.linalg.norm(d, axis=1)
    # A swing repeats, sliding grows: the last quarter's largest displacement against the third's.
    third, last = size[(t >= end / 2) & (t < 0.75 * end)], size[t >= 0.75 * end]
    assert float(last.max() - third.max()) < 1e-4, "still sliding after the transient"
