"""Contact dashpots (`[contact] damping_ratio`, `crates/nmm3d-core/src/contact/damping.rs`)
against the linear spring-dashpot's closed forms (Cundall & Strack 1979): a block settling onto a
joint follows the damped oscillator's step response, a dropped cube leaves its base at the damped
rebound speed, and the energy the dashpots take is accounted for (`damping_dissipation`).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.result import read_columns

#: The block on a joint: a 1 m cube (2500 kg) on a fixed slab, joint k_n = k_s = 10 MPa/m (K = 1e7
#: N/m on its 1 m² base), g = 10 m/s², released touching and at rest.
MASS, K, G = 2500.0, 1e7, 10.0


def settling(xi: float, duration: float = 0.5) -> nmm3d.Scenario:
    d = nmm3d.load(EXAMPLES / "block_on_joint.toml").to_dict()
    d.pop("expect")
    d["analysis"].update(duration=duration, gravity=[0.0, 0.0, -G], initial_equilibrium=False,
                         integrator="newmark", newmark_beta=0.25, newmark_gamma=0.5)
    d["joint"][0].update(normal_stiffness=K, shear_stiffness=K)
    d["contact"] = {"damping_ratio": xi}
    d["monitor"] = [{"name": "c", "select": {"point": [0.0, 0.0, 0.5]}, "quantities": ["displacement"],
                     "location": "point"}]
    return nmm3d.Scenario.from_dict(d)


def step_response(t: np.ndarray, xi: float) -> np.ndarray:
    """Settlement of a mass on a spring-dashpot under gravity, from rest at the spring's zero
    length: z = −δ [1 − e^(−ξωt) (cos ω_d t + ξ/√(1 − ξ²) sin ω_d t)], δ = m g / K."""
    w = math.sqrt(K / MASS)
    wd, delta = w * math.sqrt(1.0 - xi * xi), MASS * G / K
    return -delta * (1.0 - np.exp(-xi * w * t) * (np.cos(wd * t) + xi / math.sqrt(1.0 - xi * xi) * np.sin(wd * t)))


def rebound_speed(xi: float, v0: float, gap: float, stiffness: float, end: float) -> float:
    """Upward speed at `end` of a mass falling at `v0` through `gap` onto a spring-dashpot of
    `stiffness` (ξ of critical): contact lasts while the spring is compressed (a linear dashpot
    pulls near its end), then free flight."""
    w = math.sqrt(stiffness / MASS)
    wd, delta = w * math.sqrt(1.0 - xi * xi), MASS * G / stiffness
    t0 = (-v0 + math.sqrt(v0 * v0 + 2.0 * G * gap)) / G
    vi = v0 + G * t0
    a, b = delta, (-vi + xi * w * delta) / wd
    x = lambda t: -delta + math.exp(-xi * w * t) * (a * math.cos(wd * t) + b * math.sin(wd * t))  # noqa: E731
    lo, hi = 0.5 * math.pi / wd, 1.5 * math.pi / wd
    for _ in range(100):  # bisection for the end of contact, x = 0
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if x(mid) < 0.0 else (lo, mid)
    tc = 0.5 * (lo + hi)
    v = math.exp(-xi * w * tc) * ((-xi * w * a + wd * b) * math.cos(wd * tc) - (xi * w * b + wd * a) * math.sin(wd * tc))
    return v - G * (end - t0 - tc)


@pytest.mark.parametrize("xi", [0.1, 0.5])
def test_a_block_settles_on_its_joint_as_the_damped_oscillator(xi, tmp_path):
    r = settling(xi).run(out=tmp_path)
    h = r.history
    z, exact = h["c.displacement.z"], step_response(h["time"], xi)
    delta = MASS * G / K
    assert np.abs(z - exact).max() <= 0.005 * delta, np.abs(z - exact).max() / delta
    # The undamped spring swings to 2δ; the dashpots hold the overshoot to exp(−ξπ/√(1 − ξ²)).
    assert -z.min() == pytest.approx(delta * (1.0 + math.exp(-xi * math.pi / math.sqrt(1 - xi * xi))), rel=0.005)


def test_the_dashpots_take_what_gravity_put_in_beyond_the_springs(tmp_path):
    e = settling(0.5).run(out=tmp_path / "damped").summary["energy"]
    assert e["damping_dissipation"] > 0.4 * e["external_work"] > 0
    stored = e["kinetic"] + e["contact"] + e["elastic"]
    assert e["external_work"] == pytest.approx(stored + e["damping_dissipation"], rel=1e-3)
    assert e["max_error_ratio"] <= 1e-3 and e["warning"] is None
    undamped = settling(0.0, duration=0.1).run(out=tmp_path / "undamped").summary["energy"]
    assert undamped["damping_dissipation"] == 0.0


@pytest.mark.parametrize("xi", [0.1, 0.5])
def test_a_dropped_cube_rebounds_at_the_spring_dashpot_speed(xi, tmp_path):
    s = nmm3d.load(EXAMPLES / "damped_drop.toml", [f"contact.damping_ratio={xi}"])
    v = s.run(out=tmp_path).summary["final"]["cube.velocity.z"]
    d = s.to_dict()
    v0 = -d["body"][1]["velocity"][2]
    assert v == pytest.approx(rebound_speed(xi, v0, 1e-3, 1e9, d["analysis"]["duration"]), rel=0.005)


def test_the_example_states_the_closed_form():
    expect = nmm3d.load(EXAMPLES / "damped_drop.toml").to_dict()["expect"][0]
    assert expect["reference"] == pytest.approx(rebound_speed(0.2, 4.469899327725402, 1e-3, 1e9, 0.008), rel=1e-4)


@pytest.mark.parametrize("value", ["-0.1", "nan", "inf"])
def test_a_wrong_damping_ratio_is_named(value):
    with pytest.raises(nmm3d.ScenarioError, match="contact.damping_ratio"):
        nmm3d.load(EXAMPLES / "damped_drop.toml", [f"contact.damping_ratio={value}"])


def test_damped_dominos_never_hold_more_energy_than_gravity_gave_them(tmp_path):
    # The DDA scheme on "auto" penalties, impacts and toppling: at no step may the blocks'
    # kinetic, elastic and spring energy exceed what the push and gravity gave them (no energy
    # created by the dashpots), and the balance closes.
    r = nmm3d.load(EXAMPLES / "dominos.toml", ["analysis.duration=0.5", "contact.damping_ratio=0.3"]).run(out=tmp_path)
    e = r.summary["energy"]
    assert e["max_error_ratio"] <= 0.01 and e["damping_dissipation"] > 0
    d = read_columns(r.directory / "diagnostics.csv")
    held = d["kinetic_energy"] + d["elastic_energy"] + d["contact_energy"]
    lost = (d["friction_dissipation"] + d["damping_dissipation"] + d["numerical_dissipation"]
            + d["contact_event_dissipation"])
    initial = float((d["energy_error"] + held + lost - d["external_work"])[0])  # K₀ + S₀: the push
    given = initial + d["external_work"]
    assert (held <= 1.01 * given).all(), float((held - given).max())
