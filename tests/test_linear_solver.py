"""The linear solvers: multigrid-preconditioned CG (``linear_solver = "amg"``) against the direct
Cholesky on the same static block, the automatic choice, and the keys' validation."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

import nmm3d

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from _case import block_scenario  # noqa: E402


def block(n: int, **analysis) -> dict:
    """The benchmark block (n³ cells of 1 m, 6 n³ MEs, base held, own weight) to equilibrium."""
    s = block_scenario(n)
    s["analysis"].update({"duration": 1.0e6, "max_steps": 50, **analysis})
    return s


def two_blocks(n: int, **analysis) -> dict:
    """The block cut in two by a horizontal joint at mid-height: contact springs between them."""
    s = block(n, **analysis)
    s["joint"] = [{"name": "bedding", "friction_angle": 30.0}]
    s["joint_plane"] = [{"point": [n / 2, n / 2, n / 2], "dip": 0.0, "dip_direction": 0.0, "joint": "bedding"}]
    return s


def run(scenario: dict, tmp_path, name: str) -> dict:
    return nmm3d.Scenario.from_dict(scenario).run(out=tmp_path / name).summary


def test_multigrid_pcg_reaches_the_direct_solvers_equilibrium(tmp_path):
    direct = run(block(10, linear_solver="direct"), tmp_path, "direct")
    amg = run(block(10, linear_solver="amg", amg_tolerance=1e-10), tmp_path, "amg")
    assert (direct["linear_solver"], amg["linear_solver"]) == ("direct", "amg")
    assert direct["multigrid_iterations"] == 0 < amg["multigrid_iterations"]
    # Mesh-independent convergence: a few tens of iterations per solve, not CG's hundreds.
    assert amg["multigrid_iterations"] <= 40 * amg["steps"]
    assert "equilibrium reached" in amg["message"]
    uz, want = amg["final"]["top.displacement.z"], direct["final"]["top.displacement.z"]
    assert want < 0 and abs(uz - want) <= 1e-8 * abs(want)


def test_auto_takes_multigrid_for_a_large_single_block_and_the_direct_solver_otherwise(tmp_path):
    assert run(block(6, amg_min_equations=500), tmp_path, "large")["linear_solver"] == "amg"
    assert run(block(6), tmp_path, "small")["linear_solver"] == "direct"
    # Two blocks: contact springs, which multigrid handles poorly — direct whatever the size.
    summary = run(two_blocks(6, amg_min_equations=500), tmp_path, "two")
    assert (summary["blocks"], summary["linear_solver"]) == (2, "direct")


def test_the_smallest_ordering_keeps_the_smaller_factor_and_solves_as_that_ordering(tmp_path):
    """`ordering = "smallest"` analyses AMD and nested dissection and keeps the smaller factor
    (docs/ordering.md): the same factor, and the same answer, as the ordering it picked."""
    got = {o: run(two_blocks(6, max_steps=3, ordering=o), tmp_path, o) for o in ("amd", "nested_dissection", "smallest")}
    size = {o: s["factor_nonzeros"] for o, s in got.items()}
    assert size["amd"] != size["nested_dissection"], size
    picked = min(("amd", "nested_dissection"), key=lambda o: size[o])
    assert size["smallest"] == size[picked]
    assert got["smallest"]["final"] == got[picked]["final"]


@pytest.mark.parametrize("key, value", [("amg_tolerance", 0.0), ("amg_tolerance", 1.5), ("amg_newton_tolerance", -1e-3),
                                        ("linear_solver", "lu")])
def test_bad_solver_keys_are_refused_by_name(key, value):
    with pytest.raises(nmm3d.ScenarioError, match=key):
        nmm3d.Scenario.from_dict(block(4, **{key: value}))


def test_the_flagship_cantilever_on_multigrid_matches_the_direct_solve(tmp_path):
    """hex8 covers, a clamped end and a tip traction: the same tip deflection to 1e-6."""
    from conftest import EXAMPLES

    tips = {}
    for solver in ("direct", "amg"):
        r = nmm3d.load(EXAMPLES / "cantilever.toml", [f'analysis.linear_solver="{solver}"']).run(out=tmp_path / solver)
        assert r.completed and r.summary["linear_solver"] == solver
        tips[solver] = r.summary["final"]["tip.displacement.z"]
    assert tips["amg"] == pytest.approx(tips["direct"], rel=1e-6)


def test_a_single_static_step_is_solved_to_the_multigrid_tolerance(tmp_path):
    """Newton corrections are solved to `amg_newton_tolerance` (1e-3), the first one too — but
    with `max_steps = 1` no iteration follows to correct it: that one solve goes to
    `amg_tolerance` and matches the direct solve of the same step."""
    direct = run(block(10, linear_solver="direct", max_steps=1), tmp_path, "direct")
    amg = run(block(10, linear_solver="amg", max_steps=1), tmp_path, "amg")
    loose = run(block(10, linear_solver="amg", max_steps=1, amg_tolerance=1e-3), tmp_path, "loose")
    want = direct["final"]["top.displacement.z"]
    error = {k: abs(s["final"]["top.displacement.z"] - want) / abs(want) for k, s in [("amg", amg), ("loose", loose)]}
    assert direct["steps"] == amg["steps"] == 1
    assert error["amg"] <= 1e-7 < error["loose"], error


def test_a_compact_block_keeps_its_first_matrix_and_a_slender_beam_assembles_its_tangent(tmp_path):
    """Modified Newton (docs/theory/solver.md): the block's iterations cut the unbalanced force
    a thousandfold each, so after the first they solve with the factor's own matrix — no
    tangent is assembled, and a system on the factor's own matrix is one solve on it (no PCG,
    no factorisation); the displacement is the one of a factorisation per iteration. The
    cantilever's first iteration leaves more unbalanced force than it found (large rotation of
    a slender beam): every iteration assembles its tangent, and PCG needs several iterations on
    the older factor."""
    kept = run(block(10, linear_solver="direct"), tmp_path, "kept")
    every = run(block(10, linear_solver="direct", factor_reuse=False), tmp_path, "every")
    assert kept["factorizations"] == 1 and kept["steps"] >= 3 and kept["krylov_solves"] == 0
    assert every["factorizations"] >= 2
    uz, want = kept["final"]["top.displacement.z"], every["final"]["top.displacement.z"]
    assert abs(uz - want) <= 1e-7 * abs(want)
    from conftest import EXAMPLES
    beam = nmm3d.load(EXAMPLES / "cantilever.toml").run(out=tmp_path / "beam").summary
    assert beam["krylov_solves"] >= 2 and beam["krylov_iterations"] >= 3 * beam["krylov_solves"]


@pytest.mark.parametrize("user", [None, "1"])
def test_import_sets_the_allocators_page_defaults_unless_the_user_chose(user):
    """`import nmm3d` keeps freed pages and asks for no huge pages (docs/theory/solver.md) —
    before `_core` loads, and never over a value the user set."""
    import os
    import subprocess

    env = {k: v for k, v in os.environ.items() if not k.startswith("MIMALLOC_")}
    if user is not None:
        env["MIMALLOC_ALLOW_THP"] = user
    code = "import os, nmm3d; print(os.environ['MIMALLOC_ALLOW_THP'], os.environ['MIMALLOC_PURGE_DELAY'])"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.split() == [user or "0", "-1"]


def test_single_precision_factors_refined_reach_the_double_factors_answer(tmp_path):
    """`factor_precision = "single"`: each factorisation in f32, each solve refined by CG on the
    f64 matrix (docs/theory/solver.md, *Single-precision factors*) — the double factor's answer;
    "auto" keeps this small factor in double precision."""
    got = {p: run(two_blocks(6, max_steps=3, factor_precision=p), tmp_path, p) for p in ("double", "single", "auto")}
    assert got["single"]["single_precision_factorizations"] >= 1
    assert got["single"]["refinement_iterations"] >= 2
    assert got["double"]["single_precision_factorizations"] == got["auto"]["single_precision_factorizations"] == 0
    uz, want = got["single"]["final"]["top.displacement.z"], got["double"]["final"]["top.displacement.z"]
    assert want < 0 and abs(uz - want) <= 1e-9 * abs(want)


def test_an_unknown_factor_precision_is_named(tmp_path):
    with pytest.raises(nmm3d.ScenarioError, match="analysis.factor_precision"):
        nmm3d.Scenario.from_dict(two_blocks(4, factor_precision="half"))


EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_the_block_solver_moves_the_jointed_slope_as_the_direct_factor_does(tmp_path):
    """`linear_solver = "blocks"` (docs/theory/solver.md, *A rock mass of many blocks*): thesis
    case A sliding for 30 steps — the same steps and open–close iterations as the direct factor,
    the measuring blocks where it puts them, a few PCG iterations per solve."""
    got = {}
    for solver in ("direct", "blocks"):
        sets = ["joint.rock_joint.friction_angle=10", "analysis.duration=0.03", f'analysis.linear_solver="{solver}"']
        got[solver] = nmm3d.load(str(EXAMPLES / "rock_slope.toml"), sets).run(out=tmp_path / solver).summary
    direct, blocks = got["direct"], got["blocks"]
    assert blocks["linear_solver"] == "blocks" and blocks["status"] == "completed"
    assert (blocks["steps"], blocks["open_close_iterations"]) == (direct["steps"], direct["open_close_iterations"])
    solves = blocks["factorizations"] + blocks["krylov_solves"]
    assert 0 < blocks["multigrid_iterations"] <= 10 * solves
    moved = [k for k in direct["final"] if k.endswith("displacement.x")]
    assert all(direct["final"][k] > 1e-4 for k in moved)
    for k in moved:
        assert abs(blocks["final"][k] - direct["final"][k]) <= 1e-7 * abs(direct["final"][k]), k
