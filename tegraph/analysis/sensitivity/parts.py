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
  itself, run on affine times (:mod:`.affine`): the interval of constant
  event order.

Each part is decided once at the nominal values (:meth:`ProcessorLine.decide_nominal`);
a line evaluates only the parts it moves and reads the others' nominal
outcome (their events do not depend on the line's parameters). Every
simulation counts its event firings against the budgets of
:class:`Budget`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ...model.build import build_teg, holding_sources
from ...model.platform import Platform, clock_hyperperiod, platform_of
from ...model.skeleton import Skeleton
from ..processors._engine import PartData, PartResult, simulate_part
from ..processors.levels import Levels, processor_levels
from ..processors.schedule import (
    MAX_EVENTS,
    QUICK_LOOK,
    _Net,
    _overrun_to_come,
)
from .affine import Cut, lin
from .levels import LevelLine, level_line
from .parameters import DELAY_KINDS, Parameter, skeleton_at
from .walk import Outcome

__all__ = ["RUN_BUDGETS", "SCHEDULE", "THEOREM", "Budget", "ProcessorLine"]

THEOREM = "theorem"
SCHEDULE = "schedule"

_NAME_LOOK = 200
"""Firings simulated at a saturated point to name the task that overruns first."""

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


@dataclass
class _Part:
    data: PartData | None
    """None: every task of the part has events at time 0 only (none is simulated)."""
    names: list[str]
    """The tasks simulated (those whose events are not all at time 0)."""
    events: list[int]
    places: list[int]
    tasks: list[str]
    """Every task of the part, in file order."""
    levels: Levels | str = "not computed"
    """Its levels (:mod:`tegraph.analysis.processors.levels`), or why it has none."""
    open_units: list[str] = dataclasses.field(default_factory=list)
    """Why its levels left points of a line undecided (a unit without closing task
    missing its deadline), in words."""
    too_long: str | None = None
    delays: dict[int, list[int]] = dataclasses.field(default_factory=dict)
    """The local places holding each varied delay j of the part's links."""
    delay_at_zero: dict[int, str] = dataclasses.field(default_factory=dict)
    """A place of the part's links holding delay j that no simulation holds (its events
    fire at time 0 only at the nominal values), named ``W.write:p -> R.read:q``."""


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
    parts: list[_Part] = field(default_factory=list)
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
        label = self.net._union_parts()
        index = {t: i for i, t in enumerate(self.net.tasks)}
        members: dict[int, list[str]] = {}
        for t, lab in zip(self.net.tasks, label):
            members.setdefault(lab, []).append(t)
        for data, names, events, places in self.net.parts():
            hyper, ticks = clock_hyperperiod(sk, names)
            lab = label[index[names[0]]] if names else -1
            part = _Part(data, names, events, places, members.pop(lab, list(names)))
            if ticks > self.max_events:
                part.too_long = (f"the hyperperiod of the part of {', '.join(names[:3])}"
                                 f"{' ...' if len(names) > 3 else ''} is {hyper} {sk.unit} "
                                 f"({ticks:,} clock ticks), more than `max_events` firings")
            self.parts.append(part)
        for tasks in members.values():  # parts whose events are all at time 0
            self.parts.append(_Part(None, [], [], [], tasks))
        for i, part in enumerate(self.parts):
            for t in part.tasks:
                self.part_of[t] = i
        self._levels()
        self._level_lines: dict[tuple, LevelLine | str] = {}
        self._duration_index = {p.owner: j for j, p in enumerate(self.params)
                                if p.kind == "duration"}
        self._delay_places = self._delays()
        self.why_cut = self.spend.cap_text()
        # Places from events that fire infinitely often at time 0 into the rest
        # grow at once (schedule.py's module docstring): not schedulable, as
        # ``schedule_on_processors`` says, for the part they lead into.
        self.zero_grows: dict[int, str] = {}
        self.whole_grows: str | None = None
        net, names_ = self.net, self.teg.transition_names
        for s, d in zip(net.src, net.dst):
            if s in net.zero and d not in net.zero:
                owner = (self.teg.transition_attrs[d].get("tasks")
                         or self.teg.transition_attrs[s].get("tasks"))
                if not self.groups[net.group_of[owner[0]]].live:
                    continue
                text = f"{names_[s]} -> {names_[d]}"
                if owner[0] in self.part_of:
                    self.zero_grows.setdefault(self.part_of[owner[0]], text)
                elif self.whole_grows is None:
                    self.whole_grows = text

    def _delays(self) -> dict[int, list[int]]:
        """The places (global numbers) holding each varied delay, read off the graph's
        holding sources as the parametric groups are (a link without a place,
        ASYN/ASYN, moves no event of the schedule), and each part's own."""
        param_of = {(p.kind, p.owner): j for j, p in enumerate(self.params)
                    if p.kind in DELAY_KINDS}
        out: dict[int, list[int]] = {}
        if not param_of:
            return out
        for q, source in enumerate(holding_sources(self.teg)):
            j = param_of.get((source.kind, source.owner))
            if j is not None:
                out.setdefault(j, []).append(q)
        attrs, names, net = self.teg.transition_attrs, self.teg.transition_names, self.net
        local = [{int(q): i for i, q in enumerate(part.places)} for part in self.parts]
        for j, places in out.items():
            for q in places:
                src, dst = int(net.src[q]), int(net.dst[q])
                # A link place joins two tasks of one group: one part.
                i = self.part_of[attrs[src]["tasks"][0]]
                if q in local[i]:
                    self.parts[i].delays.setdefault(j, []).append(local[i][q])
                else:
                    self.parts[i].delay_at_zero.setdefault(j, f"{names[src]} -> {names[dst]}")
        return out

    def tasks_of(self, parts: list[int]) -> list[str]:
        """Every task of the skeleton joined to ``parts`` (by a group or a processor), in
        file order: tasks of duration 0 that no part simulates included."""
        mine = {t for i in parts for t in self.parts[i].tasks}
        return [t for t in self.net.tasks if t in mine]

    def _levels(self) -> None:
        """Each part's levels (:mod:`tegraph.analysis.processors.levels`), or why it has none."""
        group_of = self.net.group_of
        shapes = []
        for part in self.parts:
            groups = list(dict.fromkeys(group_of[t] for t in part.tasks))
            shapes.append([list(self.groups[g].tasks) for g in groups])
        found = processor_levels(self.skeleton, self.teg, shapes, self.platform)
        for part, shape, levels in zip(self.parts, shapes, found):
            live = all(self.groups[group_of[g[0]]].live for g in shape)
            part.levels = levels if live else "a group is not live"

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
            data = self._moved_data(part_index, base, direction, cut)
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

    def _unscheduled(self, part: _Part, direction: dict[int, Fraction]) -> str | None:
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

    def _saturated(self, part: _Part, base: dict[int, Fraction],
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
        """The part simulated within the budgets; ``self.why_cut`` says which one stopped it.

        Past an overrun the engine still looks for a regime (its figures need it)
        for as many firings again, and at least a tenth of its budget
        (``AFTER_OVERRUN``); a verdict needs none of it: budgets grow tenfold from
        1,000, so an early overrun costs little and the whole budget is spent at
        most once more.
        Every firing counts against the figure's and the run's budgets.
        """
        self.used.add(SCHEDULE)
        budget_of = self.spend
        assert budget_of is not None
        top = self.max_events if limit is None else min(limit, self.max_events)
        cap, self.why_cut = budget_of.cap()
        budget = min(1_000, top, cap)
        result = PartResult()
        while budget > 0:
            result = simulate_part(data, budget, keep_intervals=False)
            budget_of.spend(result.fired)
            if self.progress is not None:
                self.progress()
            if result.overrun_at or result.regime is not None or budget >= top:
                break
            cap, why = budget_of.cap()
            nxt = min(budget * 10, top, cap)
            if nxt <= budget:  # the figure's or the run's budget is spent
                self.why_cut = why
                break
            budget = nxt
        if budget >= self.max_events:
            self.why_cut = budget_of.cap_text()
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

    def _nominal_part(self, part: _Part) -> Outcome:
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
        return base.get(j, self.nominal[j]), direction.get(j, Fraction(0))

    def _parametric(self, data: PartData, part: _Part, base: dict[int, Fraction],
                    direction: dict[int, Fraction], cut: Cut) -> PartData:
        scale = self.net.scale
        index = {p.owner: j for j, p in enumerate(self.params) if p.kind == "duration"}
        duration = list(data.duration)
        for i, t in enumerate(part.names):
            if t in index:
                c, k = self._value(index[t], base, direction)
                duration[i] = lin(c * scale, k * scale, cut)
        hold = list(data.p_hold)
        clocks = self.teg.attrs["clocks"]
        local = {e: i for i, e in enumerate(part.events)}
        for j, p in enumerate(self.params):
            if p.kind != "period":
                continue
            tick = local.get(clocks[p.owner])
            if tick is None:
                continue
            c, k = self._value(j, base, direction)
            for q, (s, d) in enumerate(zip(data.p_src, data.p_dst)):
                if s == d == tick:
                    hold[q] = lin(c * scale, k * scale, cut)
        for j, places in part.delays.items():
            c, k = self._value(j, base, direction)
            for q in places:
                hold[q] = lin(c * scale, k * scale, cut)
        return dataclasses.replace(data, duration=duration, p_hold=hold)

    def _line_periods(self, base: dict[int, Fraction], direction: dict[int, Fraction]
                      ) -> dict[str, tuple[Fraction, Fraction]]:
        """Each clock's period on the line, ``c + k·t`` as (c, k) (k = 0: it stays)."""
        moving = {self.params[j].owner: j for j, k in direction.items()
                  if k and self.params[j].kind == "period"}
        return {name: (self._value(moving[name], base, direction) if name in moving
                       else (clock.period, Fraction(0)))
                for name, clock in self.skeleton.clocks.items()}

    def _moved_data(self, part_index: int, base: dict[int, Fraction],
                    direction: dict[int, Fraction], cut: Cut) -> PartData:
        """The part's data with the platform of the periods in the cut's interval.

        Rate-monotonic priorities depend on the order of the periods: every pair
        of clock periods is compared (recorded in the cut), and the platform is
        taken at a point of the interval where that order holds.
        """
        sk = self.skeleton
        periods = self._line_periods(base, direction)
        names = list(periods)
        for a in range(len(names)):
            for b in range(a + 1, len(names)):
                (c1, k1), (c2, k2) = periods[names[a]], periods[names[b]]
                cut.sign(c1 - c2, k1 - k2)
        rep = _inside(cut, periods.values())
        values = {j: base.get(j, self.nominal[j]) + rep * k for j, k in direction.items()}
        moved = skeleton_at(sk, self.params, values)
        platform = platform_of(moved, self.groups)
        net = _Net(moved, build_teg(moved), self.groups, platform)
        for data, names_, _, _ in net.parts():
            if names_[0] == self.parts[part_index].names[0]:
                scale = Fraction(self.net.scale, net.scale)
                # back to the nominal scale, in which the parametric values are given
                return dataclasses.replace(
                    data, p_hold=[h * scale for h in data.p_hold],
                    p_init=[a * scale for a in data.p_init],
                    duration=[x * scale for x in data.duration])
        raise AssertionError("the parts do not depend on the periods")

    def _verdict(self, r: PartResult, d: PartData, part: _Part, cut: Cut) -> Outcome:
        """§4b's verdict of one part from its simulation (as ``schedule._Outcome``)."""
        names = part.names
        late = [(k, names[j]) for j, k in r.overrun_at.items()]
        if late:
            k, task = min(late)
            return Outcome(False, cut, ("overrun", task, k))
        if r.regime is None:
            return Outcome(None, cut, ("undecided", self.why_cut))
        if r.regime[0] == "stop":
            return Outcome(True, cut)
        t1, t2, old, new, growing = r.regime
        if growing:
            p = min(growing)
            g = part.places[p]
            names_ = self.teg.transition_names
            return Outcome(False, cut, ("grows", f"{names_[self.net.src[g]]} -> "
                                        f"{names_[self.net.dst[g]]}"))
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
