"""Closed-form reference answers used by the verification suite and the docs.

Each function cites its source; units SI, g and angles as given.
"""

from __future__ import annotations

import math

import numpy as np


def ballistic(v0, g, t):
    """Free flight: u = v₀t + ½gt², v = v₀ + gt (exact for the DDA scheme)."""
    v0, g = np.asarray(v0, float), np.asarray(g, float)
    return v0 * t + 0.5 * g * t * t, v0 + g * t


def bar_end_load(stress: float, length: float, young: float) -> float:
    """Elongation of a bar under uniform end traction: σL/E."""
    return stress * length / young


def hanging_bar(density: float, g: float, length: float, young: float) -> float:
    """Elongation of a bar hanging under its own weight: ρgL²/(2E) (Timoshenko & Goodier §100)."""
    return density * g * length**2 / (2.0 * young)


def cantilever_tip_load(force: float, length: float, young: float, inertia: float) -> float:
    """Euler–Bernoulli tip deflection PL³/(3EI)."""
    return force * length**3 / (3.0 * young * inertia)


def cantilever_self_weight(weight_per_length: float, length: float, young: float, inertia: float) -> float:
    """Euler–Bernoulli tip deflection under uniform load qL⁴/(8EI)."""
    return weight_per_length * length**4 / (8.0 * young * inertia)


def kirchhoff_plate_corners(q: float, a: float, thickness: float, young: float, poisson: float) -> float:
    """Centre deflection of a square Kirchhoff plate on four corner points under uniform load q:
    w = 0.0255065 q a⁴ / D, D = Eh³/(12(1 − ν²)) (docs/verification.md (e); Timoshenko &
    Woinowsky-Krieger, plates supported at the corners)."""
    d = young * thickness**3 / (12.0 * (1.0 - poisson**2))
    return 0.0255065 * q * a**4 / d


def incline_sliding(slope_deg: float, friction_deg: float, g: float, t: float) -> float:
    """Distance slid down an incline from rest: ½g(sin α − tan φ cos α)t², 0 if φ ≥ α
    (thesis eq. 4-1)."""
    a, f = math.radians(slope_deg), math.radians(friction_deg)
    return max(0.0, 0.5 * g * (math.sin(a) - math.tan(f) * math.cos(a)) * t * t)
