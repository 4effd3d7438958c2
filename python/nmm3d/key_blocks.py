"""Key blocks of a cut rock mass: which blocks on an excavation or slope can come out, how, and
with what factor of safety (``nmm3d keyblocks``, :func:`keyblocks`).

The blocks are the ones ``nmm3d blocks`` cuts. A face is *held* when rock lies beyond it: another
block's face touches it (joint faces, a layer on its bedrock), or it lies on the model's outer
boundary — a side of its bounding box where the rock mass goes on (every side but those
``[keyblocks] free_sides`` names; by default the top is free ground unless the scenario has an
excavation). Every other face is *free* (excavation faces, the ground and slope surface). Each block with a free
face that is not fixed is analysed by block theory (:mod:`nmm3d.block_theory`) under its weight,
with the friction angle and cohesion of the joint on each plane (the joint that contact would
use), the pseudo-static seismic force of ``[seismic] coefficient`` and the water pressure below
``[water] table`` (on the held faces, and on the free ones unless they are drained): the normal
forces are then effective; and the passive support of its bolts (``[[bolt]]`` with a yield
force, head in the block, anchor beyond). Not included: in-situ stress.
"""

from __future__ import annotations

import csv
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

import numpy as np

from nmm3d import _core
from nmm3d.block_theory import FALLING, ONE_PLANE, TWO_PLANES, Mode, Plane, failure_mode, joint_pyramid_digit
from nmm3d.block_theory import hydrostatic_force, weight_line_leaves

#: A face touched by other blocks over more than this fraction of its area is held by them;
#: a face with more than this fraction untouched exposes a free surface.
TOUCH_FRACTION = 1e-3
#: Faces within this fraction of the model's diagonal of its bounding box are on its boundary.
BOUNDARY_RATIO = 1e-6
#: Outward normals within this angle [rad] are one plane of a block.
SAME_PLANE_ANGLE = 1e-4

#: Sides of the bounding box, as ``[keyblocks] free_sides`` names them.
SIDES = ("-x", "+x", "-y", "+y", "-z", "+z")

COLUMNS = ["id", "body", "joint_pyramid", "removable", "mode", "factor_of_safety", "critical_friction_angle",
           "volume", "weight", "centroid_x", "centroid_y", "centroid_z", "trend", "plunge", "sliding_planes",
           "free_area", "rotation_warning"]


@dataclass
class KeyBlock:
    """One block with a free face, and its block-theory verdict."""

    id: int
    body: str
    volume: float           #: [m³]
    weight: float           #: [N]
    centroid: np.ndarray    #: [m]
    #: one digit per joint feature (sets, then planes): 0 the block lies above its plane, 1 below,
    #: 2 between two planes of the set, x the feature does not bound it (Goodman & Shi 1985)
    joint_pyramid: str
    free_area: float        #: [m²]
    planes: list[Plane]
    mode: Mode
    rotation_warning: bool  #: its weight line misses its sliding faces (it may topple)
    sliding_faces: list[np.ndarray] = field(default_factory=list, repr=False)

    @property
    def removable(self) -> bool:
        return self.mode.mode != "not_removable"

    @property
    def is_key_block(self) -> bool:
        """Removable and moving under its weight alone when frictionless (falls or slides)."""
        return self.mode.mode in (FALLING, ONE_PLANE, TWO_PLANES)

    def trend_plunge(self) -> tuple[float, float]:
        """Of the movement direction [deg]; plunge negative upward; NaN without movement."""
        d = self.mode.direction
        if not np.any(d):
            return math.nan, math.nan
        return math.degrees(math.atan2(d[0], d[1])) % 360.0, math.degrees(math.asin(max(-1.0, min(1.0, -d[2]))))

    def row(self) -> dict[str, Any]:
        trend, plunge = self.trend_plunge()
        m = self.mode
        return {
            "id": self.id, "body": self.body, "joint_pyramid": self.joint_pyramid, "removable": self.removable,
            "mode": m.mode, "factor_of_safety": m.factor_of_safety, "critical_friction_angle": m.critical_friction_angle,
            "volume": self.volume, "weight": self.weight, "centroid_x": self.centroid[0],
            "centroid_y": self.centroid[1], "centroid_z": self.centroid[2], "trend": trend, "plunge": plunge,
            "sliding_planes": " + ".join(self.planes[k].label for k in m.planes), "free_area": self.free_area,
            "rotation_warning": self.rotation_warning,
        }


@dataclass
class KeyBlocks:
    """The analysed blocks of a scenario, with the surfaces for pictures."""

    blocks: list[KeyBlock]
    surfaces: dict[str, Any] = field(repr=False)
    scenario: dict[str, Any] = field(repr=False)

    def key_blocks(self) -> list[KeyBlock]:
        """The blocks that fall or slide, most dangerous first (lowest factor of safety)."""
        return sorted((b for b in self.blocks if b.is_key_block), key=lambda b: (b.mode.factor_of_safety, b.id))

    def table(self) -> dict[str, np.ndarray]:
        """The columns of ``keyblocks.csv`` as arrays."""
        rows = [b.row() for b in self.blocks]
        return {c: np.asarray([r[c] for r in rows]) for c in COLUMNS}

    def write(self, out: str | os.PathLike[str]) -> list[Path]:
        """Write ``keyblocks.csv``, ``keyblocks.png`` (3-D view) and ``keyblocks_stereonet.png``."""
        from nmm3d.key_block_plots import plot_blocks, plot_key_stereonet

        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        path = out / "keyblocks.csv"
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, COLUMNS)
            w.writeheader()
            for b in self.blocks:
                w.writerow({k: _text(v) for k, v in b.row().items()})
        return [path, plot_blocks(self, out / "keyblocks.png"), plot_key_stereonet(self, out / "keyblocks_stereonet.png")]


def keyblocks(scenario: Any, out: str | os.PathLike[str] | None = None, overrides: Iterable[str] = ()) -> KeyBlocks:
    """Key-block analysis of a scenario (a :class:`nmm3d.Scenario` or a TOML path); writes the
    outputs to ``out`` when given."""
    from nmm3d.scenario import Scenario, load

    s = scenario if isinstance(scenario, Scenario) else load(scenario, overrides)
    d = s.to_dict()
    surfaces = json.loads(_core.block_surfaces_json(s._json, s.label))
    result = KeyBlocks(_analyse(d, surfaces), surfaces, d)
    if out is not None:
        result.write(out)
    return result


def _analyse(d: dict[str, Any], surfaces: dict[str, Any]) -> list[KeyBlock]:
    if not surfaces["blocks"]:
        return []
    g = np.asarray(d["analysis"]["gravity"], float)
    # The pseudo-static seismic force k m |g| joins the weight (Hoek & Bray; Swedge, Unwedge).
    load = g + np.asarray(d.get("seismic", {}).get("coefficient", [0.0, 0.0, 0.0]), float) * np.linalg.norm(g)
    joints = {j["name"]: j for j in d.get("joint", [])}
    labels = [f"set {k + 1}" for k, _ in enumerate(d.get("joint_set", []))]
    labels += [f"joint {k + 1}" for k, _ in enumerate(d.get("joint_plane", []))]
    by_block: dict[int, list[dict[str, Any]]] = {}
    for f in surfaces["faces"]:
        by_block.setdefault(f["block"], []).append(f)
    bounds = dict(surfaces["bounds"])
    bounds["tol"] = BOUNDARY_RATIO * float(np.linalg.norm(np.subtract(bounds["max"], bounds["min"])))
    bounds["held"] = [s for s in SIDES if s not in free_sides(d)]
    names = [b["body"] for b in surfaces["blocks"]]
    out = []
    for k, b in enumerate(surfaces["blocks"]):
        faces = by_block.get(k, [])
        held = [f for f in faces if _held(f, bounds)]
        free = sum(f["area"] - f["touching"] for f in faces if not _on_boundary(f, bounds))
        if b["fixed"] or free <= TOUCH_FRACTION * sum(f["area"] for f in faces):
            continue
        labelled = [dict(f, label=_label(f, labels, names)) for f in held]
        water = _water_force(d, faces if _submerged(d) else held, float(np.linalg.norm(g)))
        support = _support(d, surfaces.get("bolts", []), k)
        out.append(_key_block(k, b, labelled, free, (g, load, water, support), joints, surfaces["features"]))
    return out


def free_sides(d: dict[str, Any]) -> list[str]:
    """The bounding-box sides that are free surfaces (``[keyblocks] free_sides`` or its default)."""
    given = d.get("keyblocks", {}).get("free_sides")
    if given is not None:
        return list(given)
    return [] if d.get("excavation") else ["+z"]


def _key_block(k, b, held, free, accelerations, joints, features) -> KeyBlock:
    """``accelerations``: gravity, the acceleration whose body force acts (gravity and the
    pseudo-static seismic one), the water's force on the block and its bolts' support [N]."""
    g, load, water, support = accelerations
    planes, polygons = _planes(held, joints)
    weight = b["density"] * b["volume"] * float(np.linalg.norm(g))
    force = b["density"] * b["volume"] * load + water
    mode = failure_mode(planes, force, support)
    centroid = np.asarray(b["centroid"], float)
    sliding = [p for i in mode.planes for p in polygons[i]]
    warn = bool(sliding) and weight_line_leaves(centroid, force, sliding)
    return KeyBlock(k, b["body"], b["volume"], weight, centroid, _pyramid(held, features), free, planes, mode,
                    warn, sliding)


def _submerged(d: dict[str, Any]) -> bool:
    return d.get("water", {}).get("free_faces", "submerged") == "submerged"


def _water_force(d: dict[str, Any], faces: list[dict[str, Any]], g: float) -> np.ndarray:
    """``g``: |gravity| [m/s²] (no gravity: no water pressure either)."""
    """The water's push on a block: hydrostatic pressure below ``[water] table`` on ``faces``
    (every face, or the held ones when free faces are drained)."""
    w = d.get("water")
    if not w or g == 0.0:
        return np.zeros(3)
    gravity = np.asarray(d["analysis"]["gravity"], float)
    unit_weight, up = w.get("density", 1000.0) * g, -gravity / g
    return sum((hydrostatic_force(np.asarray(f["vertices"], float), np.asarray(f["normal"], float), w["table"],
                                  unit_weight, up) for f in faces), np.zeros(3))


def _support(d: dict[str, Any], bolts: list[dict[str, Any]], block: int) -> np.ndarray:
    """The passive support on ``block`` [N]: an anchored bolt whose head is in it and anchor in
    another block pulls towards its anchor with its yield force; a grouted bolt, at each joint
    of the block it crosses, pulls it towards the rock across with that joint's axial capacity
    (the steel's yield force or the pull-out of the shorter bonded side, as in a run). Bolts
    without a finite capacity are not counted."""
    spec = {b["name"]: b for b in d.get("bolt", [])}
    total = np.zeros(3)
    for b in bolts:
        s = spec[b["name"]]
        axis = np.subtract(s["anchor"], s["head"])
        axis = axis / np.linalg.norm(axis)
        if s.get("grouted"):
            for c in b.get("crossings", []):
                if c["capacity"] is not None and block in (c["near_block"], c["far_block"]) \
                        and c["near_block"] != c["far_block"]:
                    total += c["capacity"] * (axis if c["near_block"] == block else -axis)
        elif b["head_block"] == block and b["anchor_block"] not in (None, block) and s.get("yield_force"):
            total += s["yield_force"] * axis
    return total


def _planes(held, joints) -> tuple[list[Plane], list[list[np.ndarray]]]:
    """Held faces grouped into planes: one outward normal and one joint each."""
    planes: list[Plane] = []
    polygons: list[list[np.ndarray]] = []
    for f in held:
        n = np.asarray(f["normal"], float)
        area = f["touching"] if f["touching"] > TOUCH_FRACTION * f["area"] else f["area"]
        j = joints.get(f["joint"], {})
        for i, p in enumerate(planes):
            if float(n @ p.normal) > math.cos(SAME_PLANE_ANGLE) and p.label == f["label"]:
                planes[i] = Plane(p.normal, p.area + area, p.friction_angle, p.cohesion, p.label)
                polygons[i].append(np.asarray(f["vertices"], float))
                break
        else:
            planes.append(Plane(n, area, j.get("friction_angle", 0.0), j.get("cohesion", 0.0), f["label"]))
            polygons.append([np.asarray(f["vertices"], float)])
    return planes, polygons


def _label(f: dict[str, Any], labels: list[str], names: list[str]) -> str:
    """What a plane is, for the report: "set 2", "joint 1", "on bedrock", "model boundary"."""
    if f["kind"] == "joint":
        return labels[f["index"]] if f["index"] < len(labels) else f"joint feature {f['index'] + 1}"
    if f["partner"] is not None and f["touching"] > TOUCH_FRACTION * f["area"]:
        return f"on {names[f['partner']]}"
    return "model boundary"


def _pyramid(held, features) -> str:
    digits = ["x"] * len(features)
    for f in held:
        if f["kind"] == "joint":
            up = np.asarray(features[f["index"]]["normal"], float)
            up = up if up[2] >= 0 else -up
            digit = str(joint_pyramid_digit(np.asarray(f["normal"], float), up))
            digits[f["index"]] = digit if digits[f["index"]] in ("x", digit) else "2"
    return "".join(digits)


def _held(f: dict[str, Any], bounds: dict[str, Any]) -> bool:
    return f["touching"] > TOUCH_FRACTION * f["area"] or _on_boundary(f, bounds)


def _on_boundary(f: dict[str, Any], bounds: dict[str, Any]) -> bool:
    """A body face on a held side of the model's bounding box (rock goes on beyond it)."""
    if f["kind"] != "body":
        return False
    n, v = np.asarray(f["normal"], float), np.asarray(f["vertices"], float)
    for side in bounds["held"]:
        axis, sign = "xyz".index(side[1]), (1.0 if side[0] == "+" else -1.0)
        at = bounds["max" if sign > 0 else "min"][axis]
        if n[axis] * sign > math.cos(SAME_PLANE_ANGLE) and np.all(np.abs(v[:, axis] - at) <= bounds["tol"]):
            return True
    return False


def _text(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else repr(float(v))
    return str(v)
