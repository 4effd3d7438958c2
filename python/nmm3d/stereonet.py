"""Lower-hemisphere, equal-area (Schmidt) stereonets of joint orientations.

Convention: x = East, y = North, z = Up; planes by dip and dip direction (degrees, clockwise
from North). A downward line with trend t and plunge p plots at radius √2·sin((90° − p)/2)
(Lambert azimuthal equal-area, unit primitive circle of radius 1) in direction t.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np


def dip_from_normal(n) -> tuple[float, float]:
    """(dip, dip direction) in degrees of the plane with normal ``n`` (either sense)."""
    n = np.asarray(n, float)
    n = n / np.linalg.norm(n)
    if n[2] < 0:
        n = -n
    dip = math.degrees(math.acos(min(1.0, n[2])))
    dd = math.degrees(math.atan2(n[0], n[1])) % 360.0
    return dip, dd


def project(trend_deg, plunge_deg):
    """Equal-area position (x = East, y = North) of downward lines, unit primitive circle."""
    t, p = np.radians(trend_deg), np.radians(plunge_deg)
    r = np.sqrt(2.0) * np.sin((np.pi / 2 - p) / 2.0)
    return r * np.sin(t), r * np.cos(t)


def great_circle(dip: float, dip_direction: float, n: int = 181):
    """Equal-area trace of a plane: its downward lines from strike to strike."""
    d, a = math.radians(dip), math.radians(dip_direction)
    strike = np.array([math.sin(a - math.pi / 2), math.cos(a - math.pi / 2), 0.0])
    down = np.array([math.cos(d) * math.sin(a), math.cos(d) * math.cos(a), -math.sin(d)])
    s = np.linspace(0.0, np.pi, n)
    v = np.outer(np.cos(s), strike) + np.outer(np.sin(s), down)
    trend = np.degrees(np.arctan2(v[:, 0], v[:, 1]))
    plunge = np.degrees(np.arcsin(np.clip(-v[:, 2], -1.0, 1.0)))
    return project(trend, plunge)


def pole(dip: float, dip_direction: float):
    """Equal-area position of a plane's pole (the downward normal)."""
    return project((dip_direction + 180.0) % 360.0, 90.0 - dip)


def orientations(scenario: dict[str, Any]) -> list[tuple[str, float, float]]:
    """(label, dip, dip direction) of every joint set and joint plane of a scenario dictionary."""
    out = []
    for k, js in enumerate(scenario.get("joint_set", [])):
        out.append((f"set {k + 1}: {js['dip']:.0f}/{js['dip_direction']:03.0f}", js["dip"], js["dip_direction"]))
    for k, jp in enumerate(scenario.get("joint_plane", [])):
        if jp.get("normal") is not None:
            dip, dd = dip_from_normal(jp["normal"])
        else:
            dip, dd = jp["dip"], jp["dip_direction"]
        out.append((f"joint {k + 1}: {dip:.0f}/{dd:03.0f}", dip, dd))
    return out


def draw_joints(ax, scenario: dict[str, Any], title: str = "") -> None:
    """Primitive circle, great circles and poles of the scenario's joints on ``ax``."""
    t = np.linspace(0, 2 * np.pi, 361)
    ax.plot(np.cos(t), np.sin(t), color="black", lw=1)
    ax.plot([0], [0], "+", color="black")
    for name, x, y in (("N", 0, 1.06), ("E", 1.06, 0), ("S", 0, -1.1), ("W", -1.1, 0)):
        ax.text(x, y, name, ha="center", va="center")
    for i, (label, dip, dd) in enumerate(orientations(scenario)):
        color = f"C{i % 10}"
        x, y = great_circle(dip, dd)
        ax.plot(x, y, color=color, label=label)
        px, py = pole(dip, dd)
        ax.plot(px, py, "o", color=color, ms=5)
    ax.set_aspect("equal")
    ax.set_xlim(-1.15, 1.15)
    ax.set_ylim(-1.15, 1.15)
    ax.axis("off")
    ax.set_title(title or "lower hemisphere, equal area", fontsize=10)


def plot_stereonet(scenario: dict[str, Any], path: str | Path, title: str = "") -> Path:
    """Draw great circles and poles of the scenario's joints to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    draw_joints(ax, scenario, title)
    if orientations(scenario):
        ax.legend(loc="lower left", fontsize=7, bbox_to_anchor=(-0.05, -0.08))
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return Path(path)
