"""Verification: a rigid footing on a tensionless joint of given stiffness (Pa/m), loaded in and
beyond its kern (`examples/eccentric_footing.toml`; Bowles 1996, `nmm3d.analytic.footing_on_joint`).

Inside the kern the whole base presses, and the joint's springs — at the corners of the cover
cells, each with an equal share of its cell — integrate the pressure by the trapezoidal rule:
the settlement is exact, the moment stiffness too large by the rule's error, so the rotation is
θ / (1 + 2h²/B²) (`corner_lumped_rotation`), second order in the cell h. Beyond the kern the heel
lifts and the contact's edge falls between corners: first order, to within 2 % at h = B/16.
"""

from __future__ import annotations

import math

import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.analytic import corner_lumped_rotation, footing_on_joint

P, B, L, K = 1.0e5, 2.0, 1.0, 1.0e7
CELLS = (0.5, 0.25, 0.125)


def footing(eccentricity: float, cell: float, tmp_path, *overrides: str) -> tuple[float, float]:
    """Rotation [rad] and settlement of the base's centre (down positive) [m]."""
    r = nmm3d.load(
        EXAMPLES / "eccentric_footing.toml",
        [f"cover.size={cell}", f"point_load.0.point=[{eccentricity}, 0.0, 0.01]", *overrides],
    ).run(out=tmp_path / f"e{eccentricity}-h{cell}-{len(overrides)}")
    assert r.completed, r.summary["message"]
    return r.history["footing.rotation.y"][-1], -r.history["footing.displacement.z"][-1]


def test_the_closed_form_is_continuous_at_the_kern():
    inside, beyond = footing_on_joint(P, B, L, B / 6.0, K), footing_on_joint(P, B, L, B / 6.0 + 1e-12, K)
    assert inside == pytest.approx(beyond, rel=1e-9)


def test_inside_the_kern_the_joint_turns_as_its_corner_springs_predict(tmp_path):
    e = 0.2
    theta, settlement, _ = footing_on_joint(P, B, L, e, K)
    errors = []
    for h in CELLS:
        rotation, sunk = footing(e, h, tmp_path)
        assert sunk == pytest.approx(settlement, rel=2e-3)
        assert rotation == pytest.approx(corner_lumped_rotation(theta, h, B), rel=5e-3), h
        errors.append(abs(rotation / theta - 1.0))
    # Second order in the cell: each halving cuts the error about fourfold.
    rates = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert all(r > 1.8 for r in rates), rates


def test_beyond_the_kern_the_heel_lifts_and_the_answer_converges(tmp_path):
    e = 0.55
    theta, settlement, contact = footing_on_joint(P, B, L, e, K)
    assert contact == pytest.approx(1.35)
    errors = []
    for h in CELLS:
        rotation, sunk = footing(e, h, tmp_path)
        errors.append(max(abs(rotation / theta - 1.0), abs(sunk / settlement - 1.0)))
    assert errors[0] > errors[1] > errors[2], errors
    assert errors[2] < 0.02, errors


def test_facets_turned_against_the_joint_take_part_with_their_part_in_the_band(tmp_path):
    """`contact.turned_face_angle`: the tilted base's facets that straddle the detection band
    count with their part in it instead of not at all — on 0.25 m cells the footing beyond its
    kern lands nearer the closed form (docs/theory/contact.md, *Turned faces in a run*)."""
    theta, settlement, _ = footing_on_joint(P, B, L, 0.55, K)
    whole = footing(0.55, 0.25, tmp_path)
    clipped = footing(0.55, 0.25, tmp_path, "contact.turned_face_angle=2")
    assert abs(clipped[0] / theta - 1.0) < 0.75 * abs(whole[0] / theta - 1.0), (whole, clipped)
    assert abs(clipped[1] / settlement - 1.0) < 0.75 * abs(whole[1] / settlement - 1.0), (whole, clipped)


@pytest.mark.parametrize("value", [-1.0, 11.0])
def test_a_turned_face_angle_out_of_range_is_named(value):
    with pytest.raises(nmm3d.ScenarioError, match="contact.turned_face_angle"):
        nmm3d.load(EXAMPLES / "eccentric_footing.toml", [f"contact.turned_face_angle={value}"])


def test_a_static_analysis_lifts_no_joint_that_closes_smoothly(tmp_path):
    """`contact.static_carry_slack` (0.05): the footing's joint, found again at most 0.8 % harder
    as the base turns, keeps the total force — lifted whole (slack 0, as a dynamic run carries
    it), it settled 3.0 % off the closed form instead of 1.4 % (docs/theory/contact.md, *Static
    analyses on soft joints*)."""
    _, settlement, _ = footing_on_joint(P, B, L, 0.55, K)
    kept = footing(0.55, 0.125, tmp_path)[1] / settlement - 1.0
    lifted = footing(0.55, 0.125, tmp_path, "contact.static_carry_slack=0")[1] / settlement - 1.0
    assert abs(kept) < 0.02 < abs(lifted), (kept, lifted)


@pytest.mark.parametrize("value", [-0.01, float("inf")])
def test_a_static_carry_slack_out_of_range_is_named(value):
    with pytest.raises(nmm3d.ScenarioError, match="contact.static_carry_slack"):
        nmm3d.load(EXAMPLES / "eccentric_footing.toml", [f"contact.static_carry_slack={value}"])
