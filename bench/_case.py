"""One benchmark case in a fresh process; prints a JSON line with timings and peak memory.

Usage: python bench/_case.py nmm3d N OUT [ORDERING] | python bench/_case.py skfem N
"""

from __future__ import annotations

import json
import resource
import sys
import time


def block_scenario(n: int, ordering: str = "auto", solver: str = "auto") -> dict:
    """A cube of n × n × n cells (tet6: 6 n³ MEs), base held, loaded by its weight."""
    return {
        "analysis": {"kind": "static", "duration": 1.0, "dt": 1.0e3, "max_steps": 1, "max_displacement_ratio": 1.0,
                     "gravity": [0.0, 0.0, -10.0], "output_interval": 0.0, "ordering": ordering,
                     "linear_solver": solver},
        "cover": {"pattern": "tet6", "size": 1.0},
        "material": [{"name": "rock", "density": 2500.0, "young": 1.0e9, "poisson": 0.25}],
        "body": [{"name": "block", "material": "rock", "shape": {"box": {"min": [0, 0, 0], "max": [n, n, n]}}}],
        "constraint": [{"select": {"box": {"min": [-0.01, -0.01, -0.01], "max": [n + 0.01, n + 0.01, 0.01]}},
                        "directions": ["x", "y", "z"]}],
        "monitor": [{"name": "top", "select": {"point": [n / 2, n / 2, n]}, "quantities": ["displacement"],
                     "location": "point"}],
    }


def run_nmm3d(n: int, out: str, ordering: str = "auto") -> dict:
    import nmm3d

    t0 = time.perf_counter()
    # The direct solver's page (bench/perf.py): pinned, the default would take multigrid.
    result = nmm3d.Scenario.from_dict(block_scenario(n, ordering, "direct")).run(out=out)
    wall = time.perf_counter() - t0
    s = result.summary
    return {"mes": s["manifold_elements"], "dofs": s["dofs"], "timings": s["timings"], "wall": wall,
            "top_uz": s["final"]["top.displacement.z"]}


def run_skfem(n: int) -> dict:
    import numpy as np
    from scipy.sparse.linalg import spsolve
    from skfem import Basis, ElementTetP1, ElementVector, LinearForm, MeshTet, asm, condense
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    t = {}
    t0 = time.perf_counter()
    x = np.linspace(0.0, float(n), n + 1)
    mesh = MeshTet.init_tensor(x, x, x)
    basis = Basis(mesh, ElementVector(ElementTetP1()))
    t["mesh_basis"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    K = asm(linear_elasticity(*lame_parameters(1.0e9, 0.25)), basis)

    @LinearForm
    def weight(v, w):
        return -2500.0 * 10.0 * v[2]

    f = asm(weight, basis)
    t["assembly"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    fixed = basis.get_dofs(lambda p: np.isclose(p[2], 0.0)).all()
    u = np.zeros(K.shape[0])
    A, b, _, I = condense(K, f, D=fixed)
    u[I] = spsolve(A, b)
    t["solve"] = time.perf_counter() - t0
    node = int(np.argmin(np.linalg.norm(mesh.p - np.array([[n / 2], [n / 2], [n]]), axis=0)))
    return {"mes": mesh.t.shape[1], "dofs": int(len(I)), "timings": t, "wall": sum(t.values()),
            "top_uz": float(u[basis.nodal_dofs[2, node]])}


if __name__ == "__main__":
    which, n = sys.argv[1], int(sys.argv[2])
    res = run_nmm3d(n, sys.argv[3], *sys.argv[4:5]) if which == "nmm3d" else run_skfem(n)
    res["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(json.dumps(res))
