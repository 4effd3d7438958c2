"""Block theory for one block: removability and the limit-equilibrium failure mode.

A block touches rock across planes k with unit normals n_k pointing *out of the block* (into the
rock beyond). A translation s can start only if s·n_k ≤ 0 for every k; the block is removable
when such an s ≠ 0 exists (Goodman & Shi 1985, ch. 5: a finite block whose joint pyramid, cut
with the rock side of its free faces, is empty).

Under the active resultant r (weight, in N) the mode is the one of Goodman & Shi (1985, ch. 8)
whose conditions hold:

* falling (lifting): r·n_k ≤ 0 for every k — it leaves every plane; FS = 0.
* sliding on plane i: N_i = r·n_i > 0, s = (r − N_i n_i)/T with T = |r − N_i n_i|, s·n_k ≤ 0 for
  k ≠ i; FS = (N_i tan φ_i + c_i A_i) / T.
* sliding on planes i, j: s = ±(n_i × n_j)/|n_i × n_j| with r·s > 0, s·n_k ≤ 0 for k ≠ i, j, and
  r − (r·s)s = N_i n_i + N_j n_j with N_i, N_j > 0; FS = (Σ N tan φ + Σ c A) / (r·s).
* stable: removable, but r presses it into the rock along every way it could move (a floor
  block under gravity); FS = ∞.

The critical friction angle is the friction angle, equal on the sliding planes, at which FS = 1:
tan φ_c = (T − Σ c A) / Σ N (0 when cohesion alone holds the block; 90° for falling).
Passive support P (bolts at capacity) adds its normal parts to the N and −P·s to the
resistance; a falling block's FS is then −P·s / |r|.
Rotation is outside translational theory: :func:`weight_line_leaves` flags a block whose line of
action through its centroid misses its sliding faces (possible toppling).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

#: Mode names, as written to ``keyblocks.csv``.
FALLING, ONE_PLANE, TWO_PLANES, NOT_REMOVABLE, STABLE = (
    "falling", "sliding_one_plane", "sliding_two_planes", "not_removable", "stable")


@dataclass(frozen=True)
class Plane:
    """One plane a block touches rock across (faces of a block with one outward normal and joint)."""

    normal: np.ndarray          #: unit, out of the block
    area: float                 #: contact area [m²]
    friction_angle: float       #: [deg]
    cohesion: float = 0.0       #: [Pa]
    label: str = ""             #: e.g. "set 1", "joint 2", "face of bedrock"


@dataclass(frozen=True)
class Mode:
    """The failure mode of a block under a resultant force."""

    mode: str                            #: one of the mode names above
    direction: np.ndarray                #: unit direction of the movement (zeros if none)
    planes: tuple[int, ...] = ()         #: indices of the sliding planes
    normal_forces: tuple[float, ...] = ()  #: N on each sliding plane [N]
    driving_force: float = 0.0           #: T along ``direction`` [N]
    factor_of_safety: float = math.inf
    critical_friction_angle: float = math.nan  #: [deg]


def can_move(normals: list[np.ndarray], tol: float = 1e-9) -> np.ndarray | None:
    """A unit translation s with s·n ≤ tol for every normal, or None when the block is locked.

    The cone {s : s·n_k ≤ 0} is non-trivial iff it holds one of the candidates: an edge
    ±(n_i × n_j) (a pointed cone's extreme ray lies on two planes), −n_k (all normals alike)
    or a vector normal to n_k (opposite normals leave a plane of motion).
    """
    if not normals:
        return np.array([0.0, 0.0, -1.0])
    candidates = [-n for n in normals]
    for a, b in itertools.combinations(normals, 2):
        c = np.cross(a, b)
        if np.linalg.norm(c) > tol:
            c = c / np.linalg.norm(c)
            candidates += [c, -c]
    for n in normals:
        p = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        p /= np.linalg.norm(p)
        candidates += [p, -p, np.cross(n, p), -np.cross(n, p)]
    for s in candidates:
        if all(float(s @ n) <= tol for n in normals):
            return s
    return None


def failure_mode(planes: list[Plane], force: np.ndarray, support: np.ndarray | None = None,
                 tol: float = 1e-9) -> Mode:
    """The mode, factor of safety and critical friction angle of a block under the active
    ``force`` [N], resisted by the passive ``support`` [N] (bolts at their capacity): the mode
    is the active force's; the support adds its normal components to the planes' normal forces
    and its component against the movement to the resistance (the passive support of Unwedge
    and Swedge; Hoek, Practical Rock Engineering, ch. 10)."""
    support = np.zeros(3) if support is None else np.asarray(support, float)
    normals = [p.normal for p in planes]
    if can_move(normals, tol) is None:
        return Mode(NOT_REMOVABLE, np.zeros(3))
    w = float(np.linalg.norm(force))
    if w == 0.0:
        return Mode(STABLE, np.zeros(3))
    r = force / w  # work per unit force; forces scaled back below
    if all(float(r @ n) <= tol for n in normals):
        held = max(0.0, -float(support @ r))
        return Mode(FALLING, r, driving_force=w, factor_of_safety=held / w, critical_friction_angle=90.0)
    for i in range(len(planes)):
        m = _one_plane(planes, i, r, tol)
        if m is not None:
            return _scaled(planes, m, w, support)
    for i, j in itertools.combinations(range(len(planes)), 2):
        m = _two_planes(planes, i, j, r, tol)
        if m is not None:
            return _scaled(planes, m, w, support)
    return Mode(STABLE, np.zeros(3))


def _one_plane(planes: list[Plane], i: int, r: np.ndarray, tol: float) -> Mode | None:
    n = planes[i].normal
    big_n = float(r @ n)
    t = r - big_n * n
    big_t = float(np.linalg.norm(t))
    if big_n <= tol or big_t <= tol:
        return None
    s = t / big_t
    if any(float(s @ p.normal) > tol for k, p in enumerate(planes) if k != i):
        return None
    return Mode(ONE_PLANE, s, (i,), (big_n,), big_t)


def _two_planes(planes: list[Plane], i: int, j: int, r: np.ndarray, tol: float) -> Mode | None:
    ni, nj = planes[i].normal, planes[j].normal
    s = np.cross(ni, nj)
    if np.linalg.norm(s) <= tol:
        return None
    s /= np.linalg.norm(s)
    if float(s @ r) < 0:
        s = -s
    drive = float(s @ r)
    if drive <= tol or any(float(s @ p.normal) > tol for k, p in enumerate(planes) if k not in (i, j)):
        return None
    # r − (r·s)s = N_i n_i + N_j n_j: the 2 × 2 normal equations of that decomposition.
    c = float(ni @ nj)
    ri, rj = float(r @ ni), float(r @ nj)
    big_ni, big_nj = (ri - c * rj) / (1 - c * c), (rj - c * ri) / (1 - c * c)
    if big_ni <= tol or big_nj <= tol:
        return None
    return Mode(TWO_PLANES, s, (i, j), (big_ni, big_nj), drive)


def _scaled(planes: list[Plane], m: Mode, w: float, support: np.ndarray) -> Mode:
    """Forces back in N with the support's share, then the factor of safety and the critical
    friction angle."""
    normal = tuple(w * x + y for x, y in zip(m.normal_forces, _normal_parts(planes, m, support)))
    normal = tuple(max(0.0, x) for x in normal)
    drive = w * m.driving_force
    held = -float(support @ m.direction)
    friction = sum(f * math.tan(math.radians(planes[k].friction_angle)) for k, f in zip(m.planes, normal))
    cohesion = sum(planes[k].cohesion * planes[k].area for k in m.planes)
    fs = (friction + cohesion + held) / drive
    total = sum(normal)
    need = max(drive - cohesion - held, 0.0)
    critical = math.degrees(math.atan(need / total)) if total > 0 else (0.0 if need == 0 else 90.0)
    return Mode(m.mode, m.direction, m.planes, normal, drive, fs, critical)


def _normal_parts(planes: list[Plane], m: Mode, f: np.ndarray) -> tuple[float, ...]:
    """The normal forces a force ``f`` adds on the sliding planes of mode ``m``."""
    if not np.any(f):
        return tuple(0.0 for _ in m.planes)
    if len(m.planes) == 1:
        return (float(f @ planes[m.planes[0]].normal),)
    ni, nj = planes[m.planes[0]].normal, planes[m.planes[1]].normal
    c, fi, fj = float(ni @ nj), float(f @ ni), float(f @ nj)
    return ((fi - c * fj) / (1 - c * c), (fj - c * fi) / (1 - c * c))


def weight_line_leaves(centroid: np.ndarray, force: np.ndarray, faces: list[np.ndarray]) -> bool:
    """Whether the line of ``force`` through ``centroid`` misses every face polygon (vertices,
    convex, in order) that the block slides on: its weight then acts outside its base, so it may
    topple or rotate, which translational block theory does not see."""
    d = force / np.linalg.norm(force)
    for poly in faces:
        n = np.cross(poly[1] - poly[0], poly[2] - poly[0])
        n /= np.linalg.norm(n)
        denom = float(d @ n)
        if abs(denom) < 1e-12:
            continue
        x = centroid + d * float((poly[0] - centroid) @ n) / denom
        signs = [float(np.cross(b - a, x - a) @ n) for a, b in zip(poly, np.roll(poly, -1, axis=0))]
        scale = 1e-9 * float(np.max(np.linalg.norm(poly - poly[0], axis=1))) ** 2
        if all(s >= -scale for s in signs) or all(s <= scale for s in signs):
            return False
    return True


def hydrostatic_force(polygon: np.ndarray, normal: np.ndarray, table: float, unit_weight: float,
                      up: np.ndarray = np.array([0.0, 0.0, 1.0])) -> np.ndarray:
    """Force on a block of water at pressure γ_w (table − h), h = up·x the height against
    gravity, on its planar face ``polygon`` (vertices in order) with outward ``normal``:
    −n γ_w ∫(table − h)⁺ dA = −n γ_w A_wet (table − h̄), h̄ the height of the wet part's
    centroid (the pressure is linear)."""
    up = np.asarray(up, float) / np.linalg.norm(up)
    wet = _below(np.asarray(polygon, float), up, table)
    if len(wet) < 3:
        return np.zeros(3)
    fan = [(wet[0], wet[i], wet[i + 1]) for i in range(1, len(wet) - 1)]
    integral = sum(0.5 * float(np.linalg.norm(np.cross(b - a, c - a))) * (table - float((a + b + c) @ up) / 3)
                   for a, b, c in fan)
    return -np.asarray(normal, float) * unit_weight * integral


def _below(poly: np.ndarray, up: np.ndarray, table: float) -> np.ndarray:
    """The part of a polygon with up·x ≤ table (Sutherland–Hodgman on one plane)."""
    h = poly @ up - table
    out = []
    for i in range(len(poly)):
        j = (i + 1) % len(poly)
        if h[i] <= 0:
            out.append(poly[i])
        if h[i] * h[j] < 0:
            out.append(poly[i] + h[i] / (h[i] - h[j]) * (poly[j] - poly[i]))
    return np.asarray(out)


def joint_pyramid_digit(outward: np.ndarray, upper: np.ndarray) -> int:
    """Goodman & Shi's joint-pyramid digit of a block bounded by a joint plane: 0 when the block
    lies in the plane's upper half-space (the side ``upper`` points to; for a dipping plane the
    side above it), so that its face's outward normal points against ``upper``; else 1."""
    return 0 if float(outward @ upper) < 0 else 1
