"""Joint stiffness in Pa/m on `[[joint]]` (what 3DEC and UDEC take): validation, and the response
of a stuck joint against its closed forms at the centre of the block's base (a material point
1 mm above it: the tilt from the moment of T does not move it).

The closure w = W / (k_n A) on several covers is verified in Rust
(`crates/nmm3d-core/tests/verification_joint_stiffness.rs`); here the shear u = T / (k_s A).
"""

from __future__ import annotations

import pytest

import nmm3d

CUBE = """
[analysis]
duration = 0.002
dt = 0.001
max_displacement_ratio = 0.01
gravity = [1.0, 0.0, -10.0]
output_interval = 0.0
initial_equilibrium = true

[cover]
pattern = "hex8"
size = 0.5

[[material]]
name = "rock"
density = 2500.0
young = 1.0e11
poisson = 0.0

[[joint]]
name = "j"
friction_angle = 45.0
normal_stiffness = 1.0e8
shear_stiffness = 5.0e7

[[body]]
name = "slab"
material = "rock"
fixed = true
shape = { box = { min = [-1.0, -1.0, -0.5], max = [1.0, 1.0, 0.0] } }

[[body]]
name = "cube"
material = "rock"
joint = "j"
shape = { box = { min = [-0.5, -0.5, 0.0], max = [0.5, 0.5, 1.0] } }

[[monitor]]
name = "base"
select = { point = [0.0, 0.0, 0.001] }
quantities = ["displacement"]
location = "point"
"""


def run(tmp_path, overrides=()):
    path = tmp_path / "cube.toml"
    path.write_text(CUBE)
    return nmm3d.load(path, overrides).run(out=tmp_path / "out")


def test_the_joint_stiffness_sets_the_closure(tmp_path):
    result = run(tmp_path)
    assert result.summary["initial_equilibrium"]["unbalanced_force_ratio"] <= 1e-7
    assert -result.summary["final"]["base.displacement.z"] == pytest.approx(25_000.0 / 1.0e8, rel=0.002)


def test_a_stuck_joint_shears_by_the_force_over_its_shear_stiffness(tmp_path):
    result = run(tmp_path)
    assert result.summary["final"]["base.displacement.x"] == pytest.approx(2_500.0 / 5.0e7, rel=0.02)


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("joint.j.normal_stiffness=-1", "joint.j.normal_stiffness"),
        ("joint.j.shear_stiffness=0", "joint.j.shear_stiffness"),
    ],
)
def test_a_wrong_stiffness_is_named_with_its_key(tmp_path, override, key):
    path = tmp_path / "cube.toml"
    path.write_text(CUBE)
    with pytest.raises(nmm3d.ScenarioError, match=key):
        nmm3d.load(path, [override])


def test_a_shear_stiffness_needs_a_normal_one(tmp_path):
    path = tmp_path / "cube.toml"
    path.write_text(CUBE.replace("normal_stiffness = 1.0e8\n", ""))
    with pytest.raises(nmm3d.ScenarioError, match="joint.j.shear_stiffness"):
        nmm3d.load(path)
