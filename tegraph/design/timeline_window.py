"""The default window of a timing diagram: a few periods of the fastest clock.

A whole proof is often a smear: a 1 ms loop beside a 100 ms one has a regime of
hundreds of its periods, in a thousand pixels. :func:`default_window` draws
:data:`WINDOW_PERIODS` periods of the fastest clock instead, around the first
problem (the first overrun's tick, the instant a deadlock leaves its group stuck,
the release of the first job that never ends; :data:`AFTER_PROBLEM` periods past
it, so that the late activation and the next tick are inside the frame), else from
the periodic regime of the part of that clock; or the whole proof when it fits.
Its text says what it shows and how to see more.
"""

from __future__ import annotations

import math
from fractions import Fraction

from maxplus.scalar import display_text

from ..analysis.processors import ProcessorSchedule
from ..model.limits import shown
from ..model.skeleton import Skeleton

__all__ = ["AFTER_PROBLEM", "WINDOW_PERIODS", "default_window"]

WINDOW_PERIODS = 10
"""Periods of the fastest clock in the default window: some 100 pixels a period on a
picture 1,000 wide, where a job of a tenth of it is still a bar, not a line."""

AFTER_PROBLEM = 2
"""Periods of the fastest clock drawn past the first problem (the late activation
and the next tick, inside the frame)."""


def default_window(skeleton: Skeleton, s: ProcessorSchedule, full: Fraction,
                   problem: tuple[Fraction, str] | None
                   ) -> tuple[Fraction, Fraction, str | None]:
    """The default drawing ``(start, end, what it shows)`` (module docstring); the text
    is None when the whole proof is drawn."""
    unit = skeleton.unit
    used = {task.clock for task in skeleton.tasks.values() if task.clock is not None}
    if not used:  # no clock gives a scale: the proof, and past a deadlock a fifth more
        end = full if problem is None else max(full, problem[0] + max(problem[0] / 4,
                                                                      Fraction(1)))
        return Fraction(0), end, None
    fastest = min(used, key=lambda c: (skeleton.clocks[c].period, list(skeleton.clocks).index(c)))
    clock = skeleton.clocks[fastest]
    period = clock.period
    span = WINDOW_PERIODS * period
    if problem is not None:
        at, what = problem
        end = at + AFTER_PROBLEM * period
        if max(full, end) <= span:
            return Fraction(0), max(full, end), None
        begin = max(end - span, Fraction(0))
        end = begin + span
        why = (f"up to {AFTER_PROBLEM} of its periods past {what}" if begin else
               f"from the start, with {what}")
    else:
        if full <= span:
            return Fraction(0), full, None
        regime = next((r["start"] for r in s.regimes if r["start"] is not None
                       and any(skeleton.tasks[t].clock == fastest for t in r["tasks"])),
                      Fraction(0))
        begin = _tick_at_or_before(clock.phase, period, regime)
        end = begin + span
        why = (f"from the periodic regime ({_at(regime, unit)})" if regime else
               "from the start")
    proof = ("the proof" if s.schedulable is not None else "the simulation")
    text = (f"drawn from {_at(begin, unit)} to {_at(end, unit)}: {WINDOW_PERIODS} periods "
            f"of {fastest} ({_at(period, unit)}), the fastest clock, {why}; {proof} runs to "
            f"{_at(full, unit)}: `horizon` {display_text(full)} draws all of it, `horizon` "
            "A..B any window")
    return begin, end, text


def _tick_at_or_before(phase: Fraction, period: Fraction, t: Fraction) -> Fraction:
    """The latest tick ``phase + n period`` at or before ``t``, and not before 0."""
    if t <= phase:
        return Fraction(0) if t < phase or phase == 0 else phase
    return phase + math.floor((t - phase) / period) * period


def _at(value: Fraction, unit: str) -> str:
    return f"{shown(display_text(value), quote=False)} {unit}"
