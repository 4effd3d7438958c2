"""Degenerate cuts at any scale and position; writes docs/cutting-degenerate.md.

Run: python bench/degenerate_cuts.py [--cases 10000] [--seed 1]

Each seeded case is a box of 1 mm to 1 km cut by planes chosen to be degenerate against it or
against each other (issue 13, item 4):

* `vertex`: a plane of random orientation through a corner of the box;
* `edge`: a plane containing an edge (its normal square to the edge, as dip and dip direction
  give it: within round-off);
* `face`: a plane parallel to a face, on it or 1e-8 … 1e-14 of the box's size off it;
* `pair`: a plane through the box and a second one 1e-8 … 1e-14 of the size beside it, or
  turned by 1e-8 … 1e-14 rad;
* `set`: a joint set along the box's axes whose planes fall on its faces and within it;
* `sets`: two joint sets of one spacing, 1e-8 … 1e-14 rad apart or their planes that far
  (× size) beside each other;
* `hole`: a box excavated from the middle of it, and a plane on a face of the hole or 1e-8 …
  1e-14 of the size off it;

each with a plane of random orientation through the box besides. Every case is cut once with
the box at the origin and once shifted to survey coordinates (1e6, 4e6, 1e3) m, through the
`nmm3d` Python API (`Scenario.blocks()`). Checks: nothing is refused; the blocks fill the box
(Σ volumes against the box's volume less the hole's, as the shifted coordinates represent them); the shifted case
makes the same blocks (count, and sorted volumes to the resolution its coordinates carry,
relative to the box's volume).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import random
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "cutting-degenerate.md"
SHIFT = (1.0e6, 4.0e6, 1.0e3)
CLASSES = ("vertex", "edge", "face", "pair", "set", "sets", "hole")
OFFSETS = (0.0, 1e-8, 1e-10, 1e-12, 1e-14)
EPS = 2.0**-52
# `cutting.sliver_ratio`, its default.
SLIVER_RATIO = 1e-4


def plane(dip: float, dd: float, point: list[float]) -> dict:
    return {"dip": dip, "dip_direction": dd, "point": point}


def features(kind: str, size: float, rng: random.Random) -> tuple[list[dict], list[dict], list[list[float]], float]:
    """Joint planes, joint sets and excavated boxes (min and max corners) of one degenerate kind,
    for a box [0, size]³, and the offset (or angle) that makes it degenerate, relative to `size`."""
    corner = [size * rng.randint(0, 1) for _ in range(3)]
    tiny = rng.choice(OFFSETS) * rng.choice((-1.0, 1.0))
    if kind == "hole":
        lo, hi = [size * rng.uniform(0.2, 0.4) for _ in range(3)], [size * rng.uniform(0.6, 0.8) for _ in range(3)]
        axis = rng.randrange(3)
        at = [lo, hi][rng.randint(0, 1)][:]
        at[axis] += tiny * size
        dip, dd = ((90.0, 90.0), (90.0, 0.0), (0.0, 0.0))[axis]
        return [plane(dip, dd, at)], [], [lo + hi], abs(tiny)
    if kind == "sets":
        dip, dd, k = 10.0 + 70.0 * rng.random(), 360.0 * rng.random(), rng.randint(2, 5)
        small = rng.choice(OFFSETS[1:])
        a = {"dip": dip, "dip_direction": dd, "spacing": size / k, "origin": [0.5 * size] * 3}
        if rng.random() < 0.5:
            return [], [a, dict(a, dip=dip + math.degrees(small))], [], small
        n = normal(dip, dd)
        return [], [a, dict(a, origin=[0.5 * size + small * size * n[j] for j in range(3)])], [], small
    if kind == "vertex":
        return [plane(90.0 * rng.random(), 360.0 * rng.random(), corner)], [], [], 0.0
    if kind == "edge":
        axis = rng.randrange(3)
        if axis == 2:  # a vertical edge: any vertical plane through it
            return [plane(90.0, 360.0 * rng.random(), corner)], [], [], 0.0
        dd = rng.choice((0.0, 180.0)) if axis == 0 else rng.choice((90.0, 270.0))
        return [plane(90.0 * rng.random(), dd, corner)], [], [], 0.0
    if kind == "face":
        axis = rng.randrange(3)
        at = corner[:]
        at[axis] += tiny * size
        dip, dd = ((90.0, 90.0), (90.0, 0.0), (0.0, 0.0))[axis]
        return [plane(dip, dd, at)], [], [], abs(tiny)
    if kind == "pair":
        dip, dd = 10.0 + 70.0 * rng.random(), 360.0 * rng.random()
        p = [size * (0.2 + 0.6 * rng.random()) for _ in range(3)]
        small = rng.choice(OFFSETS[1:])
        if rng.random() < 0.5:
            n = normal(dip, dd)
            q = [p[k] + small * size * n[k] for k in range(3)]
            return [plane(dip, dd, p), plane(dip, dd, q)], [], [], small
        return [plane(dip, dd, p), plane(dip + math.degrees(small), dd, p)], [], [], small
    # A set along an axis with its planes on the faces and k - 1 planes inside.
    axis, k = rng.randrange(3), rng.randint(1, 4)
    dip, dd = ((90.0, 90.0), (90.0, 0.0), (0.0, 0.0))[axis]
    return [], [{"dip": dip, "dip_direction": dd, "spacing": size / k, "origin": [0.0, 0.0, 0.0]}], [], 0.0


def normal(dip: float, dd: float) -> list[float]:
    a, b = math.radians(dip), math.radians(dd)
    return [math.sin(a) * math.sin(b), math.sin(a) * math.cos(b), math.cos(a)]


def scenario(size: float, planes: list[dict], sets: list[dict], holes: list[list[float]],
             o: tuple[float, float, float]) -> dict:
    move = lambda p: [p[k] + o[k] for k in range(3)]  # noqa: E731
    return {
        "cover": {"size": size},
        "material": [{"name": "rock", "density": 2500.0, "young": 1e9, "poisson": 0.25}],
        "body": [{"name": "box", "material": "rock",
                  "shape": {"box": {"min": move([0.0, 0.0, 0.0]), "max": move([size, size, size])}}}],
        "joint_plane": [dict(p, point=move(p["point"])) for p in planes],
        "joint_set": [dict(s, origin=move(s["origin"])) for s in sets],
        "excavation": [{"shape": {"box": {"min": move(h[:3]), "max": move(h[3:])}}} for h in holes],
    }


def cut(d: dict) -> tuple[list[float] | None, str]:
    import nmm3d

    try:
        return sorted(float(v) for v in nmm3d.Scenario.from_dict(d).blocks()["volume"]), ""
    except Exception as e:  # noqa: BLE001 - a refusal is what the bench counts
        return None, f"{type(e).__name__}: {str(e).splitlines()[0]}"


def box_volume(d: dict) -> float:
    """The body's volume less its excavations', as the (shifted) coordinates represent them."""
    boxes = [d["body"][0]["shape"]["box"], *(e["shape"]["box"] for e in d["excavation"])]
    v = [math.prod(b["max"][k] - b["min"][k] for k in range(3)) for b in boxes]
    return v[0] - sum(v[1:])


def run_case(rng: random.Random) -> dict:
    kind = rng.choice(CLASSES)
    size = 10.0 ** rng.uniform(-3.0, 3.0)
    planes, sets, holes, offset = features(kind, size, rng)
    planes.append(plane(90.0 * rng.random(), 360.0 * rng.random(), [size * rng.random() for _ in range(3)]))
    row = {"kind": kind, "size": size, "offset": offset}
    for where, o in (("origin", (0.0, 0.0, 0.0)), ("far", SHIFT)):
        d = scenario(size, planes, sets, holes, o)
        volumes, error = cut(d)
        v = box_volume(d)
        row[where] = {"volumes": volumes, "error": error, "box": v,
                      "fill": None if volumes is None else abs(sum(volumes) - v) / v}
    return row


def agrees(row: dict) -> tuple[bool, float]:
    """Same count, and the largest difference of the sorted volumes (× box volume)."""
    a, b = row["origin"]["volumes"], row["far"]["volumes"]
    if a is None or b is None or len(a) != len(b):
        return False, math.inf
    v = row["origin"]["box"]
    worst = max((abs(x - y) / v for x, y in zip(a, b)), default=0.0)
    return True, worst


def verdict(row: dict) -> str:
    """`same` (volumes within the coordinates' resolution), `sliver` (a sliver below
    `cutting.sliver_ratio` of its largest neighbour went to another neighbour: the volumes
    differ by less than it), `unresolved` (the case's offset is finer than the shifted
    coordinates can carry: the shifted input is another geometry) or `differ`."""
    ok, worst = agrees(row)
    if ok and worst < resolution(row["size"]):
        return "same"
    if ok and worst <= SLIVER_RATIO * max(row["origin"]["volumes"]) / row["origin"]["box"]:
        return "sliver"
    return "unresolved" if 0.0 < row["offset"] < resolution(row["size"]) else "differ"


def resolution(size: float) -> float:
    """Relative volume resolution of a box of `size` at the shifted coordinates: a few units in
    the last place of its largest coordinate, over its size."""
    return 8.0 * EPS * max(SHIFT) / size


def summarise(rows: list[dict]) -> list[list[str]]:
    table = []
    for kind in (*CLASSES, "all"):
        rs = [r for r in rows if kind in ("all", r["kind"])]
        refused = sum(r[w]["volumes"] is None for r in rs for w in ("origin", "far"))
        fill0 = max((r["origin"]["fill"] for r in rs if r["origin"]["fill"] is not None), default=0.0)
        fill1 = max((r["far"]["fill"] / resolution(r["size"]) for r in rs if r["far"]["fill"] is not None),
                    default=0.0)
        verdicts = [verdict(r) for r in rs]
        within = max((agrees(r)[1] / resolution(r["size"]) for r, x in zip(rs, verdicts) if x == "same"), default=0.0)
        table.append([kind, f"{len(rs)}", f"{refused}", f"{fill0:.1e}", f"{fill1:.2f}", f"{verdicts.count('same')}",
                      f"{within:.2f}", f"{verdicts.count('sliver')}", f"{verdicts.count('unresolved')}",
                      f"{verdicts.count('differ')}"])
    return table


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    load, clock = os.getloadavg()[0], time.perf_counter()
    rows = [run_case(rng) for _ in range(args.cases)]
    wall = time.perf_counter() - clock
    table = summarise(rows)
    failures = [r for r in rows if r["origin"]["error"] or r["far"]["error"]]
    lines = [
        "# Degenerate cuts at any scale and position",
        "",
        f"`python bench/degenerate_cuts.py --cases {args.cases} --seed {args.seed}` (do not edit by hand) — "
        f"{platform.machine()}, {os.cpu_count()} cores, load {load:.1f} at the start, {wall:.0f} s.",
        "",
        "\n\n".join((__doc__ or "").split("\n\n")[2:]).strip(),  # what each case is
        "",
        "Columns: cases of the class; cuts refused (of two per case); the largest |Σ V − V| / V at the",
        "origin; the same at the shifted coordinates in units of their resolution (8 ulp of 4·10⁶ m",
        "over the box's size); the cases whose shifted cut made the same blocks (count, and sorted",
        "volumes within that resolution of the box's volume) and the largest such difference in",
        "resolutions; the cases where a sliver (a block below `cutting.sliver_ratio` = 10⁻⁴ of its",
        "largest neighbour, merged into a neighbour) went to another neighbour than at the origin —",
        "the volumes then differ by less than the sliver; the cases whose offset is finer than the shifted",
        "coordinates carry (their shifted input is another geometry); and the cases that differ otherwise.",
        "",
        "| class | cases | refused | Σ V at the origin (relative) | Σ V shifted (resolutions) | same blocks | their largest difference (resolutions) | a sliver merged elsewhere | offset below the shifted resolution, cut otherwise | differ |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *("| " + " | ".join(r) + " |" for r in table),
        "",
    ]
    if failures:
        lines += ["Refusals (first five):", ""]
        lines += [f"- {r['kind']}, size {r['size']:.3e} m: {r['origin']['error'] or r['far']['error']}" for r in failures[:5]]
        lines.append("")
    differ = [r for r in rows if verdict(r) == "differ" and not (r["origin"]["error"] or r["far"]["error"])]
    if differ:
        lines += ["Cases that differ (first five): class, size, block counts at the origin and shifted, the",
                  "largest difference of the sorted volumes relative to the box.", ""]
        for r in differ[:5]:
            a, b = r["origin"]["volumes"], r["far"]["volumes"]
            lines.append(f"- {r['kind']}, {r['size']:.3e} m: {len(a)} / {len(b)} blocks, {agrees(r)[1]:.1e}")
        lines.append("")
    PAGE.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
