"""The run summary, ``summary.json``, as typed dataclasses.

The fields mirror the Rust struct ``nmm3d_core::output::summary::RunSummary`` one to one
(``tests/test_summary.py`` fails when they drift); the user guide documents each. Read one with
``Result.run_summary`` or ``RunSummary.from_dict(json.load(f))``.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from dataclasses import dataclass
from typing import Any, Literal

Status = Literal["completed", "interrupted", "not_converged", "failed"]


@dataclass(frozen=True)
class EnergySummary:
    """The energy accounts at the end [J] and how well they balanced over the run."""

    kinetic: float
    elastic: float
    external_work: float
    contact: float
    friction_dissipation: float
    numerical_dissipation: float
    contact_event_dissipation: float
    error: float
    #: largest balance error over the run relative to the largest account of the run
    max_error_ratio: float
    #: when that largest error occurred [s]
    max_error_time: float
    #: set when ``max_error_ratio`` or ``max_gain_ratio`` exceeds 5 %
    warning: str | None
    #: taken by the contact dashpots (``contact.damping_ratio``); 0 in summaries before them
    damping_dissipation: float = 0.0
    #: largest kinetic and strain energy held beyond what the loads and the start gave
    #: (energy from nowhere) relative to the largest account; 0 in summaries before it
    max_gain_ratio: float = 0.0
    #: when that largest gain occurred [s]
    max_gain_time: float = 0.0


@dataclass(frozen=True)
class BlockCuts:
    """A block (id of ``blocks.csv``), its body and the step cuts it was responsible for."""

    block: int
    body: str
    cuts: int


@dataclass(frozen=True)
class DtBin:
    """Accepted steps with ``from_ ≤ Δt < to`` [s] (``from`` in ``summary.json``)."""

    from_: float
    to: float
    steps: int


@dataclass(frozen=True)
class StepDiagnostics:
    """Step cuts by reason (the names of ``cuts.csv``) and block, accepted steps by Δt."""

    cuts_by_reason: dict[str, int]
    blocks_most_cut: list[BlockCuts]
    dt_histogram: list[DtBin]


@dataclass(frozen=True)
class Check:
    """One ``[[expect]]`` judged on the final value."""

    quantity: str
    value: float | None
    reference: float | None
    #: (value − reference) / reference; ``None`` for a zero or missing reference
    relative_difference: float | None
    tolerance: float
    absolute_tolerance: float
    at_least: float | None
    at_most: float | None
    passed: bool
    source: str


@dataclass(frozen=True)
class InitialEquilibrium:
    """The initial static equilibrium: iterations and the unbalanced-force ratio reached."""

    steps: int
    unbalanced_force_ratio: float
    #: within ``analysis.equilibrium_tolerance`` (older summaries lack it: taken as true)
    converged: bool = True
    #: when not converged: the blocks nothing holds, still moving at its last step
    warning: str | None = None


@dataclass(frozen=True)
class ResumedFrom:
    """The checkpoint (step, time [s]) a resumed run continued from."""

    step: int
    time: float


@dataclass(frozen=True)
class StageSummary:
    """One stage of a staged analysis as it ran (a row of ``stages.csv``)."""

    name: str
    status: Status
    message: str
    #: simulated time at the stage's start and end [s]
    start_time: float
    end_time: float
    #: accepted steps before the stage and at its end
    start_step: int
    end_step: int
    #: blocks of the stage's model
    blocks: int
    unbalanced_force_ratio: float | None
    #: wall-clock seconds, building the stage's model included
    wall_seconds: float


@dataclass(frozen=True)
class FreeFallSummary:
    """The free-fall bound: no block's centre of mass faster than a body falling freely from
    the highest point of the moving blocks at the start down to the block's lowest point,
    starting at the fastest block's initial speed."""

    #: largest speed over bound of any block over the run (> 1: past it)
    max_ratio: float
    #: that block (id of ``blocks.csv``) and its body
    block: int
    body: str
    #: when [s], its centre of mass's speed then and its bound [m/s]
    time: float
    speed: float
    bound: float
    #: set when a block went past the bound in a run that gravity alone drives
    warning: str | None = None


@dataclass(frozen=True)
class RunSummary:
    """Contents of ``summary.json``; ``None`` where a run could not define a value."""

    status: Status
    message: str
    steps: int
    #: simulated time at the end [s]
    time: float
    wall_seconds: float
    blocks: int
    manifold_elements: int
    physical_covers: int
    dofs: int
    #: deepest overlap of a contact point at the end of an accepted step [m]
    max_penetration: float
    max_contact_points: int
    open_close_iterations: int
    step_cuts: int
    penetration_cuts: int
    penalty_raises: int
    equilibrium_iterations: int
    missed_overlaps: int
    pattern_rebuilds: int
    factor_nonzeros: int
    factorizations: int
    krylov_solves: int
    krylov_iterations: int
    krylov_failures: int
    unbalanced_force_ratio: float | None
    #: ``None`` for a static run
    energy: EnergySummary | None
    step_diagnostics: StepDiagnostics
    stress_sign: str
    #: seconds per phase
    timings: dict[str, float]
    #: monitored values of the last history row
    final: dict[str, float | None]
    checks: list[Check]
    initial_equilibrium: InitialEquilibrium | None = None
    resumed_from: ResumedFrom | None = None
    #: the stages of a staged analysis; the counters and timings above are the last stage's
    #: model's, ``steps`` and ``time`` the whole run's
    stages: list[StageSummary] = dataclasses.field(default_factory=list)
    #: "direct" (sparse Cholesky), "amg" (multigrid-preconditioned CG) or "blocks" (CG
    #: preconditioned by the blocks and their rigid motions)
    linear_solver: str = "direct"
    #: PCG iterations of the multigrid or the block solver (0 with the direct one)
    multigrid_iterations: int = 0
    #: a static run with ``analysis.static_travel_limit`` that stopped with every other block in
    #: equilibrium: the blocks that moved beyond the limit (not held), farthest first
    not_held: list[int] = dataclasses.field(default_factory=list)
    #: the monitors of those blocks (pinned where they crossed the limit: a study judges them failed)
    not_held_monitors: list[str] = dataclasses.field(default_factory=list)
    #: the block closest to (or past) the free-fall bound of a dynamic run under gravity;
    #: ``None`` for a static run, without gravity, or in summaries before it
    free_fall: FreeFallSummary | None = None
    #: joint pairs found again and arrivals whose force was carried (``contact.carry_joint_force``);
    #: 0 in summaries before it
    carried_joint_forces: int = 0
    #: grown or shrunk matrix patterns factorised on an earlier symbolic analysis (their entries
    #: inside its factor); 0 in summaries before it
    patterns_adopted: int = 0
    #: factorisations the direct solver made in single precision (``analysis.factor_precision``);
    #: 0 in summaries before it
    single_precision_factorizations: int = 0
    #: iterations that refined the solves on those factors to double precision
    refinement_iterations: int = 0

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> RunSummary:
        """A summary from the parsed ``summary.json``; raises ``ValueError`` naming any key that
        the dataclasses and the file do not share."""
        return _build(cls, data)


def json_name(field: str) -> str:
    """The key of a dataclass field in ``summary.json`` (``from_`` is ``from``)."""
    return field.rstrip("_")


def _build(cls: type, data: dict[str, Any]) -> Any:
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    names = {json_name(n): n for n in fields}
    unknown = set(data) - set(names)
    required = {n for n, f in fields.items() if f.default is f.default_factory is dataclasses.MISSING}
    missing = {k for k, n in names.items() if k not in data and n in required}
    if unknown or missing:
        raise ValueError(f"summary.json and {cls.__name__} differ: unknown {sorted(unknown)}, missing {sorted(missing)}")
    return cls(**{names[k]: _convert(hints[names[k]], v) for k, v in data.items()})


def _convert(hint: Any, value: Any) -> Any:
    """``value`` as ``hint`` says: dataclasses built, lists and dicts converted item by item."""
    if value is None:
        return None
    origin = typing.get_origin(hint)
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in typing.get_args(hint) if a is not type(None)]
        return _convert(inner[0], value)
    if dataclasses.is_dataclass(hint):
        return _build(hint, value)
    if origin is list:
        return [_convert(typing.get_args(hint)[0], v) for v in value]
    if origin is dict:
        return {k: _convert(typing.get_args(hint)[1], v) for k, v in value.items()}
    return value
