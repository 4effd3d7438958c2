"""Joint stiffness in Pa/m on `[[joint]]` (what 3DEC and UDEC take): its validation.

The closed forms — closure W / (k_n A), shear T / (k_s A) — are checked on
`examples/block_on_joint.toml` (`tests/test_examples.py`) and, for the closure on several
covers, in `crates/nmm3d-core/tests/verification_joint_stiffness.rs`.
"""

from __future__ import annotations

import numpy as np
import pytest

import nmm3d
from conftest import EXAMPLES
from nmm3d.result import read_columns

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


def soft_slope_events(tmp_path, carry: bool):
    """Thesis case A (φ = 10°) on joints of 10 MPa/m for 0.5 s: the layer starts to slide and
    its blocks close on each other by centimetres. Returns the energy its contact events made
    (the steps whose contact-event account fell, summed) [J], the largest work of the loads [J]
    and the lifts counted."""
    sets = [
        "joint.rock_joint.friction_angle=10",
        "joint.rock_joint.normal_stiffness=1e7",
        "joint.rock_joint.shear_stiffness=1e7",
        "analysis.duration=0.5",
        f"contact.carry_joint_force={str(carry).lower()}",
    ]
    run = nmm3d.load(EXAMPLES / "rock_slope.toml", sets).run(out=tmp_path / f"carry_{carry}")
    d = read_columns(run.directory / "diagnostics.csv")
    steps = np.diff(d["contact_event_dissipation"], prepend=0.0)
    return -steps[steps < 0].sum(), max(d["external_work"]), run.summary["carried_joint_forces"]


def test_soft_joints_found_again_make_no_energy_when_their_force_is_carried(tmp_path):
    """Springs carrying the total force k_n A g set spring energy at once when a detection finds
    a pair centimetres deep with other points or more area, or a corner arrives deep in a face
    within a step; the contact events book it as negative dissipation (measured: 37 kJ made
    against 0.44 MJ of gravity's work). Carried across (the default) they make 1.2 kJ."""
    made, work, lifts = soft_slope_events(tmp_path, carry=True)
    assert made < 5e-3 * work and lifts > 0, (made, work, lifts)
    made, work, lifts = soft_slope_events(tmp_path, carry=False)
    assert made > 0.05 * work and lifts == 0, (made, work, lifts)
