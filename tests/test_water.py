"""Joint water pressure ([water]): hydrostatic pressure below a water table, against Archimedes
(a run with every face below the table wet), the uplift on a drained block's base (a run with
drained free faces) and Hoek & Bray's planar factor of safety with the uplift U and the crack
force V (the key-block analysis with drained free faces).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import nmm3d
from nmm3d import analytic

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
INCLINE = EXAMPLES / "incline.toml"  # 1 m cube, ρ = 2500, on a 30° plane, φ = 24°, g = 10
G, PSI, PHI, RHO = 10.0, 30.0, 24.0, 2500.0


def slide(r: nmm3d.Result) -> list[float]:
    return [r.history[f"cube.displacement.{c}"][-1] for c in "xyz"]


def sliding_acceleration(tmp_path, *overrides) -> float:
    return acceleration(nmm3d.load(INCLINE, overrides).run(out=tmp_path / "run"))


def acceleration(r: nmm3d.Result) -> float:
    return 2.0 * math.hypot(*slide(r)) / r.history["time"][-1] ** 2


@pytest.fixture(scope="module")
def submerged(tmp_path_factory) -> nmm3d.Result:
    """The incline cube under a table 5 m up (one run for the tests that read it)."""
    return nmm3d.load(INCLINE, ["water.table=5.0"]).run(out=tmp_path_factory.mktemp("submerged"))


def test_a_submerged_block_slides_straight_down(submerged):
    """The pressure follows the faces: held on the reference faces, the pushes on opposite faces
    made a couple that turned the sliding cube and drove it sideways (1 % of its slide in 1 s)."""
    u = slide(submerged)
    assert abs(u[1]) < 1e-3 * math.hypot(*u), u


def test_a_submerged_block_slides_as_archimedes_says(submerged):
    """Pressure on every face below the table: the net push is the buoyancy ρ_w g V_sub, so the
    block slides with a = g (1 − ρ_w V_sub / (ρ V)) (sin ψ − cos ψ tan φ)."""
    dry = analytic.incline_sliding(PSI, PHI, G, 1.0) * 2.0
    exact = dry * (1.0 - 1000.0 / RHO)
    assert acceleration(submerged) == pytest.approx(exact, rel=0.01)


def wet_area(h: float) -> float:
    """Area of the cube's cross-section (a unit square turned 30°, lowest corner at height 0)
    below height h: the square clipped by the water line, by the shoelace formula."""
    a = math.radians(PSI)
    square = [(0.0, 0.0), (math.cos(a), math.sin(a)), (math.cos(a) - math.sin(a), math.sin(a) + math.cos(a)),
              (-math.sin(a), math.cos(a))]
    wet = []
    for p, q in zip(square, square[1:] + square[:1]):
        if p[1] <= h:
            wet.append(p)
        if (p[1] - h) * (q[1] - h) < 0.0:
            wet.append((p[0] + (h - p[1]) / (q[1] - p[1]) * (q[0] - p[0]), h))
    return 0.5 * abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(wet, wet[1:] + wet[:1])))


def sinking_slide(t_end: float, h0: float, steps: int = 20000) -> float:
    """Distance slid in `t_end` by the cube with the table h0 above its lowest edge: the wet
    volume is the wet cross-section × 1 m, and h grows by s sin ψ as the cube slides s down:
    s'' = a_dry (1 − ρ_w V_sub(s) / ρ V) (RK4)."""
    dry = analytic.incline_sliding(PSI, PHI, G, 1.0) * 2.0
    sin_psi = math.sin(math.radians(PSI))

    def f(y):
        return (y[1], dry * (1.0 - 1000.0 * wet_area(h0 + y[0] * sin_psi) / RHO))

    y, dt = (0.0, 0.0), t_end / steps
    for _ in range(steps):
        k1 = f(y)
        k2 = f((y[0] + 0.5 * dt * k1[0], y[1] + 0.5 * dt * k1[1]))
        k3 = f((y[0] + 0.5 * dt * k2[0], y[1] + 0.5 * dt * k2[1]))
        k4 = f((y[0] + dt * k3[0], y[1] + dt * k3[1]))
        y = tuple(y[i] + dt / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]) for i in range(2))
    return y[0]


def test_a_partly_submerged_block_slides_deeper_into_the_water(tmp_path):
    """The table 0.4 m above the cube's lowest edge (z = −0.25); the pressure follows the faces, so
    the buoyancy grows as the cube slides down into the water (in 1 s from 18 % to 47 % of the
    cube under water; held at the start's wet volume it would slide 2 % farther)."""
    assert wet_area(0.4) == pytest.approx(2 * 0.4**2 / math.sqrt(3))  # ½ h (h cot 30° + h cot 60°)
    exact = 2.0 * sinking_slide(1.0, 0.4)
    assert sliding_acceleration(tmp_path, "water.table=0.15") == pytest.approx(exact, rel=0.01)


def test_water_below_the_block_changes_nothing(tmp_path):
    dry = sliding_acceleration(tmp_path / "dry")
    assert sliding_acceleration(tmp_path / "wet", "water.table=-1.0") == pytest.approx(dry, rel=1e-12)


@pytest.mark.parametrize("table", [0.5, 1.0])
def test_a_drained_block_slides_on_the_uplift_of_its_base_alone(tmp_path, table):
    """free_faces = "drained": only the faces another block touches are wet — here the cube's
    base, its open faces dry (Hoek & Bray's seepage face). The uplift U = γ_w A (h_w − h) on the
    base takes off the normal force and grows as the base goes down the plane (h = −s sin ψ):
    s'' = a₀ + k s, a₀ = g sin ψ − (g cos ψ − U₀/m) tan φ, k = γ_w A sin ψ tan φ / m, so
    s = (a₀/k)(cosh √k t − 1). (Submerged, Archimedes would buoy the whole cube instead.)"""
    r = nmm3d.load(INCLINE, [f"water.table={table}", 'water.free_faces="drained"']).run(out=tmp_path / "run")
    psi, phi, m, gw, area = math.radians(PSI), math.radians(PHI), RHO * 1.0, 1000.0 * G, 1.0
    a0 = G * math.sin(psi) - (G * math.cos(psi) - gw * area * table / m) * math.tan(phi)
    k = gw * area * math.sin(psi) * math.tan(phi) / m
    t = r.history["time"][-1]
    assert math.hypot(*slide(r)) == pytest.approx(a0 / k * (math.cosh(math.sqrt(k) * t) - 1.0), rel=2e-3)
    assert abs(slide(r)[1]) < 1e-3 * math.hypot(*slide(r))  # straight down the plane


def test_key_block_with_uplift_on_its_base_is_hoek_and_bray():
    """Drained free faces, the base wet over 0.8 m with pressure falling linearly from
    γ_w 0.4 m to 0: U = ½ γ_w 0.4 × 0.8 × 1 m; FS = (W cos ψ − U) tan φ / (W sin ψ)."""
    kb = nmm3d.keyblocks(nmm3d.load(INCLINE, ["water.table=0.15", 'water.free_faces="drained"']))
    [b] = kb.key_blocks()
    w, u = RHO * G, 0.5 * 1000.0 * G * 0.4 * 0.8
    assert b.mode.factor_of_safety == pytest.approx(analytic.planar_fs(w, PSI, PHI, uplift=u), abs=1e-9)
    # Submerged all round, the water only buoys it: the factor of safety is the dry one.
    dry = nmm3d.keyblocks(INCLINE).key_blocks()[0].mode.factor_of_safety
    wet = nmm3d.keyblocks(nmm3d.load(INCLINE, ["water.table=0.15"])).key_blocks()[0].mode.factor_of_safety
    assert wet == pytest.approx(dry, abs=1e-12)


def step_model(table: float) -> nmm3d.Scenario:
    """A 2 × 1 × 1 m block on a base, its back against a wall (the tension crack); gravity tilted
    by ψ so that the base dips ψ down +x and the crack stands normal to it."""
    psi = math.radians(PSI)
    box = lambda lo, hi: {"box": {"min": lo, "max": hi}}  # noqa: E731
    return nmm3d.Scenario.from_dict({
        "analysis": {"gravity": [G * math.sin(psi), 0.0, -G * math.cos(psi)]},
        "material": [{"name": "rock", "density": RHO, "young": 1e10, "poisson": 0.25}],
        "joint": [{"name": "j", "friction_angle": PHI}],
        "water": {"table": table, "free_faces": "drained"},
        "body": [
            {"name": "base", "material": "rock", "fixed": True, "shape": box([-2.0, 0.0, -1.0], [4.0, 1.0, 0.0])},
            {"name": "wall", "material": "rock", "fixed": True, "shape": box([-2.0, 0.0, 0.0], [0.0, 1.0, 2.0])},
            {"name": "block", "material": "rock", "joint": "j", "shape": box([0.0, 0.0, 0.0], [2.0, 1.0, 1.0])},
        ],
    })


def test_key_block_with_a_water_filled_crack_is_hoek_and_bray():
    """Heights against gravity h = −x sin ψ + z cos ψ; table at h = 0.6 cos ψ: the crack (x = 0)
    is wet up to z = 0.6, V = γ_w cos ψ 0.6²/2 pushing down the base; the whole base is wet,
    U = γ_w ∫₀² (0.6 cos ψ + x sin ψ) dx. FS = (W cos ψ − U) tan φ / (W sin ψ + V)."""
    psi = math.radians(PSI)
    gw = 1000.0 * G
    kb = nmm3d.keyblocks(step_model(0.6 * math.cos(psi)))
    [b] = kb.key_blocks()
    u = gw * (1.2 * math.cos(psi) + 2.0 * math.sin(psi))
    v = gw * math.cos(psi) * 0.6**2 / 2
    exact = analytic.planar_fs(2 * RHO * G, PSI, PHI, uplift=u, crack=v, crack_angle=0.0)
    assert b.mode.mode == "sliding_one_plane"
    assert b.mode.factor_of_safety == pytest.approx(exact, abs=1e-9)
    # And dry, the textbook tan φ / tan ψ.
    dry = nmm3d.keyblocks(step_model(-10.0)).key_blocks()[0]
    assert dry.mode.factor_of_safety == pytest.approx(math.tan(math.radians(PHI)) / math.tan(psi), abs=1e-12)
