"""Key-block analysis (block theory) on cut rock masses, against closed forms.

Goodman & Shi (1985), Block Theory and its Application to Rock Engineering: with joint sets
30/090, 60/045 and 20/330, JP 101 is the removable joint pyramid of a horizontal tunnel roof and
JP 100 that of the south wall of a tunnel along x. The blocks' volumes are computed here from
the four bounding planes alone; the two-plane wedge against the vector method (Hoek & Bray).
"""

from __future__ import annotations

import csv
import itertools
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import nmm3d
from nmm3d.block_theory import FALLING, NOT_REMOVABLE, ONE_PLANE, STABLE, TWO_PLANES, Plane, can_move, failure_mode
from nmm3d.wedge import plane_normal, wedge

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
GOODMAN = EXAMPLES / "goodman_tunnel.toml"
SETS = [(30.0, 90.0), (60.0, 45.0), (20.0, 330.0)]


def apexes() -> tuple[np.ndarray, np.ndarray]:
    """The points the example's roof and wall joints pass through (three joints each)."""
    planes = nmm3d.load(GOODMAN).to_dict()["joint_plane"]
    assert [(p["dip"], p["dip_direction"]) for p in planes] == SETS + SETS
    return np.asarray(planes[0]["point"]), np.asarray(planes[3]["point"])


def tetrahedron_volume(apex, face_normal, face_offset) -> float:
    """Volume between the three joints through ``apex`` and the plane n·x = offset."""
    normals = [plane_normal(*s) for s in SETS]
    base = [np.linalg.solve(np.array([normals[i], normals[j], face_normal]),
                            [normals[i] @ apex, normals[j] @ apex, face_offset])
            for i, j in itertools.combinations(range(3), 2)]
    return abs(np.linalg.det(np.array(base) - np.asarray(apex))) / 6.0


@pytest.fixture(scope="module")
def goodman() -> nmm3d.KeyBlocks:
    return nmm3d.keyblocks(GOODMAN)


def the_block_with(result: nmm3d.KeyBlocks, jp: str) -> list:
    """Blocks of joint pyramid ``jp`` cut off by joints alone (not by the model's box)."""
    return [b for b in result.blocks
            if b.joint_pyramid == jp and all(p.label.startswith("joint") for p in b.planes)]


def test_goodman_roof_key_block_is_jp_101_and_slides_out_whole(goodman):
    roof, _ = apexes()
    [block] = the_block_with(goodman, "101xxx")
    assert block.removable and block.is_key_block
    assert block.volume == pytest.approx(tetrahedron_volume(roof, np.array([0.0, 0.0, 1.0]), 0.0), rel=1e-9)
    # It lies above joint 2 (60°) and slides down it: FS = tan 30° / tan 60°.
    assert block.mode.mode == ONE_PLANE and [block.planes[k].label for k in block.mode.planes] == ["joint 2"]
    assert block.mode.factor_of_safety == pytest.approx(math.tan(math.radians(30)) / math.tan(math.radians(60)))


def test_goodman_south_wall_key_block_is_jp_100(goodman):
    _, wall = apexes()
    [block] = the_block_with(goodman, "xxx100")
    assert block.removable and block.is_key_block
    assert block.volume == pytest.approx(tetrahedron_volume(wall, np.array([0.0, 1.0, 0.0]), -3.0), rel=1e-9)


@pytest.mark.parametrize("free_face, outward, removable", [
    ("roof", [0.0, 0.0, -1.0], "101"), ("south wall", [0.0, 1.0, 0.0], "100"), ("floor", [0.0, 0.0, 1.0], "010")])
def test_goodman_joint_pyramids_by_the_removability_theorem(free_face, outward, removable):
    """Goodman & Shi's theorem: a JP is removable through a free plane iff the JP cone cut by the
    rock side of that plane holds no direction (the block is finite and can leave). Of the eight
    JPs of the three sets exactly one is removable through each face."""
    up = [plane_normal(*s) for s in SETS]
    found = []
    for code in itertools.product("01", repeat=3):
        # The JP cone cut by the rock's side of the free face: x·n ≤ 0 for every n pointing out
        # of the block (down for a block above its plane, digit 0; the free face's outward one).
        normals = [(-u if c == "0" else u) for u, c in zip(up, code)] + [np.asarray(outward)]
        if can_move(normals) is None:
            found.append("".join(code))
    assert found == [removable], free_face


def test_goodman_tunnel_has_no_other_key_block(goodman):
    # Every other block is locked in by joints and the rock beyond, or rests on the floor.
    assert sorted(b.joint_pyramid for b in goodman.key_blocks()) == ["101xxx", "xxx100"]
    assert all(b.mode.mode in (NOT_REMOVABLE, STABLE) for b in goodman.blocks if not b.is_key_block)


def test_two_plane_wedge_matches_the_vector_method():
    r = nmm3d.keyblocks(EXAMPLES / "tetrahedral_wedge.toml")
    [b] = r.key_blocks()
    ref = wedge((50.0, 130.0), (50.0, 230.0), 20.0)
    assert b.mode.mode == TWO_PLANES
    assert b.mode.factor_of_safety == pytest.approx(ref.factor_of_safety, abs=1e-6)
    trend, plunge = b.trend_plunge()
    assert (trend, plunge) == pytest.approx((ref.trend, ref.plunge), abs=1e-6)
    critical = math.degrees(math.atan(math.tan(math.radians(20.0)) / ref.factor_of_safety))
    assert b.mode.critical_friction_angle == pytest.approx(critical, abs=1e-6)


def test_two_plane_wedge_with_cohesion_matches_the_vector_method():
    cohesion = 5.0e3
    r = nmm3d.keyblocks(nmm3d.load(EXAMPLES / "tetrahedral_wedge.toml", [f"joint.j.cohesion={cohesion}"]))
    [b] = r.key_blocks()
    # The wedge's faces from its four planes (x = East, y = North, z = Up).
    planes = np.array([[-0.586824088833, 0.492403876506, -0.642787609687, 0.0],
                       [0.586824088833, 0.492403876506, -0.642787609687, 0.0],
                       [0.0, 0.0, 1.0, 0.0], [0.0, -1.0, 0.0, 2.0]])
    corners = {tri: np.linalg.solve(planes[list(tri), :3], planes[list(tri), 3])
               for tri in itertools.combinations(range(4), 3)}
    def area(k):
        p = [v for tri, v in corners.items() if k in tri]
        return 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
    ref = wedge((50.0, 130.0), (50.0, 230.0), 20.0, weight=b.weight,
                cohesion_force_a=cohesion * area(0), cohesion_force_b=cohesion * area(1))
    assert b.mode.factor_of_safety == pytest.approx(ref.factor_of_safety, abs=1e-6)
    # FS = 1 at tan φc = (T − Σ c A) / Σ N.
    t, n = b.mode.driving_force, sum(b.mode.normal_forces)
    c = cohesion * (area(0) + area(1))
    assert b.mode.critical_friction_angle == pytest.approx(math.degrees(math.atan((t - c) / n)), abs=1e-6)


def test_single_plane_block_on_an_incline():
    r = nmm3d.keyblocks(EXAMPLES / "incline.toml")
    [b] = r.key_blocks()
    assert b.mode.mode == ONE_PLANE
    assert b.mode.factor_of_safety == pytest.approx(math.tan(math.radians(24.0)) / math.tan(math.radians(30.0)),
                                                    abs=1e-9)
    assert b.mode.critical_friction_angle == pytest.approx(30.0, abs=1e-9)
    assert b.trend_plunge() == pytest.approx((90.0, 30.0), abs=1e-9)
    assert b.weight == pytest.approx(2500.0 * 1.0 * 10.0, rel=1e-9)
    assert not b.rotation_warning


def test_falling_roof_wedge_when_its_base_is_the_free_face():
    r = nmm3d.keyblocks(nmm3d.load(EXAMPLES / "roof_wedge.toml", ['keyblocks.free_sides=["-z"]']))
    [b] = r.key_blocks()
    assert b.mode.mode == FALLING and b.mode.factor_of_safety == 0.0
    assert b.mode.critical_friction_angle == 90.0
    # Held on the model's bottom (the default: rock goes on below), it has no free face at all.
    assert nmm3d.keyblocks(EXAMPLES / "roof_wedge.toml").blocks == []


def test_a_tall_block_on_a_gentle_plane_is_flagged_for_toppling():
    """A 1 × 1 × 6 m column on a 30° plane: its weight line leaves its base (tan 30° > 1/6)."""
    d = nmm3d.load(EXAMPLES / "incline.toml").to_dict()
    d["body"][1]["shape"]["convex"]["planes"][1][3] = 6.0
    [b] = nmm3d.keyblocks(nmm3d.Scenario.from_dict(d)).key_blocks()
    assert b.mode.mode == ONE_PLANE and b.rotation_warning
    assert not nmm3d.keyblocks(EXAMPLES / "incline.toml").key_blocks()[0].rotation_warning


def test_modes_of_a_block_on_planes_by_hand():
    up = np.array([0.0, 0.0, 1.0])
    down = np.array([0.0, 0.0, -9.81])
    floor = Plane(-up, 1.0, 30.0)
    # On a level floor: removable (upward) but stable under its weight.
    assert failure_mode([floor], down).mode == STABLE
    # Boxed in on all six sides: not removable.
    box = [Plane(s * e, 1.0, 30.0) for e in np.eye(3) for s in (1.0, -1.0)]
    assert can_move([p.normal for p in box]) is None
    assert failure_mode(box, down).mode == NOT_REMOVABLE
    # Hanging under a ceiling: falls.
    assert failure_mode([Plane(up, 1.0, 30.0)], down).mode == FALLING


def test_cli_writes_the_table_and_pictures(tmp_path):
    out = tmp_path / "kb"
    p = subprocess.run([sys.executable, "-m", "nmm3d", "keyblocks", str(EXAMPLES / "two_wedges.toml"), "--out",
                        str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "2 key blocks" in p.stdout
    rows = list(csv.DictReader(open(out / "keyblocks.csv")))
    for column in ("id", "removable", "mode", "factor_of_safety", "critical_friction_angle", "volume",
                   "centroid_x", "centroid_y", "centroid_z", "trend", "plunge"):
        assert column in rows[0]
    assert {r["mode"] for r in rows} == {TWO_PLANES}
    for name in ("keyblocks.png", "keyblocks_stereonet.png"):
        assert (out / name).stat().st_size > 10_000


def test_cli_refuses_a_bad_free_side(tmp_path):
    p = subprocess.run([sys.executable, "-m", "nmm3d", "keyblocks", str(EXAMPLES / "roof_wedge.toml"), "--out",
                        str(tmp_path / "kb"), "--set", 'keyblocks.free_sides=["up"]'],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2
    assert "keyblocks.free_sides" in p.stderr


def test_nothing_left_gives_an_empty_table(tmp_path):
    d = {"material": [{"name": "r", "density": 2500.0, "young": 1e9, "poisson": 0.2}],
         "body": [{"name": "b", "material": "r", "shape": {"box": {"min": [0, 0, 0], "max": [1, 1, 1]}}}],
         "excavation": [{"shape": {"box": {"min": [-1, -1, -1], "max": [2, 2, 2]}}}]}
    kb = nmm3d.keyblocks(nmm3d.Scenario.from_dict(d), out=tmp_path / "kb")
    assert kb.blocks == [] and (tmp_path / "kb" / "keyblocks.csv").read_text().startswith("id,")
    assert (tmp_path / "kb" / "keyblocks.png").exists()
