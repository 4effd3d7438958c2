"""Earthquake loading ([seismic]): a shaken base and pseudo-static coefficients, against
Newmark's sliding block (1965), the integrated Newmark solution on an incline and Hoek & Bray's
pseudo-static factor of safety. Displacements are relative to the base (the run is in its frame).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import nmm3d
from nmm3d import analytic

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NEWMARK = EXAMPLES / "newmark_sliding_block.toml"
G = 9.81
N = 0.2  # the example's tan φ


def run(tmp_path, path, *overrides) -> nmm3d.Result:
    return nmm3d.load(path, overrides).run(out=tmp_path / "run")


@pytest.mark.parametrize("a, t0", [(0.5, 0.2), (1.0, 0.1), (0.3, 0.3)])
def test_newmark_rectangular_pulse(tmp_path, a, t0):
    """u_m = V²/(2gN)(1 − N/A) within 2 %, for three pulses (the run lasts until it stops)."""
    stop = t0 * a / N
    r = run(tmp_path, NEWMARK, f"seismic.pulse.0.acceleration=[{a * G}, 0.0, 0.0]", f"seismic.pulse.0.duration={t0}",
            f"analysis.duration={stop + 0.1:.3f}")
    exact = analytic.newmark_pulse(a * G * t0, N, a, G)
    slip = -r.history["block.displacement.x"][-1]
    assert slip == pytest.approx(exact, rel=0.02)
    # At rest on the base once it has stopped.
    assert abs(r.history["block.velocity.x"][-1]) < 0.01 * a * G * t0


def test_below_the_yield_acceleration_the_block_rides_with_the_base(tmp_path):
    r = run(tmp_path, NEWMARK, f"seismic.pulse.0.acceleration=[{0.15 * G}, 0.0, 0.0]")
    assert max(abs(x) for x in r.history["block.displacement.x"]) < 1e-4


def test_the_pulse_ends_on_a_step_and_the_velocity_is_exact(tmp_path):
    """The block's speed relative to the base at the pulse's end: (A − N) g t₀ (steps end on the
    pulse's end, so none straddles the jump)."""
    r = run(tmp_path, NEWMARK, "analysis.duration=0.2", "analysis.dt=0.007")
    assert -r.history["block.velocity.x"][-1] == pytest.approx((0.5 - N) * G * 0.2, rel=1e-3)


def test_the_energy_balance_closes_across_the_jumps_of_the_pulse(tmp_path):
    """Gravity does no work; the base's work goes into kinetic energy and friction. At the
    pulse's start and end the step starts from the blocks' acceleration after the jump — once it
    solved from the one before it while `accept` went on from the one after, and the balance
    was 9 J (2.5 % of the base's work) short from the pulse's end on."""
    e = run(tmp_path, NEWMARK).summary["energy"]
    assert e["external_work"] == pytest.approx(e["friction_dissipation"] + e["kinetic"], rel=1e-3)
    assert e["max_error_ratio"] < 1e-6, e


def test_harmonic_base_motion_on_an_incline_against_the_integrated_newmark_solution(tmp_path):
    """A block on a 20° plane (φ = 30°) under a 2 Hz horizontal base sine of 0.35 g: it slips
    down in bursts; the slip against Newmark's method integrated in time."""
    amplitude, frequency, cycles = 0.35 * G, 2.0, 3.0
    d = nmm3d.load(NEWMARK).to_dict()
    # Tilt gravity instead of the model: a level base in a frame turned by ψ about y.
    psi = math.radians(20.0)
    d["analysis"]["gravity"] = [G * math.sin(psi), 0.0, -G * math.cos(psi)]
    d["joint"][0]["friction_angle"] = 30.0
    d["analysis"]["duration"] = cycles / frequency + 0.3
    # The horizontal base acceleration in the tilted frame: along x' and z'.
    d["seismic"] = {"sine": [{"amplitude": [amplitude * math.cos(psi), 0.0, amplitude * math.sin(psi)],
                              "frequency": frequency, "cycles": cycles}]}
    d["expect"] = []
    r = nmm3d.Scenario.from_dict(d).run(out=tmp_path / "run")
    def base(t: float) -> float:
        return amplitude * math.sin(2 * math.pi * frequency * t) if t < cycles / frequency else 0.0
    exact = analytic.newmark_incline(20.0, 30.0, G, base, d["analysis"]["duration"])
    assert exact > 0.05
    assert r.history["block.displacement.x"][-1] == pytest.approx(exact, rel=0.02)


def test_pseudo_static_coefficient_on_an_incline(tmp_path):
    """A horizontal coefficient kh = 0.1 out of the slope: the block on the 30° incline slides
    with a = g[(sin ψ + kh cos ψ) − (cos ψ − kh sin ψ) tan φ]."""
    kh, psi, phi = 0.1, math.radians(30.0), math.radians(24.0)
    r = run(tmp_path, EXAMPLES / "incline.toml", f"seismic.coefficient=[{kh}, 0.0, 0.0]")
    u = [r.history[f"cube.displacement.{c}"][-1] for c in "xyz"]
    t = r.history["time"][-1]
    acc = G * ((math.sin(psi) + kh * math.cos(psi)) - (math.cos(psi) - kh * math.sin(psi)) * math.tan(phi))
    # incline.toml's gravity is 10 m/s².
    acc *= 10.0 / G
    assert 2.0 * math.hypot(*u) / t**2 == pytest.approx(acc, rel=0.02)


def test_key_blocks_take_the_pseudo_static_force():
    for kh in (0.0, 0.1, 0.2):
        kb = nmm3d.keyblocks(nmm3d.load(EXAMPLES / "incline.toml", [f"seismic.coefficient=[{kh}, 0.0, 0.0]"]))
        [b] = kb.key_blocks()
        assert b.mode.factor_of_safety == pytest.approx(analytic.pseudo_static_planar_fs(30.0, 24.0, kh), abs=1e-9)
        assert b.weight == pytest.approx(2500.0 * 10.0, rel=1e-12)


@pytest.mark.parametrize("bad, key", [
    ("seismic.pulse.0.duration=0", "seismic.pulse[0].duration"),
    ('analysis.kind="static"', "seismic"),
])
def test_bad_seismic_inputs_are_named(bad, key):
    with pytest.raises(nmm3d.ScenarioError, match=key.replace("[", r"\[").replace("]", r"\]")):
        nmm3d.load(NEWMARK, [bad])


def test_a_series_of_velocities_is_the_pulse(tmp_path):
    """The same pulse as a velocity record (0 → V linearly over t₀, then V): the same slip."""
    v = 0.5 * G * 0.2
    d = nmm3d.load(NEWMARK).to_dict()
    d["seismic"] = {"series": {"quantity": "velocity", "time": [0.0, 0.2, 2.0],
                               "values": [[0.0, 0.0, 0.0], [v, 0.0, 0.0], [v, 0.0, 0.0]]}}
    r = nmm3d.Scenario.from_dict(d).run(out=tmp_path / "run")
    assert -r.history["block.displacement.x"][-1] == pytest.approx(analytic.newmark_pulse(v, N, 0.5, G), rel=0.02)


def test_a_recorded_motion_from_a_csv_file(tmp_path):
    """The pulse as a CSV velocity record in g·s (scale = 9.81), next to the scenario file."""
    v = 0.5 * 0.2  # V / g
    (tmp_path / "motion.csv").write_text(f"time,vx,vy,vz\n0.0,0,0,0\n0.2,{v},0,0\n2.0,{v},0,0\n")
    pulse = "pulse = [{ acceleration = [4.905, 0.0, 0.0], start = 0.0, duration = 0.2 }]"
    text = NEWMARK.read_text()
    assert pulse in text
    record = 'series = { quantity = "velocity", file = "motion.csv", scale = 9.81 }'
    (tmp_path / "shaken.toml").write_text(text.replace(pulse, record))
    loaded = nmm3d.load(tmp_path / "shaken.toml")
    assert loaded.to_dict()["seismic"]["series"]["values"][1] == pytest.approx([v * G, 0.0, 0.0])
    r = loaded.run(out=tmp_path / "run")
    exact = analytic.newmark_pulse(v * G, N, 0.5, G)
    assert -r.history["block.displacement.x"][-1] == pytest.approx(exact, rel=0.02)


@pytest.mark.parametrize("content, message", [(None, "cannot read"), ("0,1,2\n", "line 1")])
def test_a_bad_record_file_is_named(tmp_path, content, message):
    if content is not None:
        (tmp_path / "motion.csv").write_text(content)
    d = nmm3d.load(NEWMARK).to_dict()
    d["seismic"] = {"series": {"quantity": "acceleration", "file": str(tmp_path / "motion.csv")}}
    with pytest.raises(nmm3d.ScenarioError, match=f"seismic.series.file.*{message}"):
        nmm3d.Scenario.from_dict(d)


def test_the_base_motion_is_in_the_history(tmp_path):
    """base.velocity / base.displacement: the pulse integrated — V = A g t₀, then
    u = ½ A g t₀² + V (t − t₀); the block's absolute motion is the base's plus its own."""
    r = run(tmp_path, NEWMARK)
    t, a, t0 = r.history["time"], 0.5 * G, 0.2
    v = a * np.minimum(t, t0)
    u = np.where(t < t0, 0.5 * a * t**2, 0.5 * a * t0**2 + a * t0 * (t - t0))
    assert np.allclose(r.history["base.velocity.x"], v, atol=1e-9)
    assert np.allclose(r.history["base.displacement.x"], u, atol=1e-9)
    assert np.all(r.history["base.velocity.z"] == 0.0)
