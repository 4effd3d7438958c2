"""Random joint data for Monte-Carlo studies, and the probability of failure with its interval.

* Fisher distribution of a pole about its mean (Fisher 1953; sampling after Wood 1994,
  "Simulation of the von Mises–Fisher distribution"): cos θ = 1 + ln(u + (1 − u) e^{−2κ}) / κ,
  azimuth uniform; E[cos θ] = coth κ − 1/κ.
* Normal scatter truncated to an interval by rejection (the mean stays the scenario's value).
* Wilson's score interval for a binomial proportion (Wilson 1927; Agresti & Coull 1998), which
  keeps its coverage at p near 0 or 1 where the normal approximation does not.
"""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np

from nmm3d.wedge import plane_normal


def fisher_pole(mean: np.ndarray, kappa: float, rng: np.random.Generator) -> np.ndarray:
    """One unit vector from the Fisher distribution about the unit vector ``mean``."""
    u = rng.random()
    w = 1.0 + math.log(u + (1.0 - u) * math.exp(-2.0 * kappa)) / kappa
    phi = 2.0 * math.pi * rng.random()
    s = math.sqrt(max(0.0, 1.0 - w * w))
    a, b = _frame(mean)
    return w * mean + s * (math.cos(phi) * a + math.sin(phi) * b)


def _frame(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing ``n`` to an orthonormal frame."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a = np.cross(n, helper)
    a /= np.linalg.norm(a)
    return a, np.cross(n, a)


def dip_and_direction(normal: np.ndarray) -> tuple[float, float]:
    """Dip and dip direction [deg] of the plane with this normal (either sense)."""
    n = normal / np.linalg.norm(normal)
    if n[2] < 0:
        n = -n
    dip = math.degrees(math.acos(min(1.0, n[2])))
    return dip, math.degrees(math.atan2(n[0], n[1])) % 360.0


def scatter_plane(dip: float, dip_direction: float, kappa: float, rng: np.random.Generator) -> tuple[float, float]:
    """A plane whose pole is Fisher-distributed about the pole of (dip, dip direction)."""
    return dip_and_direction(fisher_pole(plane_normal(dip, dip_direction), kappa, rng))


def truncated_normal(mean: float, sd: float, low: float, high: float, rng: np.random.Generator) -> float:
    """A normal sample inside [low, high] (rejection; the mean itself is always admissible)."""
    if sd == 0.0:
        return mean
    for _ in range(1000):
        x = rng.normal(mean, sd)
        if low <= x <= high:
            return float(x)
    return float(min(max(mean, low), high))


def wilson_interval(failures: int, n: int, confidence: float) -> tuple[float, float]:
    """Wilson score interval of the proportion failures / n."""
    if n == 0:
        return 0.0, 1.0
    z = NormalDist().inv_cdf(0.5 + confidence / 2.0)
    p = failures / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    lo = 0.0 if failures == 0 else max(0.0, centre - half)  # exact ends: no round-off off 0 or 1
    hi = 1.0 if failures == n else min(1.0, centre + half)
    return lo, hi
