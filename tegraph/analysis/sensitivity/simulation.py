"""A part of the schedule on processors decided by simulating it along a line, within budgets.

Where the exact test of periodic units does not decide a part
(:mod:`tegraph.analysis.sensitivity.levels`), the engine itself
(:func:`~tegraph.analysis.processors._engine.simulate_part`) runs the part
on affine times ``c + k·t`` (:mod:`.affine`), t the factor of the line
``θ(t) = base + t·direction``: :func:`on_line` puts the varied durations,
periods and delays in the part's data, :func:`moved_data` first rebuilds it
where a period moves (rate-monotonic priorities follow the order of the
periods), :func:`simulate` runs it within the :class:`Budget` and
:func:`verdict` reads §4b's verdict off the run. Every comparison of affine
times is recorded in the :class:`~.affine.Cut`: the verdict holds on its
whole interval, the interval of constant event order.

See Also
--------
tegraph.analysis.sensitivity.parts : which parts a line moves, and how each is decided.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from ...model.build import build_teg
from ...model.platform import platform_of
from ...model.skeleton import Skeleton
from ..processors._engine import PartData, PartResult, simulate_part
from ..processors.schedule import _Net, _overrun_to_come
from .affine import Cut, lin
from .parameters import Parameter, skeleton_at
from .partition import Part
from .walk import Outcome

__all__ = ["RUN_BUDGETS", "Budget", "line_value", "moved_data", "on_line", "simulate",
           "verdict"]

RUN_BUDGETS = 20
"""The whole sensitivity on processors fires at most ``RUN_BUDGETS × max_events``
events (the nominal verdict included)."""


@dataclass
class Budget:
    """Event firings of the simulations on processors, bounded three ways.

    - one simulation of a part at one point: at most ``max_events``;
    - one figure (the scaling factor, or one margin), all its points: at most
      ``max_events`` in all;
    - the whole run (the nominal verdict and every figure): at most
      :data:`RUN_BUDGETS` ``× max_events``.

    A simulation cut by a budget is undecided, and its reason names it.
    """

    max_events: int
    total: int = 0
    spent: int = 0
    figure_left: int | None = None
    """Firings the current figure may still spend (None: no figure, the nominal verdict)."""

    def __post_init__(self) -> None:
        self.total = self.total or RUN_BUDGETS * self.max_events

    @property
    def run_left(self) -> int:
        """The event firings the whole run may still spend."""
        return max(self.total - self.spent, 0)

    def start_figure(self) -> None:
        """Give the next figure its own share of event firings."""
        self.figure_left = self.max_events

    def cap(self) -> tuple[int, str]:
        """The firings the next simulation may spend, and the reason it stops there."""
        out = (self.max_events, self.cap_text())
        # A simulation given b firings fires at most b + 1 (it stops past b).
        if self.figure_left is not None and self.figure_left - 1 < out[0]:
            out = (max(self.figure_left - 1, 0), f"this figure's budget of "
                   f"{self.max_events:,} event firings (`max_events`) is spent")
        if self.run_left - 1 < out[0]:
            out = (max(self.run_left - 1, 0), f"the run's budget of {self.total:,} event "
                   f"firings on processors ({self.total // self.max_events} × `max_events`) "
                   "is spent")
        return out

    def cap_text(self) -> str:
        """What a figure left undecided by this budget says."""
        return f"no periodic regime within {self.max_events:,} event firings (`max_events`)"

    def spend(self, fired: int) -> None:
        """Count ``fired`` event firings against the run and the current figure."""
        self.spent += fired
        if self.figure_left is not None:
            self.figure_left = max(self.figure_left - fired, 0)


def line_value(j: int, nominal: Sequence[Fraction], base: Mapping[int, Fraction],
               direction: Mapping[int, Fraction]) -> tuple[Fraction, Fraction]:
    """Parameter j on the line, ``c + k·t`` as (c, k): its nominal value where ``base``
    does not give it, fixed where ``direction`` does not move it.

    >>> line_value(1, [Fraction(2), Fraction(5)], {}, {1: Fraction(1)})
    (Fraction(5, 1), Fraction(1, 1))
    """
    return base.get(j, nominal[j]), direction.get(j, Fraction(0))


def on_line(data: PartData, part: Part, params: Sequence[Parameter],
            nominal: Sequence[Fraction], base: Mapping[int, Fraction],
            direction: Mapping[int, Fraction], net: _Net, cut: Cut) -> PartData:
    """The part's data with each varied duration, period and delay on the line
    (:func:`line_value`), as affine times on ``net``'s scale (comparisons recorded
    in ``cut``)."""
    scale = net.scale
    index = {p.owner: j for j, p in enumerate(params) if p.kind == "duration"}
    duration = list(data.duration)
    for i, t in enumerate(part.names):
        if t in index:
            c, k = line_value(index[t], nominal, base, direction)
            duration[i] = lin(c * scale, k * scale, cut)
    hold = list(data.p_hold)
    clocks = net.teg.attrs["clocks"]
    local = {e: i for i, e in enumerate(part.events)}
    for j, p in enumerate(params):
        if p.kind != "period":
            continue
        tick = local.get(clocks[p.owner])
        if tick is None:
            continue
        c, k = line_value(j, nominal, base, direction)
        for q, (s, d) in enumerate(zip(data.p_src, data.p_dst)):
            if s == d == tick:
                hold[q] = lin(c * scale, k * scale, cut)
    for j, places in part.delays.items():
        c, k = line_value(j, nominal, base, direction)
        for q in places:
            hold[q] = lin(c * scale, k * scale, cut)
    return dataclasses.replace(data, duration=duration, p_hold=hold)


def moved_data(part: Part, skeleton: Skeleton, params: Sequence[Parameter],
               nominal: Sequence[Fraction], groups: Sequence[Any], net: _Net,
               base: dict[int, Fraction], direction: dict[int, Fraction],
               cut: Cut) -> PartData:
    """The part's data with the platform of the periods in the cut's interval.

    Rate-monotonic priorities depend on the order of the periods: every pair
    of clock periods is compared (recorded in the cut), and the platform is
    taken at a point of the interval where that order holds. ``net`` is the
    nominal one, whose scale the data is given back in.
    """
    moving = {params[j].owner: j for j, k in direction.items()
              if k and params[j].kind == "period"}
    # Each clock's period on the line, c + k·t as (c, k) (k = 0: it stays).
    periods = {name: (line_value(moving[name], nominal, base, direction) if name in moving
                      else (clock.period, Fraction(0)))
               for name, clock in skeleton.clocks.items()}
    names = list(periods)
    for a in range(len(names)):
        for b in range(a + 1, len(names)):
            (c1, k1), (c2, k2) = periods[names[a]], periods[names[b]]
            cut.sign(c1 - c2, k1 - k2)
    rep = _inside(cut, periods.values())
    values = {j: base.get(j, nominal[j]) + rep * k for j, k in direction.items()}
    moved = skeleton_at(skeleton, params, values)
    platform = platform_of(moved, groups)
    moved_net = _Net(moved, build_teg(moved), groups, platform)
    for data, names_, _, _ in moved_net.parts():
        if names_[0] == part.names[0]:
            scale = Fraction(net.scale, moved_net.scale)
            # back to the nominal scale, in which the parametric values are given
            return dataclasses.replace(
                data, p_hold=[h * scale for h in data.p_hold],
                p_init=[a * scale for a in data.p_init],
                duration=[x * scale for x in data.duration])
    raise AssertionError("the parts do not depend on the periods")


def _inside(cut: Cut, periods: Iterable[tuple[Fraction, Fraction]]) -> Fraction:
    """The point of the line where the cut is taken: ``at``, or just beside it (side
    +1/-1), halfway to the interval's end and inside the periods' domain.

    A period is > 0 (the model refuses 0): on the line, c + k·t > 0 bounds t below
    where k > 0 and above where k < 0, so the point beside ``at`` stays inside
    (at - 1 could be a period of 0 or less, which no schedule has).

    >>> from fractions import Fraction as F
    >>> _inside(Cut(F(1), -1), [(F(0), F(1))])  # the period t itself: halfway to 0
    Fraction(1, 2)
    """
    periods = list(periods)
    lo = max([-c / k for c, k in periods if k > 0]
             + ([cut.lo] if cut.lo is not None else []), default=None)
    hi = min([-c / k for c, k in periods if k < 0]
             + ([cut.hi] if cut.hi is not None else []), default=None)
    if cut.side > 0:
        return (cut.at + hi) / 2 if hi is not None else cut.at + 1
    if cut.side < 0:
        return (cut.at + lo) / 2 if lo is not None else cut.at - 1
    return cut.at


def simulate(data: PartData, budget: Budget, max_events: int, limit: int | None = None,
             progress: Callable[[], None] | None = None) -> tuple[PartResult, str]:
    """The part simulated within the budgets, and which one stopped it (in words).

    Past an overrun the engine still looks for a regime (its figures need it)
    for as many firings again, and at least a tenth of its budget
    (``AFTER_OVERRUN``); a verdict needs none of it: budgets grow tenfold from
    1,000, so an early overrun costs little and the whole budget is spent at
    most once more.
    Every firing counts against the figure's and the run's budgets; ``progress``
    is called after each run of the engine.
    """
    top = max_events if limit is None else min(limit, max_events)
    cap, why_cut = budget.cap()
    firings = min(1_000, top, cap)
    result = PartResult()
    while firings > 0:
        result = simulate_part(data, firings, keep_intervals=False)
        budget.spend(result.fired)
        if progress is not None:
            progress()
        if result.overrun_at or result.regime is not None or firings >= top:
            break
        cap, why = budget.cap()
        nxt = min(firings * 10, top, cap)
        if nxt <= firings:  # the figure's or the run's budget is spent
            why_cut = why
            break
        firings = nxt
    if firings >= max_events:
        why_cut = budget.cap_text()
    return result, why_cut


def verdict(r: PartResult, d: PartData, part: Part, cut: Cut, why_cut: str,
            net: _Net) -> Outcome:
    """§4b's verdict of one part from its simulation (as ``schedule._Outcome``);
    ``why_cut``: why a run without regime stopped."""
    names = part.names
    late = [(k, names[j]) for j, k in r.overrun_at.items()]
    if late:
        k, task = min(late)
        return Outcome(False, cut, ("overrun", task, k))
    if r.regime is None:
        return Outcome(None, cut, ("undecided", why_cut))
    if r.regime[0] == "stop":
        return Outcome(True, cut)
    t1, t2, old, new, growing = r.regime
    if growing:
        p = min(growing)
        g = part.places[p]
        names_ = net.teg.transition_names
        return Outcome(False, cut, ("grows", f"{names_[net.src[g]]} -> "
                                    f"{names_[net.dst[g]]}"))
    fired = [b - a for a, b in zip(old.fired, new.fired)]
    compute_of = {j: e for e, j in enumerate(d.compute_task) if j >= 0}
    tick_of = {j: e for e, ts in d.watched.items() for j in ts}
    for j, t in enumerate(names):
        if fired[compute_of[j]] == 0 and new.pending[j] >= 0:
            return Outcome(False, cut, ("starved", t))
    coming = []
    for j in r.tick_log:
        last = d.end_event[j]
        ends = new.finished[j] - old.finished[j] if last is None else fired[last]
        at = _overrun_to_come(r.tick_log[j], t1, t2, fired[tick_of[j]], ends)
        if at is not None:
            coming.append((at, names[j]))
    if coming:
        k, task = min(coming)
        return Outcome(False, cut, ("overrun", task, k))
    return Outcome(True, cut)
