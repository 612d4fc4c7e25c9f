"""What ``explore`` judges a variant by: its objectives, its constraints, their version.

The objectives are all minimized: a chain's figures of spec §4c (``latency``,
``age``, ``reaction``, one per chain), ``period``, ``load``, ``utilization`` and,
where tasks run is a choice, ``processors``, ``traffic`` and ``busiest``. The
constraints (:class:`Constraints`) are what every kept design must meet besides
liveness, consistency and schedulability. :data:`DEFINITIONS` numbers the version
of these definitions, part of a space's fingerprint, so that a results file judged
under other definitions is not resumed.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ...errors import InputError
from ...model.skeleton import Protocol, Skeleton
from ...model.skeleton.checks import Locator, check_chain
from .allocation import Allocation
from .choices import _time

__all__ = [
    "CHAIN_FIGURES",
    "Constraints",
    "PLACEMENT_OBJECTIVES",
    "chain_objective",
    "latency_name",
    "parse_latency_bound",
    "parse_period_requirement",
]

OBJECTIVES = ("latency", "age", "reaction", "period", "load", "utilization", "processors",
              "traffic", "busiest")

PLACEMENT_OBJECTIVES = ("processors", "traffic", "busiest")
"""The objectives of where tasks run: the processors used, the links that cross
processors, the busiest processor's demand (``Σ duration/period`` at the §4 periods)."""

CHAIN_FIGURES = {"latency": "first_use", "age": "age", "reaction": "reaction"}
"""Each chain objective and the figure of spec §4c it minimizes, on processors."""


def chain_objective(name: str) -> tuple[str, tuple[str, ...]] | None:
    """``"age:A,B"`` -> (``"age"``, the chain), for a chain objective; None otherwise.

    >>> chain_objective("reaction:TG.JS,CO.JS"), chain_objective("load")
    (('reaction', ('TG.JS', 'CO.JS')), None)
    """
    key, _, chain = name.partition(":")
    return (key, tuple(chain.split(","))) if key in CHAIN_FIGURES and chain else None


def latency_name(chain: Sequence[str]) -> str:
    """The objective name of a chain's latency.

    >>> latency_name(["TG.JS", "TF.TT.JS", "CO.JS"])
    'latency:TG.JS,TF.TT.JS,CO.JS'
    """
    return "latency:" + ",".join(chain)


def _objective_names(objectives: Sequence[str] | None, chains: Sequence[tuple[str, ...]],
                     skeleton: Skeleton, allocation: Allocation | None = None
                     ) -> tuple[str, ...]:
    if objectives is None:
        processors = ({t.runs_on for t in skeleton.tasks.values()} if allocation is None
                      else set(allocation.offered))
        wanted = [o for o in OBJECTIVES if (o != "latency" or chains) and o not in (
                  "age", "reaction") and (o != "utilization" or len(processors) > 1)
                  and (o not in PLACEMENT_OBJECTIVES or allocation is not None)]
    else:
        wanted = []
        for k, name in enumerate(objectives):
            key = str(name).strip().lower()
            if key not in OBJECTIVES:
                raise InputError(f"unknown objective {name!r}; expected one of "
                                 f"{', '.join(OBJECTIVES)}", f"objectives[{k}]")
            if key in CHAIN_FIGURES and not chains:
                raise InputError(f"the objective {key} needs a chain; expected a `chain` "
                                 "or the skeleton's chains", f"objectives[{k}]")
            wanted.append(key)
        if not wanted:
            raise InputError(f"no objective; expected some of {', '.join(OBJECTIVES)}",
                             "objectives")
    out: list[str] = []
    for key in dict.fromkeys(wanted):
        if key in CHAIN_FIGURES:
            out += [f"{key}:" + ",".join(c) for c in dict.fromkeys(chains)]
        else:
            out.append(key)
    return tuple(out)


@dataclass(frozen=True)
class Constraints:
    """What every kept design must meet, besides liveness, consistency and schedulability.

    Attributes
    ----------
    periods : tuple of (task, op, period)
        The task's period (its group's, in the variant) ``=`` or ``<=`` the period.
    latencies : tuple of (chain, latency)
        The chain's first use on processors (spec §4c, exact: never a bound) at most
        this value; a variant where it is undecided does not meet it.
    forbidden : tuple of Protocol
        Protocols taken out of every chosen link's choices (a link not chosen may
        not use one either).
    free_running : bool
        Keep designs where a task runs free that the input design runs on a clock
        (its group has no clock in the variant: it runs as often as its processor
        lets it, at the lowest priority, and its rate is nobody's choice). False (the
        default): such a design is not kept.
    """

    periods: tuple[tuple[str, str, Fraction], ...] = ()
    latencies: tuple[tuple[tuple[str, ...], Fraction], ...] = ()
    forbidden: tuple[Protocol, ...] = ()
    free_running: bool = False

    def __bool__(self) -> bool:
        """True when a variant can fail them (forbidden protocols restrict the space
        instead)."""
        return bool(self.periods or self.latencies)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the report and the fingerprint."""
        return {"periods": [{"task": t, "op": op, "period": exact_text(v)}
                            for t, op, v in self.periods],
                "latencies": [{"chain": list(c), "at_most": exact_text(v)}
                              for c, v in self.latencies],
                "forbidden": [p.value for p in self.forbidden],
                "free_running": self.free_running}

    def texts(self, unit: str) -> list[str]:
        """Each constraint in words."""
        return ([f"{t}.period {op} {exact_text(v)} {unit}" for t, op, v in self.periods]
                + [f"latency {','.join(c)} <= {exact_text(v)} {unit}"
                   for c, v in self.latencies]
                + [f"no {p.value} link" for p in self.forbidden])


_REQUIREMENT = re.compile(r"\s*(?P<task>[^=<>]+?)\.period\s*(?P<op><=|=)\s*(?P<value>\S.*?)\s*$")


def parse_period_requirement(text: str, where: str) -> tuple[str, str, str]:
    """``"CTRL.period=2"`` or ``"CTRL.period<=5/2"`` -> (task, ``=`` or ``<=``, period text).

    >>> parse_period_requirement("CTRL.period = 2", "requires[0]")
    ('CTRL', '=', '2')
    """
    found = _REQUIREMENT.fullmatch(str(text))
    if not found:
        raise InputError(f"cannot read {str(text)!r}; expected TASK.period=P or "
                         "TASK.period<=P, such as CTRL.period=2", where)
    return found["task"].strip(), found["op"], found["value"]


def parse_latency_bound(text: str, where: str) -> tuple[tuple[str, ...], str]:
    """``"A,B,C=12"`` -> (chain, latency text).

    >>> parse_latency_bound("A, B,C = 25/2", "max_latency[0]")
    (('A', 'B', 'C'), '25/2')
    """
    chain, equals, value = str(text).rpartition("=")
    names = tuple(n.strip() for n in chain.split(","))
    if not equals or not value.strip() or len(names) < 2 or not all(names):
        raise InputError(f"cannot read {str(text)!r}; expected A,B,C=LATENCY (a chain of "
                         "two tasks or more), such as MT1,MT2,MT3=12", where)
    return names, value.strip()


def _requirements(skeleton: Skeleton, requires: Sequence[Any]
                  ) -> tuple[tuple[str, str, Fraction], ...]:
    out: dict[str, tuple[str, str, Fraction]] = {}
    for k, item in enumerate(requires):
        where = f"requires[{k}]"
        task, op, text = (parse_period_requirement(item, where) if isinstance(item, str)
                          else item)
        if task not in skeleton.tasks:
            raise InputError(f"no task {task!r} in the skeleton; expected TASK.period=P with "
                             "one of its tasks", where)
        if op not in ("=", "<="):
            raise InputError(f"expected '=' or '<=', got {op!r}", where)
        if task in out:
            raise InputError(f"the period of {task!r} is required twice; expected each task "
                             "once (the second would silently replace the first)", where)
        out[task] = (task, op, _time(text, where, "a period"))
    return tuple(out.values())


def _latency_bounds(skeleton: Skeleton, bounds: Sequence[Any]
                    ) -> tuple[tuple[tuple[str, ...], Fraction], ...]:
    out: dict[tuple[str, ...], tuple[tuple[str, ...], Fraction]] = {}
    for k, item in enumerate(bounds):
        where = f"max_latency[{k}]"
        chain, text = parse_latency_bound(item, where) if isinstance(item, str) else item
        chain = check_chain(skeleton, list(chain), ("max_latency", k), Locator())
        if chain in out:
            raise InputError(f"the latency of {','.join(chain)} is bounded twice; expected "
                             "each chain once (the second would silently replace the first)",
                             where)
        out[chain] = (chain, _time(text, where, "a latency"))
    return tuple(out.values())


DEFINITIONS = 6
"""The version of the definitions of a verdict and of the objectives, part of the
fingerprint: a results file judged under other definitions is not resumed. Version 1:
the period ratio against the input group's fastest clock, no utilization, no Rule 2
count; version 2: every variant judged with a processor per task (spec §4) and the
response-time test; version 3: judged on its processors (spec v1.2 §4b, the exact
schedule within ``max_events``), the period ratio, load and utilization read on
processors; version 4: as 3, and a design where a task runs free that the input design
runs on a clock is kept only when asked (``Constraints.free_running``); version 5: as 4,
and the chains' objectives and ``max_latency`` exact on processors (spec v1.3 §4c: first
use, age, reaction), a variant whose figure is undecided rejected, never ranked by a
bound; version 6: as 5, and where the tasks run may be a choice (the allocation digits,
least significant, an allocation and its renamings over interchangeable processors one
variant), with the ``processors``, ``traffic`` and ``busiest`` objectives, and a chain's
message visible its link's communication delay after its write (spec v1.3 §4d), not at
the write."""

CURRENT_DEFINITIONS = ("each variant judged on its processors, spec §4b; a design where a "
                       "task runs free that the input design clocks is not kept unless "
                       "asked; the chains' figures exact on processors, spec §4c; where "
                       "tasks run may be chosen, one variant per allocation up to renaming")

OLDER_DEFINITIONS = {1: "the period ratio against the input group's fastest clock",
                     2: "every variant judged with a processor per task and the "
                        "response-time test, before the schedule on processors (§4b)",
                     3: "designs kept where a task runs free that the input design runs on "
                        "a clock, and a chain's latency with a processor per task, or a "
                        "published bound across groups, before its exact figures on "
                        "processors (§4c)",
                     4: "a chain's latency with a processor per task, or a published "
                        "bound across groups, before its exact figures on processors (§4c)",
                     5: "before the allocation of tasks to processors was a choice, and "
                        "a chain's messages visible at their write, before the "
                        "communication delays of the links (§4d)"}
"""What each older version of :data:`DEFINITIONS` judged differently (said when a
results file of that version is refused)."""
