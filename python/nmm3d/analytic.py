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


def newmark_pulse(velocity: float, yield_coefficient: float, pulse_coefficient: float, g: float) -> float:
    """Slip of a rigid block on a level base shaken by one rectangular acceleration pulse A g of
    velocity V = A g t₀, when the yield acceleration is N g < A g:
    u_m = V² / (2 g N) · (1 − N / A) (Newmark 1965, Géotechnique 15(2), eq. 8); 0 if N ≥ A."""
    n, a = yield_coefficient, pulse_coefficient
    return 0.0 if n >= a else velocity**2 / (2.0 * g * n) * (1.0 - n / a)


def newmark_incline(slope_deg: float, friction_deg: float, g: float, base_acceleration, duration: float,
                    dt: float = 1e-5) -> float:
    """Downslope slip of a rigid block on a plane dipping ``slope_deg`` towards +x under a
    horizontal base acceleration a_b(t) along x, integrated in time (Newmark's method on an
    incline: Goodman & Seed 1966; Franklin & Chang 1977). In the base's frame the block feels
    −m a_b; the normal force is m (g cos ψ + a_b sin ψ), the downslope drive m (g sin ψ − a_b cos ψ);
    it slides down while the drive exceeds tan φ × normal or while it moves (upslope slip is
    taken as impossible, true for the cases used here), and stops when its speed returns to 0."""
    psi, tan = math.radians(slope_deg), math.tan(math.radians(friction_deg))
    s, v, t = 0.0, 0.0, 0.0
    while t < duration:
        ab = base_acceleration(t)
        drive = g * math.sin(psi) - ab * math.cos(psi)
        normal = g * math.cos(psi) + ab * math.sin(psi)
        acc = drive - tan * normal
        if v > 0.0 or acc > 0.0:
            v_new = v + acc * dt
            if v_new < 0.0:  # stops within the step
                s += 0.5 * v * v / -acc if acc < 0 else 0.0
                v = 0.0
            else:
                s += 0.5 * (v + v_new) * dt
                v = v_new
        t += dt
    return s


def pseudo_static_planar_fs(slope_deg: float, friction_deg: float, kh: float) -> float:
    """Factor of safety of a block on a plane of dip ψ under its weight and a horizontal
    pseudo-static force kh W pointing down the dip direction (out of the slope):
    FS = (cos ψ − kh sin ψ) tan φ / (sin ψ + kh cos ψ) (Hoek & Bray 1981, ch. 7)."""
    psi, tan = math.radians(slope_deg), math.tan(math.radians(friction_deg))
    return (math.cos(psi) - kh * math.sin(psi)) * tan / (math.sin(psi) + kh * math.cos(psi))


def planar_fs(weight: float, slope_deg: float, friction_deg: float, cohesion_force: float = 0.0, uplift: float = 0.0,
              crack: float = 0.0, crack_angle: float | None = None) -> float:
    """Factor of safety of a block sliding on one plane of dip ψ with water (Hoek & Bray 1981,
    Rock Slope Engineering, ch. 7, eq. for plane failure):
    FS = (c A + (W cos ψ − U − V sin θ) tan φ) / (W sin ψ + V cos θ),
    U the water's uplift on the sliding plane, V its push on the tension crack and θ the angle
    between V and the sliding plane (θ = ψ for a vertical crack, the textbook case; 0 for a
    crack normal to the plane)."""
    psi, tan = math.radians(slope_deg), math.tan(math.radians(friction_deg))
    theta = psi if crack_angle is None else math.radians(crack_angle)
    normal = weight * math.cos(psi) - uplift - crack * math.sin(theta)
    return (cohesion_force + normal * tan) / (weight * math.sin(psi) + crack * math.cos(theta))


def grouted_side_stiffness(axial_rigidity: float, bond_stiffness: float, length: float) -> float:
    """Axial stiffness [N/m] of a bar of rigidity EA [N] bonded over ``length`` [m] by a grout of
    shear stiffness k_b [N/m per m], pulled at one end: √(EA k_b) tanh(βL), β = √(k_b/EA)
    (Farmer 1975)."""
    return math.sqrt(axial_rigidity * bond_stiffness) * math.tanh(math.sqrt(bond_stiffness / axial_rigidity) * length)


def grouted_axial_stiffness(axial_rigidity: float, bond_stiffness: float, l1: float, l2: float) -> float:
    """Axial stiffness [N/m] of a grouted bar across a joint with ``l1`` and ``l2`` [m] bonded on
    its sides: the two sides in series."""
    k1, k2 = (grouted_side_stiffness(axial_rigidity, bond_stiffness, length) for length in (l1, l2))
    return k1 * k2 / (k1 + k2)


def dowel_stiffness(foundation_modulus: float, bending_rigidity: float) -> float:
    """Shear stiffness [N/m] of a bar across a joint: each side a semi-infinite beam of rigidity
    EI [N m²] on a Winkler foundation k_f [Pa], loaded at the joint with zero moment, deflects
    2Vλ/k_f (Hetényi 1946), λ = (k_f/4EI)^¼; the joint's shear is twice that: k_f/(4λ)."""
    lam = (foundation_modulus / (4.0 * bending_rigidity)) ** 0.25
    return foundation_modulus / (4.0 * lam)


def lame_excavation(r, a: float, b: float, pressure: float, young: float, poisson: float):
    """Radial displacement [m] (outward positive) and hoop stress change [Pa] (tension positive)
    at radius ``r`` when a circular opening of radius ``a`` is excavated in a thick cylinder
    (outer radius ``b``, its outer traction unchanged) under hydrostatic in-situ stress
    ``pressure`` (compression, > 0), plane strain: u = A r + B / r with the radial stress change
    +p at r = a and 0 at r = b (Lamé; Jaeger, Cook & Zimmerman, *Fundamentals of Rock
    Mechanics*, 4th ed. 2007, ch. 8). As b → ∞ it is
    Kirsch's u = −p a² (1 + ν) / (E r)."""
    g = young / (2.0 * (1.0 + poisson))
    lam = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))
    # σ_r = 2(λ + G) A − 2G B / r²; σ_θ = 2(λ + G) A + 2G B / r².
    m = np.array([[2.0 * (lam + g), -2.0 * g / a**2], [2.0 * (lam + g), -2.0 * g / b**2]])
    big_a, big_b = np.linalg.solve(m, [pressure, 0.0])
    r = np.asarray(r, dtype=float)
    return big_a * r + big_b / r, 2.0 * (lam + g) * big_a + 2.0 * g * big_b / r**2


def footing_on_joint(load: float, width: float, length: float, eccentricity: float, stiffness: float):
    """Rotation [rad], settlement of the base's centre [m] (down positive) and contact width [m]
    of a rigid footing (base ``width`` × ``length``) on a tensionless joint of normal stiffness
    ``stiffness`` [Pa/m], under a vertical ``load`` [N] at ``eccentricity`` [m] from the centre
    across the width. Inside the kern (e ≤ B/6) the whole base presses: θ = 12 P e / (k L B³),
    δ₀ = P / (k B L). Beyond it the heel lifts and the pressure is a triangle over
    c = 3 (B/2 − e), its peak 2P / (c L) (Bowles, *Foundation Analysis and Design*, 5th ed.
    1996, §4-8): θ = 2P / (k c² L), δ₀ = θ (c − B/2)."""
    half, e = 0.5 * width, abs(eccentricity)
    if e <= width / 6.0:
        return 12.0 * load * e / (stiffness * length * width**3), load / (stiffness * width * length), width
    c = 3.0 * (half - e)
    theta = 2.0 * load / (stiffness * c * c * length)
    return theta, theta * (c - half), c


def corner_lumped_rotation(rotation: float, cell: float, width: float) -> float:
    """The rotation [rad] of a footing pressing with its whole base (``footing_on_joint`` in the
    kern) when the joint's springs sit at the corners of square cover cells of side ``cell`` [m],
    each carrying an equal share of its cell's area: their moment of inertia is the trapezoidal
    rule's Σ A x², larger than ∫ x² dA = L B³/12 by the rule's error L B h²/6 (a width of whole
    cells), so θ_h = θ / (1 + 2h² / B²) — second order in the cell."""
    return rotation / (1.0 + 2.0 * (cell / width) ** 2)
