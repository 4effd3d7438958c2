"""Full-size verification runs; writes docs/verification.md. Run: python bench/verification.py

Each case runs an example scenario (with overrides) through the Python API and compares with
the closed form kept in `nmm3d.analytic` (or an independent reference, quoted beside its
table). The fast versions of these checks are tests
(crates/nmm3d-core/tests/verification_*.rs); this script runs the larger meshes and records
what was measured. Figures are written, never typed.
"""

from __future__ import annotations

import argparse
import math
import platform
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

import nmm3d
from nmm3d import analytic

ROOT = Path(__file__).resolve().parent.parent
EX = ROOT / "examples"
PATTERNS = ["tet5", "tet6", "tet24", "hex8"]


class Report:
    def __init__(self, tmp: Path) -> None:
        self.tmp = tmp
        self.lines: list[str] = []
        self.count = 0

    def run(self, example: str, *overrides: str) -> nmm3d.Result:
        return self.run_scenario(nmm3d.load(EX / example, list(overrides)), f"{example} {' '.join(overrides)}")

    def run_scenario(self, scenario: nmm3d.Scenario, label: str) -> nmm3d.Result:
        self.count += 1
        out = self.tmp / f"run{self.count}"
        t0 = time.perf_counter()
        r = scenario.run(out=out)
        print(f"  {label}: {r.status} in {time.perf_counter() - t0:.1f} s", flush=True)
        return r

    def table(self, title: str, intro: str, header: list[str], rows: list[list[str]]) -> None:
        self.lines += [f"## {title}", "", intro, "", "| " + " | ".join(header) + " |",
                       "|" + "---|" * len(header)]
        self.lines += ["| " + " | ".join(r) + " |" for r in rows]
        self.lines.append("")


def titles(rep: Report) -> list[str]:
    return [ln[3:] for ln in rep.lines if ln.startswith("## ")]


def mark(ok: bool) -> str:
    return "pass" if ok else "**FAIL**"


def free_fall(rep: Report) -> None:
    rows = []
    for v0 in ([0.0, 0.0, 0.0], [1.0, 2.0, 3.0]):
        u_ex, v_ex = analytic.ballistic(v0, [0, 0, -10.0], 1.0)
        for p in PATTERNS:
            r = rep.run("free_fall.toml", f"cover.pattern=\"{p}\"", f"body.cube.velocity={v0}")
            f = r.summary["final"]
            u = np.array([f[f"cube.displacement.{c}"] for c in "xyz"])
            v = np.array([f[f"cube.velocity.{c}"] for c in "xyz"])
            eu = np.linalg.norm(u - u_ex) / np.linalg.norm(u_ex)
            ev = np.linalg.norm(v - v_ex) / np.linalg.norm(v_ex)
            smax = max(abs(f[f"cube.stress.{c}"]) for c in ("xx", "yy", "zz", "xy", "yz", "zx"))
            rows.append([str(v0), p, f"{u[2]:.9f}", f"{u_ex[2]:.9f}", f"{eu:.1e}", f"{ev:.1e}", f"{smax:.1e}",
                         mark(eu <= 1e-6 and ev <= 1e-6)])
    rep.table("(a1, a2) Free fall and ballistic flight",
              "1 m cube, ρ = 2500, g = 10, t = 1 s, cover rotated (20°, 35°, −10°); closed form "
              "u = v₀t + ½gt². Tolerance 1e-6 relative; stress must stay ≈ 0.",
              ["v₀ [m/s]", "pattern", "u_z [m]", "exact u_z [m]", "rel. error u", "rel. error v",
               "max |σ| [Pa]", "result"], rows)


def spin(rep: Report) -> None:
    rows = []
    for p in ["tet6", "tet24", "hex8"]:
        one = rep.run("spinning_block.toml", f"cover.pattern=\"{p}\"", "analysis.duration=1.0")
        two = rep.run("spinning_block.toml", f"cover.pattern=\"{p}\"", "analysis.duration=2.0")
        v1 = one.summary["final"]["cube.volume.value"]
        v2 = two.summary["final"]["cube.volume.value"]
        rows.append([p, f"{v1 - 1:+.2e}", f"{v2 - 1:+.2e}", mark(abs(v1 - 1) < 1e-3 and abs(v2 - 1) <= abs(v1 - 1) + 1e-4)])
    rep.table("(a3) Spinning block", "1 m cube spinning at ω = 2π rad/s about z, no gravity. Volume change after one "
              "and two revolutions; tolerance < 1e-3 and no growth.",
              ["pattern", "ΔV/V after 1 turn", "ΔV/V after 2 turns", "result"], rows)


def vtu_stress(path: Path) -> np.ndarray:
    """The cell array `stress` of an nmm3d frame, read as a user would (meshio)."""
    import meshio

    return np.concatenate([np.asarray(s).reshape(-1, 6) for s in meshio.read(path).cell_data["stress"]])


def last_frame(r: nmm3d.Result) -> Path:
    pvd = ET.parse(r.directory / "result.pvd").getroot()
    return r.directory / pvd.findall("./Collection/DataSet")[-1].get("file")


def bars(rep: Report) -> None:
    rows = []
    exact = analytic.bar_end_load(1e6, 10.0, 10e9)
    for p in PATTERNS:
        for rot in ("[0.0, 0.0, 0.0]", "[10.0, 25.0, 40.0]"):
            r = rep.run("bar_patch.toml", f"cover.pattern=\"{p}\"", f"cover.rotation={rot}")
            s = vtu_stress(last_frame(r))
            err = max(np.abs(s[:, 0] - 1e6).max(), np.abs(s[:, 1:]).max()) / 1e6
            f = r.summary["final"]
            stretch = f["end.displacement.x"] - f["start.displacement.x"]
            rows.append([p, rot, str(len(s)), f"{err:.1e}", f"{stretch * 1e3:.9f}", f"{abs(stretch - exact) / exact:.1e}",
                         mark(err < 1e-6 and abs(stretch - exact) < 1e-6 * exact)])
    rep.table("(f) End-loaded bar: the patch test",
              "L = 10 m, 1 × 1 m, E = 10 GPa, ν = 0.25, 1 MPa pulling on both ends, six statically determinate "
              "point supports. Exact: σ_xx = 1 MPa in every ME, u(L) − u(0) = σL/E = 1 mm. Tolerance 1e-6.",
              ["pattern", "cover rotation [deg]", "MEs", "max stress error / σ", "u(L) − u(0) [mm]", "rel. error", "result"], rows)
    rows = []
    exact = analytic.hanging_bar(2500.0, 10.0, 10.0, 10e9)
    for p in PATTERNS:
        r = rep.run("hanging_bar.toml", f"cover.pattern=\"{p}\"")
        f = r.summary["final"]
        got = f["top.displacement.z"] - f["bottom.displacement.z"]
        rows.append([p, f"{got * 1e3:.5f}", f"{exact * 1e3:.5f}", f"{abs(got - exact) / exact:.2%}", mark(abs(got - exact) < 0.01 * exact)])
    rep.table("(f) Hanging bar under self-weight",
              "Same bar hanging from its top face (rollers), ρ = 2500, g = 10, cover size 0.5 m. Exact ρgL²/(2E) = 0.125 mm. Tolerance 1 %.",
              ["pattern", "stretch [mm]", "exact [mm]", "error", "result"], rows)


def cantilever(rep: Report) -> None:
    for example, ref, title, closed in (
        ("cantilever.toml", 0.04009, "(f) Cantilever, tip load 100 kN",
         analytic.cantilever_tip_load(1e5, 10.0, 10e9, 1 / 12)),
        ("cantilever_self_weight.toml", 0.03762, "(f) Cantilever under self-weight",
         analytic.cantilever_self_weight(2500 * 10.0, 10.0, 10e9, 1 / 12)),
    ):
        rows = []
        for p in ["tet6", "tet24", "hex8"]:
            vals = []
            for s in (0.5, 0.25, 0.125):
                r = rep.run(example, f"cover.pattern=\"{p}\"", f"cover.size={s}")
                vals.append(-r.summary["final"]["tip.displacement.z"])
            monotone = all(a < b for a, b in zip(vals, vals[1:]))
            rows.append([p] + [f"{v:.5f} ({(v - ref) / ref:+.1%})" for v in vals] + ["yes" if monotone else "**no**"])
        rep.table(title, f"L = 10 m, 1 × 1 m, E = 10 GPa, ν = 0.25, clamped face (penalty on every boundary vertex). "
                  f"3-D reference {ref} m (Euler–Bernoulli {closed:.5f} m). Tip deflection [m] (error against the 3-D "
                  "reference) by cover size; target ≤ 2 % at the finest mesh, monotone convergence.",
                  ["pattern", "s = 0.5 m", "s = 0.25 m", "s = 0.125 m", "monotone"], rows)


def plate(rep: Report) -> None:
    kirchhoff = analytic.kirchhoff_plate_corners(12.0 * 10.0 * 0.1, 2.0, 0.1, 10e6, 0.3)
    ref = 5.61e-3
    rows = []
    for p, sizes in (("hex8", (0.1, 0.05, 0.025, 0.02)), ("tet24", (0.1, 0.05))):
        for s in sizes:
            r = rep.run("plate_self_weight.toml", f"cover.pattern=\"{p}\"", f"cover.size={s}")
            w = -r.summary["final"]["centre.displacement.z"]
            rows.append([p, str(s), f"{r.summary['dofs']:,}", f"{w * 1e3:.3f}", f"{(w - ref) / ref:+.1%}", f"{r.summary['wall_seconds']:.1f}"])
    rep.table("(e) Plate on four corners, small strain (thesis Table 4-1, E = 10 MPa)",
              f"2 × 2 × 0.1 m, ν = 0.3, ρ = 12, g = 10; vertical corner edges on rollers. Kirchhoff {kirchhoff * 1e3:.3f} mm; "
              "3-D roller-corner reference ≈ 5.61 mm. Target 3 % at the finest mesh, monotone convergence.",
              ["pattern", "cover size [m]", "DOFs", "centre deflection [mm]", "error vs 5.61 mm", "wall [s]"], rows)
    rows = []
    for rot in ("[0.0, 0.0, 0.0]", "[0.0, 0.0, 30.0]", "[0.0, 0.0, 45.0]"):
        r = rep.run("plate_self_weight.toml", "cover.pattern=\"hex8\"", "cover.size=0.05", f"cover.rotation={rot}")
        rows.append([rot, f"{-r.summary['final']['centre.displacement.z'] * 1e3:.4f}"])
    ws = [float(r[1]) for r in rows]
    spread = (max(ws) - min(ws)) / np.mean(ws)
    rep.table("Mesh orientation (thesis §4, orientation study)",
              f"The small-strain plate with hex8 covers of 0.05 m turned about z. Spread {spread:.2%} "
              f"(target ≤ 2 %): {mark(spread <= 0.02)}.", ["cover rotation [deg]", "centre deflection [mm]"], rows)
    rows = []
    # Green–Lagrange at 0.025 m converges slowly (the co-rotational tangent underestimates SVK's
    # stiffness at the corners' 30 % strains), so it is left out of the documented run.
    for measure, sizes in (("green_lagrange", (0.1, 0.05)), ("corotational", (0.1, 0.05, 0.025))):
        for s in sizes:
            r = rep.run("plate_large_deflection.toml", f"cover.size={s}", f"analysis.strain_measure=\"{measure}\"")
            w = -r.summary["final"]["centre.displacement.z"]
            ok = abs(w - 0.40) <= 0.05 * 0.40
            rows.append([measure, str(s), f"{r.summary['dofs']:,}", f"{w:.4f}", f"{(w - 0.40) / 0.40:+.1%}",
                         str(r.summary["steps"]), mark(ok) if measure == "green_lagrange" else "(for comparison)"])
    rep.table("(e) Plate, large deflection (thesis Table 4-1 as printed, E = 10 kPa)",
              "Vertical corner edges pinned in x, y, z (every boundary vertex on them held by penalty springs); hex8 covers; "
              "static, geometry updated every step. Geometrically nonlinear 3-D reference 0.391 / 0.398 / 0.401 m (refining), "
              "thesis 0.3997 m; target within 5 % of 0.40 m. Strains reach tens of percent next to the pinned corners, so "
              "the strain measure decides the converged answer: St Venant–Kirchhoff (`strain_measure = \"green_lagrange\"`, the "
              "example's setting) converges onto the reference; the default co-rotational small-strain measure is softer "
              "in large tension and drifts above it as the mesh resolves the corners.",
              ["strain measure", "cover size [m]", "DOFs", "centre deflection [m]", "error vs 0.40 m", "steps", "result"], rows)


def incline(rep: Report) -> None:
    rows = []
    a = math.radians(30.0)
    down = np.array([math.cos(a), 0.0, -math.sin(a)])  # down-dip (east)
    for phi in [0, 5, 10, 15, 20, 24, 25, 29, 31, 35]:
        r = rep.run("incline.toml", f"joint.face.friction_angle={phi}")
        f = r.summary["final"]
        u = np.array([f[f"cube.displacement.{c}"] for c in "xyz"])
        d = float(np.linalg.norm(u))
        exact = max(0.0, 0.5 * 10.0 * (math.sin(a) - math.tan(math.radians(phi)) * math.cos(a)))
        off = math.degrees(math.acos(min(1.0, float(u @ down) / d))) if exact > 0.01 else float("nan")
        ok = abs(d - exact) <= max(0.01 * exact, 1e-3) and (exact <= 0.01 or off < 0.5)
        rows.append([f"{phi}", f"{exact:.4f}", f"{d:.4f}", f"{1e3 * (d - exact):+.2f}", "–" if math.isnan(off) else f"{off:.3f}",
                     f"{r.summary['steps']}", f"{r.summary['step_cuts']}", f"{r.summary['max_penetration']:.1e}", mark(ok)])
    rep.table("(b) Cube on a 30° incline",
              "`examples/incline.toml`: 1 m cube, ρ = 2500, E = 10 GPa, ν = 0, g = 10, from its initial equilibrium; "
              "d(1 s) against ½ g (sin α − tan φ cos α) t². Tolerance max(1 %, 1 mm), direction within 0.5° of down-dip.",
              ["φ [°]", "exact d [m]", "d [m]", "error [mm]", "direction off [°]", "steps", "cuts", "max penetration [m]",
               "result"], rows)


def roof_wedge(rep: Report) -> None:
    alpha = math.radians(30.0)
    sigma_n = 0.05e6 * math.cos(alpha) ** 2
    r0 = 2.0 / math.sqrt(3.0)
    area = 3.0 * 2.0 * math.sqrt(1.0 + 0.25 * r0 * r0) / 2.0
    weight = 2000.0 * 10.0 * math.sqrt(3.0) / 3.0
    phi_c = math.degrees(math.atan(weight * math.cos(alpha) / (sigma_n * area)) + alpha)
    settle = weight / (10.0e6 * area)
    rows = []
    for dphi in (-1.0, 1.0, 3.0):
        r = rep.run("roof_wedge.toml", f"joint.j.friction_angle={phi_c + dphi:.3f}")
        z = -r.summary["final"]["wedge.displacement.z"]
        ok = z > 0.01 if dphi < 0 else abs(z - settle) <= 0.05 * settle
        rows.append([f"{phi_c + dphi:.2f}", "falls" if dphi < 0 else f"stays, {1e3 * settle:.3f} mm", f"{1e3 * z:.3f}", mark(ok)])
    rep.table("(c) Roof wedge C1 held by in-situ stress",
              f"`examples/roof_wedge.toml`: σ_h = −0.05 MPa, k_n = k_s = 10 MPa/m; closed form φ_c = {phi_c:.2f}° "
              "(tan(φ_c − α) = W cos α / (σ_n ΣA)), settlement W / (k ΣA). Wedge displacement after 0.5 s.",
              ["φ [°]", "expected", "downward displacement [mm]", "result"], rows)


def impact(rep: Report) -> None:
    g, k, m, v = 10.0, 1e9, 2500.0, math.sqrt(20.0)
    w = math.sqrt(k / m)
    rr = math.hypot(g / w**2, v / w)
    t_ex, p_ex = (math.pi + 2.0 * math.asin(g / w**2 / rr)) / w, g / w**2 + rr
    rows = []
    for integ in ("newmark", "dda"):
        r = rep.run("drop_test.toml", f'analysis.integrator="{integ}"')
        hist = r.history
        z, t = hist["cube.displacement.z"], hist["time"]
        inside = t[z < -1e-3]
        tc, pen = inside[-1] - inside[0], float(-z.min() - 1e-3)
        vz = hist["cube.velocity.z"][-1]
        ok = integ == "dda" or (abs(tc - t_ex) <= 0.05 * t_ex and abs(pen - p_ex) <= 0.05 * p_ex)
        rows.append([integ, f"{1e3 * tc:.3f} / {1e3 * t_ex:.3f}", f"{1e3 * pen:.3f} / {1e3 * p_ex:.3f}",
                     f"{vz / v:.3f}", mark(ok)])
    rep.table("(i) Drop test",
              "`examples/drop_test.toml`: 1 m cube at the speed of a 1 m drop onto a base of total normal stiffness "
              "1e9 N/m, Δt = 10 µs; exact piecewise-linear ODE. Newmark γ = ½ must match within 5 %; the DDA scheme "
              "is dissipative (restitution < 1, reported).",
              ["integrator", "contact time [ms] (ours / exact)", "max penetration [mm] (ours / exact)",
               "rebound / impact speed", "result"], rows)
    rows = []
    for wdt, table in [(0.05, 0.962), (0.1, 0.925), (0.2, 0.855), (0.5, 0.684)]:
        r = rep.run("drop_test.toml", f"analysis.dt={wdt / w}", 'analysis.integrator="dda"', "analysis.gravity=[0, 0, 0]",
                    "analysis.duration=0.012", "analysis.max_displacement_ratio=1.0")
        vz = r.history["cube.velocity.z"]
        e = float(-vz[-1] / vz[0])
        rows.append([f"{wdt}", f"{table:.3f}", f"{e:.4f}", mark(abs(e - table) < 0.005)])
    rep.table("(i) Restitution of the DDA scheme",
              "The same impact without gravity, integrator \"dda\" (Newmark β = ½, γ = 1): rebound / impact speed "
              "against the tabulated restitution of the scheme (case (i)).",
              ["ω Δt", "table", "measured", "result"], rows)


def tetrahedral_wedge(rep: Report) -> None:
    from nmm3d.wedge import critical_friction_angle, wedge

    a, b, t = (50.0, 130.0), (50.0, 230.0), 0.4
    rows = []
    for phi in (10.0, 20.0, critical_friction_angle(a, b) + 1.0):
        ref = wedge(a, b, phi, g=9.81)
        r = rep.run("tetrahedral_wedge.toml", f"joint.j.friction_angle={phi:.3f}")
        u = np.array([r.summary["final"][f"wedge.displacement.{c}"] for c in "xyz"])
        d = float(np.linalg.norm(u))
        if ref.stable:
            rows.append([f"{phi:.2f}", ref.mode, "stable", f"{d:.1e} m", "–", mark(d < 1e-4)])
            continue
        off = math.degrees(math.acos(min(1.0, float(u @ ref.direction) / d)))
        acc = 2.0 * d / t**2
        rows.append([f"{phi:.2f}", ref.mode, f"{ref.acceleration:.4f}", f"{acc:.4f}", f"{off:.3f}",
                     mark(off < 1.0 and abs(acc - ref.acceleration) <= 0.02 * ref.acceleration)])
    rep.table("(d) Tetrahedral wedge against the vector method",
              "`examples/tetrahedral_wedge.toml` (joints 50/130 and 50/230) against `nmm3d.wedge` (Hoek & Bray): "
              "acceleration from the displacement after 0.4 s (½ a t²), direction against the line of intersection. "
              "Tolerances 2 % and 1°; stable 1° above the critical angle.",
              ["φ [°]", "mode", "a exact [m/s²]", "a [m/s²]", "direction off [°]", "result"], rows)


def sliding_wedge_scenario(k: float | None, *overrides: str) -> nmm3d.Scenario:
    """`examples/sliding_wedge.toml` with joint stiffness k [Pa/m], or the `[contact]` penalty (None)."""
    data = nmm3d.load(EX / "sliding_wedge.toml", ["analysis.output_interval=0.0", *overrides]).to_dict()
    joint = data["joint"][0]
    joint.pop("normal_stiffness"), joint.pop("shear_stiffness")
    if k is not None:
        joint["normal_stiffness"] = joint["shear_stiffness"] = k
    return nmm3d.Scenario.from_dict(data)


def sliding_wedge(rep: Report) -> None:
    from nmm3d.wedge import critical_friction_angle, wedge

    a, b, g, t = (40.0, 130.0), (60.0, 220.0), 10.0, 0.6
    phi_c = critical_friction_angle(a, b)
    ref = wedge(a, b, 30.0, g=g)
    rows, study_rows = [], []
    # (stiffness, contact damping ratio). Released from its locked equilibrium the wedge slips on
    # its joints until friction holds it and swings on their springs; that transient lasts as long
    # as √(m/k): on joints softer than 10 MPa/m the windows (0.3–0.6 s to fit the acceleration,
    # 0.8 s at φc + 1°) stretch by √(10 MPa/m / k) — 1 MPa/m joints swing with a period of 0.5 s.
    for k, xi in ((1e6, 0.0), (1e6, 0.3), (1e7, 0.0), (1e8, 0.0), (1e11, 0.0), (None, 0.0)):
        name = ("auto" if k is None else f"{k:.0e} Pa/m") + (f", ξ = {xi:g}" if xi else "")
        damping = f"contact.damping_ratio={xi}"
        stretch = max(1.0, math.sqrt(1e7 / k)) if k else 1.0
        t, rest = 0.6 * stretch, 0.8 * stretch
        r = rep.run_scenario(sliding_wedge_scenario(k, f"analysis.duration={t}", damping), f"sliding wedge {name} φ = 30°")
        h = r.history
        time_, d = h["time"], np.c_[[h[f"wedge.displacement.{c}"] for c in "xyz"]].T
        late = time_ >= t / 2  # after the joints' settlement
        acc = 2.0 * float(np.polyfit(time_[late], d[late] @ ref.direction, 2)[0])
        step = d[-1] - d[late][0]
        off = math.degrees(math.acos(min(1.0, float(step @ ref.direction) / float(np.linalg.norm(step)))))
        r = rep.run_scenario(sliding_wedge_scenario(k, f"joint.j.friction_angle={phi_c + 1.0}",
                                                    f"analysis.duration={rest}", damping), f"sliding wedge {name} φc + 1°")
        h = r.history
        d = np.linalg.norm(np.c_[[h[f"wedge.displacement.{c}"] for c in "xyz"]].T, axis=1)
        # Sliding makes the displacement grow; a swing on the joints' springs does not: the
        # largest displacement of the last quarter against that of the third.
        quarter = np.minimum((4 * np.asarray(h["time"]) / rest).astype(int), 3)
        creep = float(d[quarter == 3].max() - d[quarter == 2].max())
        settle = float(d[-1])
        ok = abs(acc - ref.acceleration) <= 0.01 * ref.acceleration and off < 1.0 and creep < 1e-4
        rows.append([name, f"{ref.acceleration:.4f}", f"{acc:.4f}", f"{off:.3f}", f"{1e3 * settle:.2f}",
                     f"{creep:.1e} ({rest / 2:.2g}–{rest:.2g} s)", mark(ok)])
        if k in (1e7, None) and not xi:
            t0 = time.perf_counter()
            s = nmm3d.Study(sliding_wedge_scenario(k), rep.tmp / f"study{rep.count}").run(workers=2).summary
            print(f"  sliding wedge {name} study: {s['status']} in {time.perf_counter() - t0:.1f} s", flush=True)
            lo, hi = s["bracket"]
            found = s["critical_friction_angle"]
            study_rows.append([name, f"{phi_c:.3f}", f"{found:.3f} ({lo:.2f}–{hi:.2f})", f"{found - phi_c:+.3f}",
                               f"{s['runs']}", mark(abs(found - phi_c) <= 0.5)])
    rep.table("(d) The 3DEC sliding wedge: joint stiffness from 1 MPa/m to 100 GPa/m",
              "`examples/sliding_wedge.toml` (Itasca's 3DEC verification problem: joints 40/130 and 60/220, "
              "ρ = 2000 kg/m³, g = 10 m/s², k_n = k_s per unit joint area as in 3DEC, or `auto`, the contact penalty) "
              "against `nmm3d.wedge` (Hoek & Bray). At φ = 30° the acceleration is fitted to the displacement along "
              "the line of intersection over 0.3–0.6 s (after the joints' settlement) and the direction is that of "
              "the displacement over the same time; 1° above the critical angle the wedge must not slide over the "
              "second half of a 0.8 s run: the largest displacement of its last quarter may exceed that of its "
              "third by at most 0.1 mm (a swing on the joints' springs repeats; sliding grows). Released from its "
              "locked equilibrium the wedge slips until friction holds it and swings on its joints for a time "
              "that grows as √(m/k): on joints softer than 10 MPa/m every window stretches by √(10 MPa/m / k) "
              "(×3.16 on 1 MPa/m joints, which swing with a period of about 0.5 s). Settlement: the displacement "
              "at the end, the joints' elastic closure and the slip before friction held. ξ: contact dashpots "
              "(`contact.damping_ratio`), a third of critical damping. Tolerances 1 %, 1° and 0.1 mm.",
              ["joint stiffness", "a exact [m/s²]", "a [m/s²]", "direction off [°]", "settlement at φc + 1° [mm]",
               "growth of the largest displacement, last quarter over third [m]", "result"], rows)
    rep.table("(d) The 3DEC sliding wedge: critical friction angle by a study",
              "`nmm3d study examples/sliding_wedge.toml` (bisection over φ; unstable when the wedge has moved "
              "more than 2 cm after 1.5 s) against the vector method's 33.357° (3DEC's closed form). Tolerance 0.5°.",
              ["joint stiffness", "φc exact [°]", "φc nmm3d [°] (bracket)", "difference [°]", "runs", "result"],
              study_rows)


def tower(rep: Report) -> None:
    r = rep.run("block_tower.toml")
    f = r.summary["final"]
    rho, g, e, h, kn = 2500.0, 10.0, 10.0e9, 1.0, 10.0 * 10.0e9 * 0.5
    w, n = rho * g * h, 3
    expected = sum((n - k) * w / (4.0 * kn) + ((n - k - 1) * w * h / e + rho * g * h * h / (2.0 * e) if k + 1 < n else 0.0)
                   for k in range(n)) + 3.0 / 8.0 * rho * g * h * h / e
    drift = max(abs(f[f"cube{k}.displacement.{c}"]) for k in range(n) for c in "xy")
    settled = -f["cube2.displacement.z"]
    ok = drift < 1e-4 and abs(settled - expected) <= 0.1 * expected
    rep.table("Block on block: a three-cube tower",
              "`examples/block_tower.toml`: 10⁴ dynamic steps of 1 ms. Drift must stay below 0.1 mm; the top cube "
              "settles by the penalty compression of the three interfaces plus the elastic shortening (ν = 0).",
              ["steps", "largest drift [m]", "top settlement [µm] (ours / expected)", "max penetration [m]", "result"],
              [[f"{r.summary['steps']}", f"{drift:.1e}", f"{1e6 * settled:.3f} / {1e6 * expected:.3f}",
                f"{r.summary['max_penetration']:.1e}", mark(ok)]])


def newmark(rep: Report) -> None:
    g, n = 9.81, 0.2
    rows = []
    for a, t0 in ((0.3, 0.3), (0.5, 0.2), (1.0, 0.1), (2.0, 0.05)):
        stop = t0 * a / n
        r = rep.run("newmark_sliding_block.toml", f"seismic.pulse.0.acceleration=[{a * g}, 0.0, 0.0]",
                    f"seismic.pulse.0.duration={t0}", f"analysis.duration={stop + 0.1:.3f}")
        exact = analytic.newmark_pulse(a * g * t0, n, a, g)
        slip = -r.history["block.displacement.x"][-1]
        rows.append([f"{a:.1f}", f"{t0:.2f}", f"{a * g * t0:.3f}", f"{exact:.5f}", f"{slip:.5f}",
                     f"{100 * (slip - exact) / exact:+.2f}", mark(abs(slip - exact) <= 0.02 * exact)])
    rep.table("(s) Newmark's sliding block under a rectangular base pulse",
              "`examples/newmark_sliding_block.toml`: a block on a level joint, yield acceleration N g (N = tan φ = 0.2), "
              "on a base shaken by one pulse A g for t₀ (`[seismic]`, the run in the base's frame): the slip on the base "
              "against u_m = V²/(2gN)(1 − N/A), V = A g t₀ (Newmark 1965). Tolerance 2 %.",
              ["A", "t₀ [s]", "V [m/s]", "u_m exact [m]", "u_m [m]", "difference [%]", "result"], rows)


def footing(rep: Report) -> None:
    p, b, length, k = 1.0e5, 2.0, 1.0, 1.0e7
    rows = []
    for e in (0.2, 0.55):
        theta, settle, contact = analytic.footing_on_joint(p, b, length, e, k)
        for h in (0.5, 0.25, 0.125, 0.1, 0.0625):
            for angle in ((0.0, 2.0) if e > b / 6.0 else (0.0,)):
                r = rep.run("eccentric_footing.toml", f"cover.size={h}", f"point_load.0.point=[{e}, 0.0, 0.01]",
                            f"contact.turned_face_angle={angle}")
                rot, sunk = r.history["footing.rotation.y"][-1], -r.history["footing.displacement.z"][-1]
                kern = e <= b / 6.0
                # Inside the kern the corner springs' trapezoidal rule is the reference; beyond it
                # the closed form, within 3 % from h = B/16 (the edge falls anywhere in a cell).
                ref = analytic.corner_lumped_rotation(theta, h, b) if kern else theta
                tol = 5e-3 if kern else (0.03 if h <= b / 16.0 else None)
                d_rot, d_settle = 100 * (rot - theta) / theta, 100 * (sunk - settle) / settle
                ok = "–" if tol is None else mark(abs(rot - ref) <= tol * ref and abs(sunk - settle) <= max(tol, 2e-3) * settle)
                rows.append([f"{e:.2f}", f"{contact:.2f}", f"{h:g}", f"{angle:g}", f"{1e3 * theta:.3f}",
                             f"{1e3 * ref:.3f}" if kern else "–", f"{1e3 * rot:.3f}", f"{d_rot:+.2f}",
                             f"{1e3 * settle:.3f}", f"{1e3 * sunk:.3f}", f"{d_settle:+.2f}", ok])
    rep.table("(d) A footing on a tensionless joint, in and beyond its kern",
              "`examples/eccentric_footing.toml`: a concrete block 2 m × 1 m × 0.5 m on a fixed slab, joint "
              "k_n = k_s = 10 MPa/m, a vertical 100 kN at eccentricity e just above the base, no gravity, a static run. "
              "Rigid on tensionless springs (Bowles 1996, `nmm3d.analytic.footing_on_joint`): in the kern (e ≤ B/6) "
              "θ = 12 P e / (k L B³) and δ₀ = P / (k B L); beyond it the heel lifts, the pressure a triangle over "
              "c = 3 (B/2 − e), θ = 2P / (k c² L), δ₀ = θ (c − B/2). The joint's springs sit at the corners of the "
              "cover cells (h), each with an equal share of its cell: in the kern they integrate the moment by the "
              "trapezoidal rule and turn by θ / (1 + 2h²/B²) (*corner springs*, tolerance 0.5 %, settlement 0.2 %); "
              "beyond it the contact's edge falls between corners and the error goes down with h, but not steadily (it "
              "depends on where in a cell the edge falls): tolerance 3 % from h = B/16 (coarser rows: –). "
              "*turned*: `contact.turned_face_angle` (0: facets wholly in the detection band only; 2°: a facet "
              "turned by up to 2° against the plane takes part with its part in the band).",
              ["e [m]", "c [m]", "h [m]", "turned [°]", "θ exact [mrad]", "θ corner springs [mrad]", "θ [mrad]",
               "θ diff. [%]", "δ₀ exact [mm]", "δ₀ [mm]", "δ₀ diff. [%]", "result"], rows)


def support(rep: Report) -> None:
    """Rock bolts: anchored and fully grouted, against their closed forms."""
    w, m, ea, kb = 2500.0 * 9.81, 2500.0, 9.82e7, 1.0e9
    dynamic = ['analysis.kind="dynamic"', "analysis.dt=0.001", "analysis.duration=0.3",
               "analysis.max_displacement_ratio=0.01"]
    rows = []

    def row(case: str, exact: float, got: float, tol: float, unit: str) -> None:
        err = (got - exact) / exact
        rows.append([case, f"{exact:.6g}", f"{got:.6g}", unit, f"{100 * err:+.4f}", f"{100 * tol:g}",
                     mark(abs(err) <= tol)])

    r = rep.run("bolted_block.toml")
    row("anchored bolt, hanging cube: stretch W/k", w / 1e7, r.history["b1.elongation.value"][-1], 1e-6, "m")
    for depth in (0.5, 0.999):
        r = rep.run("grouted_bolt.toml", f"bolt.rebar.anchor=[0.5, 0.5, {depth}]")
        k = analytic.grouted_axial_stiffness(ea, kb, 0.95, depth)
        row(f"grouted rebar, {depth:g} m in the roof: stretch W/k_a", w / k, r.history["rebar.elongation.value"][-1],
            1e-6, "m")
    r = rep.run("grouted_bolt.toml", *dynamic, "bolt.rebar.bond_strength=2e4")
    t, v = r.history["time"], r.history["block.velocity.z"]
    late = t > 0.05
    row("grouted rebar pulls out (τ_b = 20 kN/m × 0.5 m): descent (W − τ_b L)/m", (w - 1e4) / m,
        -np.polyfit(t[late], v[late], 1)[0], 0.01, "m/s²")
    drive = w * math.sin(math.radians(20.0))
    ks = analytic.dowel_stiffness(1e9, ea * 0.025**2 / 16.0)
    r = rep.run("grouted_dowel.toml")
    row("dowel on a smooth 20° joint: shear force W sin 20°", drive, r.history["dowel.shear_force.value"][-1], 1e-4, "N")
    row("dowel on a smooth 20° joint: slip W sin 20°/k_s", drive / ks, r.history["block.displacement.x"][-1], 0.01, "m")
    r = rep.run("grouted_dowel.toml", *dynamic, "bolt.dowel.shear_capacity=5e3")
    t, v = r.history["time"], r.history["block.velocity.x"]
    late = t > 0.05
    row("dowel past its 5 kN capacity: slide (W sin 20° − 5 kN)/m", (drive - 5e3) / m,
        np.polyfit(t[late], v[late], 1)[0], 0.02, "m/s²")
    rep.table("(t) Rock bolts: anchored and fully grouted",
              "`examples/bolted_block.toml`, `examples/grouted_bolt.toml`, `examples/grouted_dowel.toml` "
              "([theory/bolts.md](theory/bolts.md)): a 1 m cube (W = 24 525 N) hanging on an anchored bolt "
              "(k = 10⁷ N/m) or on a grouted 25 mm rebar (EA = 9.82·10⁷ N, grout k_b = 1 GPa) bonded 0.95 m in "
              "the cube, its axial stiffness across the joint k_a = k₁k₂/(k₁+k₂), k_i = √(EA k_b) tanh(βL_i), "
              "β = √(k_b/EA) (Farmer 1975); pull-out at the bond strength times the shorter side; a cube on a "
              "frictionless joint held in shear by the same rebar, k_s = k_f/(4λ), λ = (k_f/4EI)^¼, "
              "k_f = 1 GPa (Hetényi 1946). Rates fitted after 0.05 s of 0.3 s.",
              ["case", "exact", "nmm3d", "unit", "difference [%]", "tolerance [%]", "result"], rows)


def hoop_stress(path: Path, radius: float, band: float) -> float:
    """Mean hoop stress σ_θ of the MEs whose centroid lies within `band` of `radius` from the z
    axis, read from a frame as a user would (PyVista) [Pa]."""
    import pyvista

    mesh = pyvista.read(path)
    s = np.asarray(mesh.cell_data["stress"]).reshape(-1, 6)
    centres = np.asarray(mesh.cell_centers().points)
    th = np.arctan2(centres[:, 1], centres[:, 0])
    hoop = s[:, 0] * np.sin(th) ** 2 + s[:, 1] * np.cos(th) ** 2 - 2 * s[:, 3] * np.sin(th) * np.cos(th)
    near = np.abs(np.hypot(centres[:, 0], centres[:, 1]) - radius) < band
    return float(hoop[near].mean())


def stages(rep: Report) -> None:
    """A circular tunnel excavated after in-situ equilibrium, against Lamé's thick cylinder."""
    a, b, p, young, nu = 1.0, 5.0, 1.0e7, 1.0e10, 0.25
    rows = []
    for size in (0.2, 0.1, 0.05):
        r = rep.run("staged_tunnel_lame.toml", f"cover.size={size}")
        before = int(np.searchsorted(r.history["time"], r.summary["stages"][0]["end_time"], side="right")) - 1
        for radius in (1.0, 1.5, 2.0, 4.0):
            u = r.history[f"r{str(radius).replace('.', '_')}.displacement.x"]
            got = u[-1] - u[before]
            exact = analytic.lame_excavation(radius, a, b, p, young, nu)[0]
            err = got / exact - 1
            tol = 0.02 if radius == a else 0.01
            rows.append([f"{size:g}", f"u_r({radius:g} m)", f"{exact * 1e3:.4f}", f"{got * 1e3:.4f}", "mm",
                         f"{100 * err:+.2f}", f"{100 * tol:g}", mark(abs(err) <= tol) if size <= 0.1 else "coarse"])
        for radius in (1.5, 2.0, 3.0):
            exact = -p + analytic.lame_excavation(radius, a, b, p, young, nu)[1]
            got = hoop_stress(last_frame(r), radius, size)
            err = got / exact - 1
            rows.append([f"{size:g}", f"σ_θ({radius:g} m)", f"{exact / 1e6:.3f}", f"{got / 1e6:.3f}", "MPa",
                         f"{100 * err:+.2f}", "3", mark(abs(err) <= 0.03) if size <= 0.1 else "coarse"])
    rep.table("(u) Staged excavation: a circular tunnel in hydrostatic in-situ stress",
              "`examples/staged_tunnel_lame.toml` (written by `bench/lame_tunnel.py`; "
              "[theory/stages.md](theory/stages.md)): a quarter of a plane-strain slab of outer radius 5 m, its "
              "outer arc loaded by the in-situ stress p = 10 MPa (every direction), E = 10 GPa, ν = 0.25. Stage 1 "
              "holds the tunnel's rock in place (static equilibrium); stage 2 removes the tunnel (radius 1 m, a "
              "64-sided disc) and finds the new equilibrium. Exact (Lamé, the thick cylinder): "
              "u = A r + B/r with the radial stress change +p at the wall and 0 at the outer arc; σ_θ = −p + "
              "2(λ+G)A + 2G B/r² (−2p at the wall as the outer radius grows: Kirsch). NMM: the displacement "
              "at each radius since stage 1's end (material points); σ_θ the mean over the MEs whose centroid "
              "lies within one cover size of the radius. Tolerances (2 % at the wall, 1 % beyond, 3 % for "
              "σ_θ) apply from cover size 0.1 m; the 64-sided opening alone accounts for −0.3 %.",
              ["cover size [m]", "quantity", "exact", "nmm3d", "unit", "difference [%]", "tolerance [%]", "result"],
              rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--only", nargs="*", help="run only these sections (names below)")
    args = ap.parse_args()
    sections = {"free_fall": free_fall, "spin": spin, "bars": bars, "cantilever": cantilever, "plate": plate,
                "incline": incline, "roof_wedge": roof_wedge, "impact": impact, "tetrahedral_wedge": tetrahedral_wedge,
                "sliding_wedge": sliding_wedge, "footing": footing, "tower": tower, "newmark": newmark,
                "support": support, "stages": stages}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        rep = Report(Path(tmp))
        for name, fn in sections.items():
            if not args.only or name in args.only:
                print(name, flush=True)
                fn(rep)
    if args.only:
        # Keep the other sections of the existing document.
        old = (ROOT / "docs" / "verification.md").read_text().split("\n## ")
        kept = ["## " + part for part in old[1:] if not any(part.startswith(t) for t in titles(rep))]
        rep.lines = [ln for part in kept for ln in part.rstrip("\n").split("\n") + [""]] + rep.lines
    head = ["# Verification", "",
            f"Produced by `python bench/verification.py` (nmm3d {nmm3d.__version__}, {platform.machine()}, "
            f"Python {platform.python_version()}, {time.perf_counter() - t0:.0f} s"
            + (f" for {', '.join(args.only)}; the other sections kept from the previous run" if args.only else "")
            + "). Do not edit by hand: rerun it.",
            "The fast versions of these checks run in the test suite (`crates/nmm3d-core/tests/verification_*.rs`).",
            "Closed forms are in `python/nmm3d/analytic.py`; independent references (3-D solutions computed outside nmm3d) are quoted beside each table.",
            "Contact cases checked by tests only: the sliding/toppling chart (`tests/test_toppling.py`) and the "
            "dominos run (`verification_dominos.rs`, timed in `docs/performance-contact.md`) and the dougong collapse "
            "(`verification_dougong.rs`). Block theory (`nmm3d keyblocks`) against Goodman & Shi's joint pyramids, the "
            "vector method and the NMM critical-friction studies: `tests/test_keyblocks.py` and "
            "[keyblocks-results.md](keyblocks-results.md); the thesis tunnel's roof and side-wall key blocks, limit "
            "equilibrium against per-block NMM studies: [applications/tunnel-key-blocks.md](applications/tunnel-key-blocks.md); "
            "the thesis rock slope's blocks, block theory against a per-block NMM study of the dry slope, and like for like with the layer's base held: "
            "[applications/rock-slope-loading.md](applications/rock-slope-loading.md).",
            ""]
    (ROOT / "docs" / "verification.md").write_text("\n".join(head + rep.lines))
    print("wrote docs/verification.md")


if __name__ == "__main__":
    sys.exit(main())
