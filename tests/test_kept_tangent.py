"""A block that does not turn keeps its tangent across dynamic steps (`analysis.tangent_keep_angle`,
`time/kept_tangent.rs`): the forces stay exact, so the answer must not move beyond what a tangent
turned by that angle can do — and keeping it far longer must (the test can fail).
"""

from __future__ import annotations

import nmm3d
from conftest import EXAMPLES


def finals(example: str, out, *overrides: str) -> dict:
    r = nmm3d.load(EXAMPLES / example, list(overrides)).run(out=out)
    assert r.completed, r.summary["message"]
    return r.summary["final"]


def largest_difference(a: dict, b: dict) -> float:
    assert a.keys() == b.keys()
    return max(abs(a[k] - b[k]) for k in a)


def test_standing_dominos_keep_their_tangent_while_the_first_falls(tmp_path):
    # Eight dominos, 0.5 s: the first tips over onto the second; the others stand, turning by
    # 1e-9 to 1e-11 rad per step, and keep their tangents.
    run = lambda name, angle: finals(
        "dominos.toml", tmp_path / name, "analysis.duration=0.5", f"analysis.tangent_keep_angle={angle}"
    )
    afresh, kept, stale = run("afresh", 0), run("kept", 1e-6), run("stale", 0.3)
    largest = max(abs(v) for v in afresh.values())
    # Measured: 4.6e-7 of 0.77 (rotations in rad, velocities in m/s).
    assert largest_difference(afresh, kept) < 1e-5 * largest
    # Tangents kept through 0.3 rad of turning: the falling domino's steps stop converging to
    # their end's equilibrium and the answer moves (measured: 0.71).
    assert largest_difference(afresh, stale) > 0.1 * largest


def test_a_slope_at_rest_keeps_every_tangent_to_round_off(tmp_path):
    # The thesis slope at φ = 45°, above every joint's dip: it only settles onto its joints.
    run = lambda name, angle: finals(
        "rock_slope.toml",
        tmp_path / name,
        "joint.rock_joint.friction_angle=45",
        "analysis.duration=0.3",
        f"analysis.tangent_keep_angle={angle}",
    )
    afresh, kept = run("afresh", 0), run("kept", 1e-6)
    # Displacements of about 0.5 mm; measured 1.3e-11 m apart.
    assert largest_difference(afresh, kept) < 1e-9
