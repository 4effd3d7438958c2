"""Stereonet geometry: lower hemisphere, equal area, x = East, y = North."""

import numpy as np
import pytest

from nmm3d.stereonet import dip_from_normal, great_circle, pole, project


def test_projection_of_reference_lines():
    assert project(0.0, 90.0) == pytest.approx((0.0, 0.0), abs=1e-15)      # vertical: centre
    assert project(90.0, 0.0) == pytest.approx((1.0, 0.0), abs=1e-15)      # horizontal east: rim
    x, y = project(180.0, 30.0)
    assert x == pytest.approx(0.0, abs=1e-15) and y == pytest.approx(-np.sqrt(2) * np.sin(np.radians(30)))


def test_poles_and_great_circles():
    assert pole(0.0, 0.0) == pytest.approx((0.0, 0.0), abs=1e-15)          # horizontal plane
    assert pole(90.0, 90.0) == pytest.approx((-1.0, 0.0), abs=1e-12)       # vertical, facing east
    x, y = great_circle(90.0, 90.0)                                          # the N–S diameter
    assert np.allclose(x, 0.0, atol=1e-12) and np.isclose(np.abs(y).max(), 1.0)
    x, y = great_circle(30.0, 90.0)
    r = np.hypot(x, y)
    assert r.max() == pytest.approx(1.0) and r.min() == pytest.approx(np.sqrt(2) * np.sin(np.radians(30)), rel=1e-3)


def test_dip_from_normal_either_sense():
    for n in ([0.5, 0.0, np.sqrt(3) / 2], [-0.5, 0.0, -np.sqrt(3) / 2]):
        dip, dd = dip_from_normal(n)
        assert dip == pytest.approx(30.0) and dd == pytest.approx(90.0)
