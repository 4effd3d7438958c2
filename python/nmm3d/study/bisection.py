"""Bracketing search for the value where runs turn unstable, for several targets at once.

A target is one yes/no question asked of every run ("does any monitored block move more than D?",
"does block 7?"). Along the varied value x each target is assumed monotone: unstable on one side
of a critical value, stable on the other. The search starts from the two ends of the range and
then puts ``points_per_round`` equally spaced points inside the widest bracket still wider than
the tolerance (k-section: the points of one round run in parallel). The points depend only on
the outcomes, never on how many workers there are, so a study gives the same answer on one
worker or on a cluster.
"""

from __future__ import annotations

from dataclasses import dataclass

Outcome = dict[str, bool | None]  # target → unstable (None: the run could not tell)


@dataclass(frozen=True)
class Bracket:
    """Where one target turns unstable."""

    status: str                 #: "converged", "open", "stable_in_range", "unstable_in_range", "undetermined"
    unstable: float | None      #: the value nearest the boundary that was unstable
    stable: float | None        #: the value nearest the boundary that was stable
    non_monotone: bool = False  #: an unstable run lies beyond a stable one

    @property
    def value(self) -> float | None:
        """The middle of the bracket (None when the boundary is outside the range)."""
        if self.unstable is None or self.stable is None:
            return None
        return 0.5 * (self.unstable + self.stable)

    def as_dict(self) -> dict:
        return {"status": self.status, "value": self.value, "bracket": _ordered(self.unstable, self.stable),
                "non_monotone": self.non_monotone}


def _ordered(a: float | None, b: float | None) -> list[float | None]:
    if a is None or b is None:
        return [a, b]
    return [min(a, b), max(a, b)]


class BracketSearch:
    """The points to run next, given what the runs so far said.

    ``unstable_below``: True when small values fail (friction angle), False when large ones do
    (strength-reduction factor).
    """

    def __init__(self, low: float, high: float, tolerance: float, points_per_round: int, unstable_below: bool) -> None:
        self.low, self.high = low, high
        self.tolerance = tolerance
        self.k = points_per_round
        self.sign = 1.0 if unstable_below else -1.0
        self.stuck: set[str] = set()

    def first_points(self) -> list[float]:
        return [self.low, self.high]

    def bracket(self, target: str, observations: dict[float, Outcome]) -> Bracket:
        """The bracket of one target (x values in the caller's units)."""
        ys = {self.sign * x: o.get(target) for x, o in observations.items()}
        stable = [y for y, u in ys.items() if u is False]
        s = min(stable) if stable else None
        unstable = [y for y, u in ys.items() if u is True and (s is None or y < s)]
        u = max(unstable) if unstable else None
        non_monotone = s is not None and any(v is True and y > s for y, v in ys.items())
        back = (lambda y: None if y is None else self.sign * y)
        if u is None and s is None:
            status = "undetermined"
        elif u is None:
            status = "stable_in_range"
        elif s is None:
            status = "unstable_in_range"
        elif s - u <= self.tolerance * (1.0 + 1e-9):
            status = "converged"
        else:
            status = "undetermined" if target in self.stuck else "open"
        return Bracket(status, back(u), back(s), non_monotone)

    def next_points(self, targets: list[str], observations: dict[float, Outcome]) -> list[float]:
        """Points inside the widest open bracket; [] when every target is resolved."""
        open_ = [(self._width(t, observations), t) for t in sorted(targets)
                 if self.bracket(t, observations).status == "open"]
        if not open_:
            return []
        _, target = max(open_, key=lambda wt: wt[0])
        b = self.bracket(target, observations)
        u, s = self.sign * b.unstable, self.sign * b.stable
        points = [self.sign * (u + (s - u) * j / (self.k + 1)) for j in range(1, self.k + 1)]
        fresh = [x for x in points if all(abs(x - o) > 1e-12 * max(1.0, abs(x)) for o in observations)]
        if not fresh:  # the runs inside this bracket could not tell: give it up, keep the rest
            self.stuck.add(target)
            return self.next_points(targets, observations)
        return fresh

    def _width(self, target: str, observations: dict[float, Outcome]) -> float:
        b = self.bracket(target, observations)
        return abs(b.stable - b.unstable)
