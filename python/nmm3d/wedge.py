"""Rigid tetrahedral wedge on two planes: the Hoek & Bray vector method (a Swedge-like check).

Planes by dip / dip direction (x = East, y = North, z = Up). With unit normals v_A, v_B pointing
up into the wedge, c = v_A·v_B and W the weight, the normal reactions when the wedge rests on
both planes are

    N_A / W = (v_Az − c v_Bz) / (1 − c²),    N_B / W = (v_Bz − c v_Az) / (1 − c²),

and the wedge slides along the (downward) line of intersection i with plunge ψ_i:

    FS = (N_A tan φ_A + N_B tan φ_B + c_A A_A + c_B A_B) / (W sin ψ_i).

Modes: both reactions negative → the wedge lifts off both planes (falls); one negative → it
slides on the other plane alone (FS = (N tan φ + cA) / (W sin ψ) with N = W cos ψ of that plane);
else it slides on both. Dynamic sliding (FS < 1): a = g sin ψ (1 − FS) along the sliding direction.
Source: Hoek & Bray (1981) Rock Slope Engineering, ch. 8 and appendix; Wyllie & Mah (2004) ch. 7;
docs/verification.md (d).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def plane_normal(dip: float, dip_direction: float) -> np.ndarray:
    """Upward unit normal n = (sin δ sin α, sin δ cos α, cos δ)."""
    d, a = math.radians(dip), math.radians(dip_direction)
    return np.array([math.sin(d) * math.sin(a), math.sin(d) * math.cos(a), math.cos(d)])


def dip_vector(dip: float, dip_direction: float) -> np.ndarray:
    """Unit vector down the dip."""
    d, a = math.radians(dip), math.radians(dip_direction)
    return np.array([math.cos(d) * math.sin(a), math.cos(d) * math.cos(a), -math.sin(d)])


def trend_plunge(v: np.ndarray) -> tuple[float, float]:
    """Trend (clockwise from North) and plunge (down from horizontal) of a direction, degrees."""
    v = v / np.linalg.norm(v)
    if v[2] > 0:
        v = -v
    return math.degrees(math.atan2(v[0], v[1])) % 360.0, math.degrees(math.asin(-v[2]))


@dataclass(frozen=True)
class WedgeResult:
    """Outcome of the wedge check (forces per unit weight)."""

    mode: str                   #: "lift-off", "sliding on A", "sliding on B", "sliding on both"
    factor_of_safety: float     #: 0 for lift-off
    direction: np.ndarray       #: unit sliding direction (downward); zeros for lift-off
    acceleration: float         #: sliding acceleration [m/s²] (0 if stable)
    normal_a: float             #: N_A / W
    normal_b: float             #: N_B / W
    trend: float                #: of the sliding direction [deg]
    plunge: float               #: of the sliding direction [deg]

    @property
    def stable(self) -> bool:
        return self.mode != "lift-off" and self.factor_of_safety >= 1.0


def wedge(plane_a: tuple[float, float], plane_b: tuple[float, float], friction_a: float, friction_b: float | None = None,
          g: float = 9.81, weight: float = 1.0, cohesion_force_a: float = 0.0, cohesion_force_b: float = 0.0,
          above_a: bool = True, above_b: bool = True) -> WedgeResult:
    """Check a wedge bounded by planes A and B, given as (dip, dip direction) in degrees.

    Friction angles in degrees; `cohesion_force_*` = cohesion × face area [N] (with `weight` in N).
    `above_*`: whether the wedge lies above that plane (its normal into the wedge points up); a
    wedge hanging under an overhanging joint lies below it.
    """
    fb = friction_a if friction_b is None else friction_b
    va = plane_normal(*plane_a) * (1.0 if above_a else -1.0)
    vb = plane_normal(*plane_b) * (1.0 if above_b else -1.0)
    c = float(va @ vb)
    if abs(1.0 - c * c) < 1e-12:
        raise ValueError("the two planes are parallel: no wedge")
    i = np.cross(va, vb)
    i /= np.linalg.norm(i)
    if i[2] > 0:
        i = -i
    na = (va[2] - c * vb[2]) / (1.0 - c * c)
    nb = (vb[2] - c * va[2]) / (1.0 - c * c)
    ta, tb = math.tan(math.radians(friction_a)), math.tan(math.radians(fb))
    if na < 0 and nb < 0:
        return WedgeResult("lift-off", 0.0, np.zeros(3), g, na, nb, 0.0, 90.0)
    if nb < 0 or na < 0:
        on_a = nb < 0
        dip, dd = plane_a if on_a else plane_b
        s = dip_vector(dip, dd)
        psi = math.radians(dip)
        n = math.cos(psi)
        tan, coh = (ta, cohesion_force_a) if on_a else (tb, cohesion_force_b)
        drive = math.sin(psi)
        fs = (n * tan + coh / weight) / drive if drive > 0 else math.inf
        mode = "sliding on A" if on_a else "sliding on B"
        return _result(mode, fs, s, drive, g, na if on_a else 0.0, 0.0 if on_a else nb)
    drive = -i[2]  # sin ψ_i
    fs = (na * ta + nb * tb + (cohesion_force_a + cohesion_force_b) / weight) / drive if drive > 0 else math.inf
    return _result("sliding on both", fs, i, drive, g, na, nb)


def _result(mode, fs, direction, sin_psi, g, na, nb) -> WedgeResult:
    accel = g * sin_psi * (1.0 - fs) if fs < 1.0 else 0.0
    trend, plunge = trend_plunge(direction)
    return WedgeResult(mode, fs, direction, accel, na, nb, trend, plunge)


def critical_friction_angle(plane_a: tuple[float, float], plane_b: tuple[float, float]) -> float:
    """Friction angle (equal on both planes, no cohesion) at which FS = 1 [deg]."""
    r = wedge(plane_a, plane_b, 45.0)
    if r.mode == "lift-off":
        return 90.0
    # FS is proportional to tan φ when cohesion is zero.
    return math.degrees(math.atan(1.0 / r.factor_of_safety))
