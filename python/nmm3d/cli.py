"""The ``nmm3d`` command line. Exit status: 0 done, 2 invalid input, 1 the run failed or did not converge,
130 interrupted (Ctrl-C; the outputs so far and ``summary.json`` are written)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from nmm3d import _core
from nmm3d.scenario import load
from nmm3d.summary import Check, RunSummary
from nmm3d.units import unit

# Defined once, in the native module (nmm3d_core::error::exit).
EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_INTERRUPTED = _core.EXIT_OK, _core.EXIT_FAILED, _core.EXIT_INPUT, _core.EXIT_INTERRUPTED


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="nmm3d", description="3-D numerical manifold method for jointed rock")
    p.add_argument("--version", action="version", version=f"nmm3d {_core.__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scenario and write its outputs")
    run.add_argument("file", type=Path)
    run.add_argument("--out", type=_directory, required=True, help="output directory")
    run.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE",
                     help="override a scalar or array, e.g. joint.smooth.friction_angle=24")
    run.add_argument("--quiet", action="store_true", help="no progress line")
    run.add_argument("--overwrite", action="store_true",
                     help="replace the outputs of an earlier run in --out (without it such a directory is refused)")
    run.add_argument("--resume", action="store_true",
                     help="continue the run whose checkpoint.json is in --out (after Ctrl-C, a crash, or to go on "
                          "past its duration with --set analysis.duration=...)")
    check = sub.add_parser("check", help="validate a scenario without running it")
    check.add_argument("file", type=Path)
    check.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    blocks = sub.add_parser("blocks", help="cut the rock mass into blocks and write the geometry outputs only")
    blocks.add_argument("file", type=Path)
    blocks.add_argument("--out", type=_directory, required=True, help="output directory")
    blocks.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    keyblocks = sub.add_parser("keyblocks", help="block theory on the cut rock mass: removable blocks, failure "
                               "mode, factor of safety and critical friction angle of each block with a free face")
    keyblocks.add_argument("file", type=Path)
    keyblocks.add_argument("--out", type=_directory, required=True, help="output directory")
    keyblocks.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    study = sub.add_parser("study", help="run the scenario's [study] (critical friction, strength reduction, sweep, "
                           "Monte-Carlo) on Dask")
    study.add_argument("file", type=Path)
    study.add_argument("--out", type=_directory, required=True, help="study directory (rerun with the same one to resume)")
    study.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    study.add_argument("--workers", type=int, default=None, help="local worker processes (default: the cores)")
    study.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="a running Dask scheduler, e.g. tcp://host:8786 (instead of local workers)")
    study.add_argument("--quiet", action="store_true", help="no progress")
    plot = sub.add_parser("plot", help="draw a run's monitored histories, and its time step, unbalanced force and "
                          "energy, to PNG")
    plot.add_argument("dir", type=Path)
    plot.add_argument("--out", type=Path, default=None,
                      help="PNG file of the histories (default DIR/history.png; the diagnostics go beside it)")
    return p


USED_MARKERS = ("summary.json", "history.csv", "checkpoint.json")
"""Files whose presence says a directory holds an earlier run's outputs."""


def _directory(text: str) -> Path:
    """An output directory; an empty name would silently mean the working directory."""
    if not text.strip():
        raise argparse.ArgumentTypeError("the output directory must not be empty (use . for this one)")
    return Path(text)


def _run(args: argparse.Namespace) -> int:
    scenario = load(args.file, args.overrides)
    used = [m for m in USED_MARKERS if (args.out / m).exists()]
    if used and not (args.overwrite or args.resume):
        print(f"nmm3d: {args.out} holds the outputs of an earlier run ({', '.join(used)}): add --overwrite to "
              f"replace them, --resume to continue that run, or choose another --out", file=sys.stderr)
        return EXIT_INPUT
    try:
        result = scenario.run(args.out, progress=not args.quiet, resume=args.resume)
    except KeyboardInterrupt as e:
        print(f"nmm3d: {e}", file=sys.stderr)
        print(f"summary.json (status \"interrupted\"), the outputs so far and checkpoint.json are in {args.out}; "
              f"continue with: nmm3d run {args.file} --out {args.out} --resume", file=sys.stderr)
        return EXIT_INTERRUPTED
    s = result.run_summary
    line = (f"{s.status}: {s.message} — {s.steps} steps, t = {s.time:.6g} s, "
            f"{s.manifold_elements} MEs, {s.dofs} DOFs, {s.wall_seconds:.2f} s wall")
    for warning in _warnings(s):
        print(f"nmm3d: warning: {warning}", file=sys.stderr)
    if result.completed:
        print(line)
        _print_answers(s)
        return EXIT_OK
    what = "not converged" if s.status == "not_converged" else "run failed"
    print(f"nmm3d: {what}: {s.message}", file=sys.stderr)
    print(f"outputs up to the last good step are in {args.out}", file=sys.stderr)
    return EXIT_FAILED


def _warnings(s: RunSummary) -> list[str]:
    """The summary's warnings: an initial equilibrium not reached, an energy balance off, a
    block faster than a free fall."""
    found = [
        s.initial_equilibrium.warning if s.initial_equilibrium else None,
        s.energy.warning if s.energy else None,
        s.free_fall.warning if s.free_fall else None,
    ]
    return [w for w in found if w]


MAX_FINAL_LINES = 12
"""Final monitor values printed after a run (all of them are in summary.json)."""


def _print_answers(s: RunSummary) -> None:
    """The final monitored values, then each ``[[expect]]`` beside its reference."""
    for key in list(s.final)[:MAX_FINAL_LINES]:
        value = s.final[key]
        print(f"  {key} = {'undefined' if value is None else f'{value:.6g} {unit(key)}'.rstrip()}")
    if len(s.final) > MAX_FINAL_LINES:
        print(f"  … {len(s.final) - MAX_FINAL_LINES} more in summary.json")
    for c in s.checks:
        print(_check_line(c))


def _check_line(c: Check) -> str:
    u = unit(c.quantity)
    with_unit = lambda x: f"{x:.6g} {u}".rstrip()  # noqa: E731
    value = "missing" if c.value is None else with_unit(c.value)
    verdict = "within" if c.passed else "OUTSIDE"
    source = f" ({c.source})" if c.source else ""
    bounds = [f"≥ {with_unit(c.at_least)}" if c.at_least is not None else "",
              f"≤ {with_unit(c.at_most)}" if c.at_most is not None else ""]
    bounds_text = " and ".join(b for b in bounds if b)
    if c.reference is None:
        return f"check {c.quantity} = {value}; expected {bounds_text}{source}: {'yes' if c.passed else 'NO'}"
    diff = "" if c.relative_difference is None else f", {100 * c.relative_difference:+.2f} %"
    bound = f"{100 * c.tolerance:g} %" if c.reference != 0 else f"{c.absolute_tolerance:g} {u}".rstrip()
    also = f", and {bounds_text}" if bounds_text else ""
    return (f"check {c.quantity} = {value}; reference {with_unit(c.reference)}{source}{diff}: "
            f"{verdict} {bound}{also}")


def _check(args: argparse.Namespace) -> int:
    scenario = load(args.file, args.overrides)
    d = scenario.to_dict()
    if "study" in d:
        from nmm3d.study.spec import parse

        parse(d, str(args.file))
    model = scenario.check()["stages"]
    blocks, mes = ", ".join(str(s["blocks"]) for s in model), max(s["manifold_elements"] for s in model)
    built = (f"the model: {blocks} blocks, {mes} MEs" if len(model) == 1
             else f"the model by stage: {blocks} blocks, up to {mes} MEs")
    print(f"{args.file}: valid ({len(d['body'])} bodies, {len(d['material'])} materials, "
          f"{len(d['monitor'])} monitors; {built})")
    return EXIT_OK


def _blocks(args: argparse.Namespace) -> int:
    from nmm3d.stereonet import plot_stereonet

    scenario = load(args.file, args.overrides)
    r = scenario.write_blocks(args.out)
    print(f"{r['blocks']} blocks ({r['non_convex_blocks']} non-convex, {r['pieces']} convex pieces), "
          f"total volume {r['total_volume']:.6g} m³ (mean {r['mean_volume']:.6g}, min {r['min_volume']:.6g}, "
          f"max {r['max_volume']:.6g} m³)")
    print(f"smallest block: id {r['smallest_block']} ({r['min_volume']:.6g} m³); excavated volume "
          f"{r['excavated_volume']:.6g} m³; slivers merged {r['slivers_merged']}, dropped {r['slivers_dropped']}; "
          f"cut in {r['cutting_seconds']:.2f} s")
    plot_stereonet(scenario.to_dict(), args.out / "stereonet.png", title=str(args.file.name))
    print(f"wrote {args.out / 'blocks.csv'}, {args.out / 'blocks.vtu'} and {args.out / 'stereonet.png'}")
    return EXIT_OK


def _keyblocks(args: argparse.Namespace) -> int:
    from nmm3d.key_blocks import keyblocks

    result = keyblocks(load(args.file, args.overrides))
    try:
        written = result.write(args.out)
    except OSError as e:
        print(f"nmm3d: cannot write the key-block outputs to {args.out}: {e}", file=sys.stderr)
        return EXIT_FAILED
    key = result.key_blocks()
    print(f"{len(result.blocks)} blocks with a free face, {sum(b.removable for b in result.blocks)} removable, "
          f"{len(key)} key blocks (fall or slide under their weight)")
    if key:
        print(f"{'id':>5} {'JP':>6} {'mode':<19} {'FS':>7} {'phi_c [deg]':>11} {'volume [m3]':>11} "
              f"{'trend/plunge [deg]':>18}  sliding on")
    for b in key:
        m = b.mode
        trend, plunge = b.trend_plunge()
        warn = "  (weight line leaves its base: may topple)" if b.rotation_warning else ""
        print(f"{b.id:>5} {b.joint_pyramid:>6} {m.mode:<19} {m.factor_of_safety:>7.3f} "
              f"{m.critical_friction_angle:>11.3f} {b.volume:>11.4g} {trend:>8.1f}/{plunge:<9.1f} "
              f"{' + '.join(b.planes[k].label for k in m.planes)}{warn}")
    print("wrote " + ", ".join(str(p) for p in written))
    return EXIT_OK


def _study(args: argparse.Namespace) -> int:
    from nmm3d.study.driver import Study, describe

    if args.workers is not None and args.workers < 1:
        print(f"nmm3d: invalid input:\n--workers: must be at least 1, got {args.workers}", file=sys.stderr)
        return EXIT_INPUT
    result = Study(args.file, args.out, args.overrides).run(args.workers, args.scheduler, progress=not args.quiet)
    print(describe(result))
    print(f"wrote {args.out / 'study.json'}, {args.out / 'study.csv'} and {args.out / 'study.png'}")
    return EXIT_OK if result.status in ("completed", "out_of_range") else EXIT_FAILED


def _plot(args: argparse.Namespace) -> int:
    from nmm3d.plot import plot_diagnostics, plot_history

    if not (args.dir / "history.csv").is_file():
        print(f"nmm3d: {args.dir} has no history.csv (is it a run's output directory?)", file=sys.stderr)
        return EXIT_INPUT
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
    try:
        print(plot_history(args.dir, args.out))
        if (args.dir / "diagnostics.csv").is_file():
            beside = None if args.out is None else args.out.with_name(args.out.stem + "_diagnostics.png")
            print(plot_diagnostics(args.dir, beside))
    except (UnicodeDecodeError, ValueError, IndexError, KeyError) as e:
        print(f"nmm3d: {args.dir}: its tables are not the ones nmm3d writes ({type(e).__name__}: {e})",
              file=sys.stderr)
        return EXIT_INPUT
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    args = _parser().parse_args(argv)
    handlers = {"run": _run, "check": _check, "blocks": _blocks, "keyblocks": _keyblocks, "study": _study,
                "plot": _plot}
    try:
        return handlers[args.command](args)
    except _core.ScenarioError as e:
        print(f"nmm3d: invalid input:\n{e}", file=sys.stderr)
        return e.exit_code
    except _core.NmmError as e:
        print(f"nmm3d: {e}", file=sys.stderr)
        return e.exit_code
    except KeyboardInterrupt:
        print("nmm3d: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        # The reader of our output went away (`nmm3d blocks … | head`): stop quietly.
        sys.stderr.close()
        return EXIT_OK
    except OSError as e:
        # A picture or table Python writes (a stereonet, a plot) on a full or read-only disk.
        where = f" {e.filename}" if e.filename else ""
        print(f"nmm3d: cannot write{where}: {e.strerror or e}", file=sys.stderr)
        return EXIT_FAILED


if __name__ == "__main__":
    sys.exit(main())
