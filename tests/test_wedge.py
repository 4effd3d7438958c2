"""The analytic two-plane wedge module against independent closed forms.

* Symmetric wedges: Hoek & Bray's wedge factor, FS = (sin β / sin(ξ/2)) · tan φ / tan ψ_i, with
  ξ the included angle of the wedge and β = 90° for a wedge symmetric about the vertical plane
  through its line of intersection (Hoek & Bray 1981, ch. 8).
* Equilibrium: N_A v_A + N_B v_B balances the weight's component normal to the line of
  intersection.
* Single-plane limit and lift-off.
"""

import math

import numpy as np
import pytest

from nmm3d.wedge import critical_friction_angle, plane_normal, wedge


@pytest.mark.parametrize("dip, half_spread, phi", [(45, 45, 30), (60, 30, 35), (50, 60, 20), (70, 20, 40)])
def test_symmetric_wedge_matches_the_wedge_factor(dip, half_spread, phi):
    a, b = (dip, 180 - half_spread), (dip, 180 + half_spread)
    r = wedge(a, b, phi)
    assert r.mode == "sliding on both"
    va, vb = plane_normal(*a), plane_normal(*b)
    xi = math.pi - math.acos(float(va @ vb))
    psi = math.radians(r.plunge)
    k = 1.0 / math.sin(xi / 2.0)
    assert r.factor_of_safety == pytest.approx(k * math.tan(math.radians(phi)) / math.tan(psi), rel=1e-12)
    assert r.trend == pytest.approx(180.0, abs=1e-9)   # slides due south, down the symmetry plane


def test_reactions_balance_the_weight():
    a, b = (55, 150), (40, 250)
    r = wedge(a, b, 25)
    i = r.direction
    z = np.array([0.0, 0.0, 1.0])
    z_perp = z - (z @ i) * i
    np.testing.assert_allclose(r.normal_a * plane_normal(*a) + r.normal_b * plane_normal(*b), z_perp, atol=1e-12)


def test_single_plane_sliding_and_lift_off():
    # B dips steeply the same way as A (v_Bz < c v_Az): the wedge leaves B and rides on A alone.
    r = wedge((30, 180), (80, 200), 20)
    assert r.normal_b == 0.0 and r.trend == pytest.approx(180.0)
    assert r.mode == "sliding on A"
    assert r.factor_of_safety == pytest.approx(math.tan(math.radians(20)) / math.tan(math.radians(30)))
    assert r.acceleration == pytest.approx(9.81 * (math.sin(math.radians(30)) - math.cos(math.radians(30)) * math.tan(math.radians(20))))
    # A wedge hanging under two joints (the roof of an opening): nothing holds it but cohesion.
    r = wedge((60, 30), (60, 150), 30, above_a=False, above_b=False)
    assert r.mode == "lift-off" and not r.stable and r.acceleration == pytest.approx(9.81)


def test_critical_friction_angle_gives_unit_factor():
    a, b = (50, 130), (45, 230)
    phi = critical_friction_angle(a, b)
    assert wedge(a, b, phi).factor_of_safety == pytest.approx(1.0, rel=1e-12)
    assert wedge(a, b, phi + 1).stable and not wedge(a, b, phi - 1).stable
