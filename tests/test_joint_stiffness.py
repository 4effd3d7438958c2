"""Joint stiffness in Pa/m on `[[joint]]` (what 3DEC and UDEC take): its validation.

The closed forms — closure W / (k_n A), shear T / (k_s A) — are checked on
`examples/block_on_joint.toml` (`tests/test_examples.py`) and, for the closure on several
covers, in `crates/nmm3d-core/tests/verification_joint_stiffness.rs`.
"""

from __future__ import annotations

import pytest

import nmm3d
from conftest import EXAMPLES

EXAMPLE = EXAMPLES / "block_on_joint.toml"


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("joint.j.normal_stiffness=-1", "joint.j.normal_stiffness"),
        ("joint.j.shear_stiffness=0", "joint.j.shear_stiffness"),
    ],
)
def test_a_wrong_stiffness_is_named_with_its_key(override, key):
    with pytest.raises(nmm3d.ScenarioError, match=key):
        nmm3d.load(EXAMPLE, [override])


def test_a_shear_stiffness_needs_a_normal_one(tmp_path):
    path = tmp_path / "no_normal.toml"
    path.write_text(EXAMPLE.read_text().replace("normal_stiffness = 1.0e8\n", ""))
    with pytest.raises(nmm3d.ScenarioError, match="joint.j.shear_stiffness"):
        nmm3d.load(path)
