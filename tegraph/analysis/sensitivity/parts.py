"""The parts of a skeleton on its processors, evaluated at a point of a line of parameters.

Along a line ``θ(t) = base + t·direction`` of the parameters (all varied
durations times one factor, or one parameter alone), :class:`ProcessorLine`
decides each part of the §4b schedule (tasks joined by a group or a
processor) at a point t, or just beside it, and gives the interval around t
where the same verdict holds:

- a part with levels (each group one periodic unit of its summed work at a
  priority of its own on one processor, or a background task without clock:
  :mod:`tegraph.analysis.processors.levels`) by Lehoczky, Sha and Ding's
  exact test, level by level from the most urgent down
  (:mod:`tegraph.analysis.sensitivity.levels`): the piece of the line of the
  same verdict;
- any other part, or a point the theorem does not decide, by the engine
  itself, run on affine times (:mod:`.simulation`): the interval of constant
  event order.

The parts are read once off the nominal graph (:mod:`.partition`). Each is
decided once at the nominal values (:meth:`ProcessorLine.decide_nominal`);
a line evaluates only the parts it moves and reads the others' nominal
outcome (their events do not depend on the line's parameters). Every
simulation counts its event firings against the budgets of
:class:`~.simulation.Budget`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ...model.build import build_teg
from ...model.platform import Platform, platform_of
from ...model.skeleton import Skeleton
from ..processors._engine import PartData, PartResult
from ..processors.schedule import MAX_EVENTS, QUICK_LOOK, _Net
from .affine import Cut, lin
from .levels import LevelLine, level_line
from .parameters import DELAY_KINDS, Parameter
from .partition import Part, delay_places, nominal_parts, part_levels, zero_grows
from .simulation import Budget, line_value, moved_data, on_line, simulate, verdict
from .walk import Outcome

__all__ = ["SCHEDULE", "THEOREM", "ProcessorLine"]

THEOREM = "theorem"
SCHEDULE = "schedule"

_NAME_LOOK = 200
"""Firings simulated at a saturated point to name the task that overruns first."""


@dataclass
class ProcessorLine:
    """The parts of a skeleton on its processors, ready to be evaluated along lines.

    Built once per sensitivity analysis from the nominal analysis (its groups,
    event graph and platform); ``max_events`` is the budget of each part's
    simulation at each point.
    """

    skeleton: Skeleton
    params: Sequence[Parameter]
    nominal: list[Fraction]
    groups: Sequence[Any]
    max_events: int = MAX_EVENTS
    parts: list[Part] = field(default_factory=list)
    part_of: dict[str, int] = field(default_factory=dict)
    evaluations: int = 0
    use_theorem: bool = True
    """Decide parts with levels by Lehoczky, Sha and Ding (False: simulate them too)."""
    used: set[str] = field(default_factory=set)
    """How the parts evaluated were decided (``THEOREM``, ``SCHEDULE``)."""
    budget: Budget | None = None
    """Default ``Budget(max_events)``."""
    nominal_outcomes: list[Outcome] = field(default_factory=list)
    """Each part's outcome at the nominal values (:meth:`decide_nominal`)."""
    progress: Any = None
    """Called with no argument after each simulation (the CLI redraws its bar)."""
    nominal_platform: Platform | None = None
    """The platform (``report.platform``); default ``platform_of(skeleton, groups)``."""

    def __post_init__(self) -> None:
        # The budget in use, typed for what follows (the field is None by default).
        self.spend: Budget = self.budget if self.budget is not None else Budget(self.max_events)
        self.budget = self.spend
        sk = self.skeleton
        self.teg = build_teg(sk)
        self.platform: Platform = (platform_of(sk, self.groups) if self.nominal_platform is None
                                   else self.nominal_platform)
        self.net = _Net(sk, self.teg, self.groups, self.platform)
        self.parts.extend(nominal_parts(self.net, self.max_events))
        for i, part in enumerate(self.parts):
            for t in part.tasks:
                self.part_of[t] = i
        part_levels(self.net, self.parts)
        self._level_lines: dict[tuple, LevelLine | str] = {}
        self._duration_index = {p.owner: j for j, p in enumerate(self.params)
                                if p.kind == "duration"}
        self._delay_places = delay_places(self.net, self.params, self.parts, self.part_of)
        self.why_cut = self.spend.cap_text()
        self.zero_grows, self.whole_grows = zero_grows(self.net, self.part_of)

    def tasks_of(self, parts: list[int]) -> list[str]:
        """Every task of the skeleton joined to ``parts`` (by a group or a processor), in
        file order: tasks of duration 0 that no part simulates included."""
        mine = {t for i in parts for t in self.parts[i].tasks}
        return [t for t in self.net.tasks if t in mine]

    # ---------------------------------------------------------- which parts move
    def moving(self, direction: dict[int, Fraction]) -> list[int]:
        """The parts holding a task or clock whose parameter moves along ``direction``."""
        out: set[int] = set()
        for j, k in direction.items():
            if not k:
                continue
            p = self.params[j]
            if p.kind == "duration":
                if p.owner in self.part_of:
                    out.add(self.part_of[p.owner])
            elif p.kind in DELAY_KINDS:
                out.update(i for i, part in enumerate(self.parts)
                           if j in part.delays or j in part.delay_at_zero)
            else:
                out.update(self.part_of[t] for t, task in self.skeleton.tasks.items()
                           if task.clock == p.owner and t in self.part_of)
        return sorted(out)

    # ---------------------------------------------------------- one evaluation
    def evaluate(self, part_index: int, base: dict[int, Fraction],
                 direction: dict[int, Fraction], at: Fraction, side: int) -> Outcome:
        """The verdict of one part at ``at`` (``side``: just above/below), and its interval."""
        self.evaluations += 1
        part = self.parts[part_index]
        cut = Cut(at, side)
        periods_move = any(k and self.params[j].kind == "period" for j, k in direction.items())
        if self._delays_move(direction) is None and not periods_move and self.use_theorem:
            line = self._level_line(part_index, base, direction)
            if isinstance(line, LevelLine):
                out = line.outcome(at, side)
                if out.verdict is not None:
                    self.used.add(THEOREM)
                    return out
                why = str(out.why[1]) if out.why else "undecided"
                if why not in part.open_units:
                    part.open_units.append(why)
        unscheduled = self._unscheduled(part, direction)
        if unscheduled is not None:
            return Outcome(None, cut, ("undecided", unscheduled))
        if not periods_move:
            saturated = self._saturated(part, base, direction, cut)
            if saturated is not None:
                return saturated
        if part.too_long and not periods_move:
            return Outcome(None, cut, ("undecided", part.too_long))
        assert part.data is not None  # _unscheduled: a part with a moving task is simulated
        data = part.data
        if periods_move:
            data = moved_data(part, self.skeleton, self.params, self.nominal, self.groups,
                              self.net, base, direction, cut)
        data = self._parametric(data, part, base, direction, cut)
        return self._verdict(self._simulate(data), data, part, cut)

    def why_simulated(self, parts: Sequence[int], base: dict[int, Fraction] | None = None,
                      direction: dict[int, Fraction] | None = None) -> list[str]:
        """Why these parts were simulated rather than decided by their levels along the
        line (at the nominal values without one), in words, for a figure that stays a
        bound."""
        out = []
        for i in parts:
            part = self.parts[i]
            if direction is None:
                reason = part.levels if isinstance(part.levels, str) else None
            else:
                reason = self.level_reason(i, base or {}, direction)
            if reason is None and self.parts[i].open_units:
                reason = "; ".join(self.parts[i].open_units)
            if reason is not None:
                who = ", ".join(part.tasks[:3]) + (" ..." if len(part.tasks) > 3 else "")
                out.append(f"the part of {who} is not decided by the exact test of "
                           f"periodic units (one per group and priority): {reason}; its "
                           "schedule is simulated instead")
        return out

    def has_levels(self, part_index: int, direction: dict[int, Fraction]) -> bool:
        """Whether the part is decided by its levels along lines in ``direction`` (from 0)."""
        return self.use_theorem and self.level_reason(
            part_index, {j: Fraction(0) for j in direction}, direction) is None

    def level_reason(self, part_index: int, base: dict[int, Fraction],
                     direction: dict[int, Fraction]) -> str | None:
        """Why the part is not decided by its levels along this line (None: it is, where
        its units close their activations)."""
        if any(k and self.params[j].kind == "period" for j, k in direction.items()):
            return "a period moves along the line (the units' scheduling points move with it)"
        delay = self._delays_move(direction)
        if delay is not None:
            return delay
        line = self._level_line(part_index, base, direction)
        return line if isinstance(line, str) else None

    def _level_line(self, part_index: int, base: dict[int, Fraction],
                    direction: dict[int, Fraction]) -> LevelLine | str:
        """The part's levels along the line, made once per line."""
        key = (part_index, tuple(sorted(base.items())), tuple(sorted(direction.items())))
        if key not in self._level_lines:
            part = self.parts[part_index]
            if isinstance(part.levels, str):
                self._level_lines[key] = part.levels
            else:
                self._level_lines[key] = level_line(
                    part.levels, {t: self._duration(t, base, direction) for t in part.tasks})
        return self._level_lines[key]

    def _duration(self, task: str, base: dict[int, Fraction], direction: dict[int, Fraction]
                  ) -> tuple[Fraction, Fraction]:
        """A task's duration on the line, ``c + k·t`` as (c, k)."""
        j = self._duration_index.get(task)
        if j is None:
            return self.skeleton.tasks[task].duration, Fraction(0)
        return self._value(j, base, direction)

    def _delays_move(self, direction: dict[int, Fraction]) -> str | None:
        """Why the levels do not decide along a line on which a delay moves (None: no
        delay moves): a unit is its group's summed work, released at its tick, which a
        delay between two of its jobs would hold back."""
        moving = [self.params[j].name for j, k in direction.items()
                  if k and self.params[j].kind in DELAY_KINDS and self._delay_places.get(j)]
        if moving:
            return (f"{moving[0]} moves along the line (a periodic unit takes no delay "
                    "between its jobs)")
        return None

    def _unscheduled(self, part: Part, direction: dict[int, Fraction]) -> str | None:
        """Why the schedule of the part cannot be simulated along the line: a moving task
        has duration 0 at the nominal values, with its events at time 0 only (its schedule
        of a positive duration is not built), or so has an event a moving delay holds
        back; None: it can."""
        moving = {self.params[j].owner for j, k in direction.items()
                  if k and self.params[j].kind == "duration"}
        names = set(part.names)
        for t in part.tasks:
            if t in moving and t not in names:
                return (f"{t} has duration 0 at the nominal values and its events fire at "
                        "time 0 only there; its schedule with a positive duration is not "
                        "simulated")
        for j, k in direction.items():
            if k and j in part.delay_at_zero:
                return (f"{part.delay_at_zero[j]} holds {self.params[j].name}, and its events "
                        "fire at time 0 only at the nominal values; its schedule with a "
                        "positive delay is not simulated")
        return None

    def _saturated(self, part: Part, base: dict[int, Fraction],
                   direction: dict[int, Fraction], cut: Cut) -> Outcome | None:
        """A processor asked for more than all its time: proven not schedulable.

        Schedulable (§4b) implies every group keeps pace with its clock: each
        task of a group with one clock of period T runs once per T in the
        regime, so its processor is busy at least ``Σ duration / T`` of the
        time, which cannot pass 1 (tasks of other groups only add work). The
        sum is affine along the line: where it passes 1 is recorded in the
        cut, so the walk stops exactly at the point where the load reaches 1,
        which no simulation just beyond could prove (the schedule falls behind
        by ε per period there, with no finite regime on the germ).
        """
        if part.data is None:
            return None
        index = {p.owner: j for j, p in enumerate(self.params) if p.kind == "duration"}
        load: dict[str, Any] = {}
        for t in part.names:
            group = self.groups[self.net.group_of[t]]
            if len(group.clocks) != 1:
                continue
            period = self.skeleton.clocks[group.clocks[0]].period
            c, k = (self._value(index[t], base, direction) if t in index
                    else (self.skeleton.tasks[t].duration, Fraction(0)))
            proc = self.platform.processor_of[t]
            load[proc] = load.get(proc, Fraction(0)) + lin(c / period, k / period, cut)
        if not any(work > 1 for work in load.values()):
            return None
        proc = next(p for p, work in load.items() if work > 1)
        # Proven; a short look names the task that overruns first, if one does
        # early (also a proof, on the same cut).
        data = self._parametric(part.data, part, base, direction, cut)
        look = self._simulate(data, _NAME_LOOK)
        if look.overrun_at:
            return self._verdict(look, data, part, cut)
        return Outcome(False, cut, ("saturated", proc))

    def _simulate(self, data: PartData, limit: int | None = None) -> PartResult:
        """The part simulated within the budgets (:func:`~.simulation.simulate`);
        ``self.why_cut`` says which one stopped it."""
        self.used.add(SCHEDULE)
        result, self.why_cut = simulate(data, self.spend, self.max_events, limit, self.progress)
        return result

    def decide_nominal(self, live: bool = True) -> tuple[bool | None, Outcome | None]:
        """Each part at the nominal values, once; the skeleton's verdict and its reason.

        ``live``: the skeleton is live (spec §4); not live is not schedulable
        (§4b). Returns (verdict, the outcome of the first part that is not
        schedulable, or undecided; None when all are). Parts are decided
        smallest first, as ``schedule_on_processors`` does; a part with levels
        by the exact test of its units (at any hyperperiod).
        """
        cut = Cut(Fraction(0), 0)
        outcomes: list[Outcome] = [Outcome(True, cut)] * len(self.parts)
        size = [0 if part.data is None else part.data.n_events for part in self.parts]
        for i in sorted(range(len(self.parts)), key=size.__getitem__):
            outcomes[i] = self._nominal_part(self.parts[i])
        for i, why in self.zero_grows.items():
            if outcomes[i].verdict is not False:
                outcomes[i] = Outcome(False, cut, ("grows", why))
        self.nominal_outcomes = outcomes
        if not live:
            return False, Outcome(False, cut, ("not live", None))
        bad = [o for o in outcomes if o.verdict is False] + [o for o in outcomes
                                                             if o.verdict is None]
        if self.whole_grows is not None and not any(o.verdict is False for o in outcomes):
            bad.insert(0, Outcome(False, cut, ("grows", self.whole_grows)))
        if not bad:
            return True, None
        return bad[0].verdict, bad[0]

    def _nominal_part(self, part: Part) -> Outcome:
        cut = Cut(Fraction(0), 0)
        if self.use_theorem and not isinstance(part.levels, str):
            line = level_line(part.levels, {t: (self.skeleton.tasks[t].duration, Fraction(0))
                                            for t in part.tasks})
            if isinstance(line, LevelLine):
                verdict, why = line.verdict(Fraction(0))
                if verdict is not None:
                    self.used.add(THEOREM)
                    return Outcome(verdict, cut, why)
        if part.data is None:  # every event at time 0: nothing waits, nothing runs late
            return Outcome(True, cut)
        saturated = self._saturated(part, {}, {}, cut)
        if saturated is not None:
            return saturated
        if part.too_long:  # only an early overrun can be seen: a short look for it
            result = self._simulate(part.data, QUICK_LOOK)
            if result.overrun_at:
                return self._verdict(result, part.data, part, cut)
            return Outcome(None, cut, ("undecided", part.too_long))
        return self._verdict(self._simulate(part.data), part.data, part, cut)

    def _value(self, j: int, base: dict[int, Fraction], direction: dict[int, Fraction]
               ) -> tuple[Fraction, Fraction]:
        return line_value(j, self.nominal, base, direction)

    def _parametric(self, data: PartData, part: Part, base: dict[int, Fraction],
                    direction: dict[int, Fraction], cut: Cut) -> PartData:
        return on_line(data, part, self.params, self.nominal, base, direction, self.net, cut)

    def _verdict(self, r: PartResult, d: PartData, part: Part, cut: Cut) -> Outcome:
        """§4b's verdict of one part from its simulation (:func:`~.simulation.verdict`)."""
        return verdict(r, d, part, cut, self.why_cut, self.net)
