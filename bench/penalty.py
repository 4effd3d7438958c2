"""How stiff the automatic contact penalty of a web of touching blocks should be; writes
docs/penalty.md.

Run: python bench/penalty.py

`contact.normal_stiffness = "auto"` gives each contact point `contact.auto_penalty_factor` (10)
× the largest Young's modulus × the cover size. On a web of touching blocks the open–close
iteration's count, and with it the factorisations, follow that stiffness: the stiffer the
springs, the more points flip between stick, slide and open at nearly zero force
(docs/theory/contact.md). Each case here runs back to back with the factor 10, 3, 1, 0.3 and
0.1: iterations, factorisations, systems solved on the last factor instead (PCG), wall time,
the deepest overlap and the energy balance, and the answer (the roof block's travel; the
dominos' tilts) beside them. The packed pile of `bench/contact.py` (300 cubes touching side to
side, settling 2 mm onto the floor) runs in this process.
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from pathlib import Path

from _page import write_page
from _run import run_scenario
from contact import pile

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "penalty.md"
FACTORS = [10.0, 3.0, 1.0, 0.3, 0.1]


def roof(s: dict) -> str:
    """How far Goodman's roof key block moved [m]."""
    return f"roof block {math.sqrt(sum(s['final'][f'roof_block.displacement.{a}'] ** 2 for a in 'xyz')):.4f} m"


def tilts(s: dict) -> str:
    """The ten dominos' final tilts [°]."""
    return "tilts " + ", ".join(f"{abs(s['final'][f'd{k}.rotation.y']) * 180.0 / math.pi:.0f}" for k in range(10))


def nothing(s: dict) -> str:
    return "–"


def from_file(scenario: Path, sets: list[str]):
    """A case run by the command line: the summary for a factor."""
    return lambda setting: run_scenario(scenario, [*sets, setting])


def packed_pile(n: int):
    """A case built by `bench/contact.py`, run through the Python API."""
    def run(setting: str) -> dict:
        import nmm3d

        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            s = nmm3d.Scenario.from_dict(pile(n, packed=True), [setting]).run(out=out).summary
            return {**s, "wall": time.perf_counter() - t0}
    return run


DOMINOS = ROOT / "bench" / "peers" / "dominos_yade_match.toml"
# (case, how it runs, answer).
CASES = [
    ("Goodman's tunnel, 0.3 s (20 meshed blocks, 2 m cover)", from_file(ROOT / "examples" / "goodman_tunnel.toml", []),
     roof),
    ("Yade-matched dominos, 3 s (0.1 m cover)", from_file(DOMINOS, ["analysis.duration=3.0"]), tilts),
    ("the same dominos on a 0.5 m cover (a few MEs each)",
     from_file(DOMINOS, ["analysis.duration=3.0", "cover.size=0.5"]), tilts),
    ("packed pile of 300 cubes, 40 steps (0.5 m cover)", packed_pile(300), nothing),
]


def row(name: str, factor: float, s: dict, answer) -> str:
    return (f"| {name} | {factor:g} | {s['steps']} | {s['step_cuts']} | {s['open_close_iterations']} | "
            f"{s['factorizations']} | {s['krylov_solves']} | {s['timings'].get('factorization', 0.0):.1f} | "
            f"{s['wall']:.1f} | {1e3 * s['max_penetration']:.2f} | {s['missed_overlaps']} | "
            f"{100 * s['energy']['max_error_ratio']:.2f} % | {answer(s)} |")


def main() -> None:
    load0 = os.getloadavg()[0]
    lines = []
    for name, run, answer in CASES:
        for factor in FACTORS:
            s = run(f"contact.auto_penalty_factor={factor}")
            lines.append(row(name, factor, s, answer))
            print(lines[-1], flush=True)
    write_page(PAGE, "The automatic contact penalty on webs of touching blocks", "penalty.py", load0, [
        "Each case runs with `contact.auto_penalty_factor` set to each value, back to back (10 is the",
        "default: the normal penalty of a point is that × the largest Young's modulus × the cover size).",
        "*Iterations*: open–close iterations; *factorisations*: numeric factorisations (an iteration",
        "whose matrix differs from the last factor's by at most `analysis.factor_reuse_closeness` of its",
        "largest entry is solved by PCG on that factor instead: *on the factor*, the end-of-step",
        "equilibrium corrections included); *factorising*: seconds of the solves that factorised;",
        "*overlap*: the deepest contact overlap [mm]; *late*: overlaps found deeper than a detection lets",
        "one arise (`missed_overlaps`); *balance*: the largest energy balance error relative to the",
        "largest account. Wall times on this machine vary by up to 20 % between identical runs.",
        "What the numbers mean: [theory/contact.md](theory/contact.md), *The penalty sets the count*.",
        "",
        "| case | factor | steps | cuts | iterations | factorisations | on the factor | factorising [s] "
        "| wall [s] | overlap [mm] | late | balance | answer |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
        *lines,
    ])
    print(f"wrote {PAGE.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
