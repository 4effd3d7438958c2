"""Symmetric roof wedges held by horizontal in-situ stress: the relaxation closed forms.

A wedge hangs in a flat roof (z = 0), bounded by n identical joint faces that lean inward at the
semi-apical angle α (angle between face and vertical; dip = 90° − α) and meet above the roof.
Horizontal in-situ stress σ_h (magnitude, compression) acting on a face whose normal lies in a
vertical plane gives the normal stress σ_n = σ_h cos²α and the up-dip shear τ₀ = σ_h sin α cos α;
the initial tractions of all faces balance (the roof carries no σ_zz). Under its weight W the
wedge settles by δ; each face opens by δ sin α and slips by δ cos α, so with stiffnesses k_n, k_s
per unit area (ΣA: total face area)

    N = σ_n ΣA − k_n ΣA δ sin α,   T = τ₀ ΣA + k_s ΣA δ cos α,   ΣA δ (k_s cos²α + k_n sin²α) = W,

and the wedge is at limit when T = N tan φ (Goodman, Shi & Boyle 1982; Brady & Brown,
"Rock Mechanics for Underground Mining", §9.3; Sofianos 1986). For k_s = k_n:

    tan(φ_c − α) = W cos α / (σ_n ΣA).

With zero cohesion the factor of safety by strength reduction (tan φ / F) is
FS = tan φ / tan φ_c. The 2-D-like prism (two faces, σ_xx only, free ends) and the pyramid
(four faces, σ_xx = σ_yy) follow with their own W and ΣA.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class RoofWedge:
    """A symmetric roof wedge: n faces at semi-apical angle α, weight W, total face area ΣA."""

    alpha: float        #: semi-apical angle [deg]
    weight: float       #: W [N]
    face_area: float    #: ΣA [m²]
    sigma_h: float      #: horizontal in-situ stress magnitude (compression positive here) [Pa]

    @property
    def sigma_n(self) -> float:
        """Initial normal stress on each face [Pa]."""
        return self.sigma_h * math.cos(math.radians(self.alpha)) ** 2

    def settlement(self, kn: float, ks: float) -> float:
        """δ = W / (ΣA (k_s cos²α + k_n sin²α)) with k per unit area [Pa/m]."""
        a = math.radians(self.alpha)
        return self.weight / (self.face_area * (ks * math.cos(a) ** 2 + kn * math.sin(a) ** 2))

    def critical_friction_angle(self, kn: float = 1.0, ks: float = 1.0) -> float:
        """φ_c [deg] at which T = N tan φ after settling (any k_s/k_n; k_s = k_n by default)."""
        a = math.radians(self.alpha)
        delta_a = self.settlement(kn, ks) * self.face_area  # δ ΣA
        n = self.sigma_n * self.face_area - kn * delta_a * math.sin(a)
        t = self.sigma_n * math.tan(a) * self.face_area + ks * delta_a * math.cos(a)
        return 90.0 if n <= 0 else math.degrees(math.atan(t / n))

    def factor_of_safety(self, friction_angle: float, kn: float = 1.0, ks: float = 1.0) -> float:
        """Strength-reduction factor of safety without cohesion: tan φ / tan φ_c."""
        return math.tan(math.radians(friction_angle)) / math.tan(math.radians(self.critical_friction_angle(kn, ks)))


def prism(half_width: float, height: float, length: float, density: float, g: float, sigma_h: float) -> RoofWedge:
    """Two faces from the roof edges x = ±half_width up to a ridge at ``height``, along y."""
    alpha = math.degrees(math.atan(half_width / height))
    weight = density * g * half_width * height * length
    area = 2.0 * length * math.hypot(half_width, height)
    return RoofWedge(alpha, weight, area, sigma_h)


def pyramid(half_width: float, height: float, density: float, g: float, sigma_h: float) -> RoofWedge:
    """Four faces from the edges of a square (side 2·half_width) up to an apex at ``height``."""
    alpha = math.degrees(math.atan(half_width / height))
    weight = density * g * (2.0 * half_width) ** 2 * height / 3.0
    area = 4.0 * half_width * math.hypot(half_width, height)
    return RoofWedge(alpha, weight, area, sigma_h)
