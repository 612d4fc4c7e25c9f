"""How much each task's duration can grow before its group stops being consistent.

``duration_margins`` answers, for every task of a consistent group, the
largest δ such that the group stays consistent (spec §4: rate-consistent, no
overrun) for every duration in ``[d, d + δ]``, the other times unchanged.
Unlike the slack of spec §4 (which only sees circuits), it also sees the
overruns: a task can show a slack of 4 ms and overrun at activation 2.

In a *clocked* consistent group (period λ = P of its clocks) it is read off
one nominal analysis, without any search:

- **Pace.** Every circuit that holds ``d_T`` passes through ``T.compute``
  once (each place holding ``d_T`` leaves ``T.compute``), so the group keeps
  its period exactly while ``d_T - d <= slack_T`` (spec §4); past it, a
  circuit is slower than the clocks and a place is unbounded. No source
  component can fall behind as ``d_T`` grows (ratios only grow).
- **Overruns.** While no circuit is slower than P, ``Y_e`` (the longest path
  of :mod:`.oracle`, weights ``h - m·P``) is the larger of the
  longest path avoiding the places ``p`` that hold ``d_T`` (it does not
  change) and ``Y_src(p) + w_p + R(dst(p))`` (R: the longest path to the end
  of the watched task), which grows one for one with ``d_T``: a path through
  p twice holds a circuit through p, of weight <= 0. So the task watched
  overruns exactly when ``d_T - d > φ - offset - (Y_src(p) + w_p + R(dst(p)))``;
  a watched task whose activation ends with its own computation (spec v1.1)
  also has ``d_T`` in its end: ``d_T - d > φ - Y_end - offset``.

The margin is the smallest of these bounds. One forward and one reverse
longest-path computation per clocked task, all groups at once, give them
all. A group without a clock has no overrun and no period to keep; its
margins come from the exact line search of :mod:`.line`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction

import numpy as np

from ...model.skeleton import Skeleton
from ..results import Report
from .line import Line, solve_lines
from .oracle import longest_paths
from .parameters import parse_vary
from .parametric import ParametricGroup, parametric_groups

__all__ = ["duration_margins", "group_consistent"]


def group_consistent(report: Report, index: int) -> bool:
    """Whether group ``index`` of an analysis is consistent (live, rate-consistent, no overrun)."""
    group = report.groups[index]
    return (group.live and group.rate_consistent
            and all(report.tasks[t].overrun_at is None and report.tasks[t].overrun_decided
                    for t in group.tasks))


def duration_margins(skeleton: Skeleton, report: Report | None = None
                     ) -> dict[str, Fraction | None]:
    """How much each task's duration can grow, its group staying consistent.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report, optional
        Its analysis (:func:`~tegraph.analysis.analyze.analyze_skeleton`);
        computed when not given.

    Returns
    -------
    dict of str to Fraction or None
        For every task of a consistent group (spec §4), in file order: the
        largest δ >= 0 with the group consistent for every duration in
        ``[d, d + δ]``; None when it stays consistent however long the task
        takes. Tasks of groups that are not consistent are left out (no
        growth keeps them consistent: they are not to begin with).

    Raises
    ------
    TegraphError
        Only as :func:`~tegraph.analysis.analyze.analyze_skeleton` would, on
        a skeleton built in code without validation; ``report`` is trusted
        to be the analysis of ``skeleton``.

    See Also
    --------
    tegraph.analysis.sensitivity.sensitivity : every consistent value of each
        duration and period, with causes.
    tegraph.analyze : shows these margins as "can grow by" beside the slack.

    Notes
    -----
    The slack of spec §4 is a period margin: it sees circuits only, not an
    activation that ends after the next tick while the group keeps pace.
    Here both bounds are taken (module docstring: one forward and one
    reverse longest path per clocked task, weights ``h - P·m``); groups
    without clock are searched exactly along the line [1]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, "Synchronization
       and Linearity", Wiley 1992, §3.6 (daters and cycle times of timed
       event graphs); the critical scaling factor of J. Lehoczky, L. Sha,
       Y. Ding, RTSS 1989, per duration.

    Examples
    --------
    B waits for A's message, so its activation ends at ``d(A) + d(B)`` after
    their common tick: both margins are ``10 - 1 - 2 = 7``, less than the
    slacks (9 and 8), which only see each task's own circuit:

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10, "outputs": ["o"]},
    ...     "B": {"duration": 2, "period": 10, "inputs": ["i"], "outputs": ["u"]}},
    ...     "links": [{"from": "A:o", "to": "B:i", "protocol": "ASYN/SYN"}]})
    >>> {t: str(m) for t, m in duration_margins(sk).items()}
    {'A': '7', 'B': '7'}
    """
    if report is None:
        from ..analyze import analyze_skeleton

        report = analyze_skeleton(skeleton)
    params = parse_vary(skeleton)
    index = {p.owner: j for j, p in enumerate(params)}
    # The analysis' own groups (report.structure), so g.index numbers report.groups.
    groups = [g for g in parametric_groups(skeleton, params, report.structure)
              if group_consistent(report, g.index)]
    nominal = [p.nominal for p in params]
    margins: dict[str, Fraction | None] = {}
    clocked = [g for g in groups if g.clocks and _slack_covers(g, index)]
    for bounds in _clocked_margins(clocked, nominal, report, index):
        margins.update(bounds)
    done = {g.index for g in clocked}  # by index: comparing groups field by field is slow
    searched = [(g, Line({index[t]: Fraction(0)}, {index[t]: Fraction(1)}, nominal[index[t]],
                         None)) for g in groups if g.index not in done for t in g.tasks]
    sets, _, _ = solve_lines(searched, nominal)
    for (_, line), found in zip(searched, sets):
        (j,) = line.direction
        high = found.intervals[0][1] if found.intervals else nominal[j]
        margins[params[j].owner] = None if high is None else high - nominal[j]
    return {t: margins[t] for t in skeleton.tasks if t in margins}


def _slack_covers(g: ParametricGroup, index: dict[str, int]) -> bool:
    """Whether the places holding each task's duration are exactly those leaving its compute.

    That is what makes the slack of spec §4 the pace bound; spec §2 says so,
    and a group where it would not hold is searched instead.
    """
    compute = {t: g.names.index(f"{t}.compute") for t in g.tasks}
    for t in g.tasks:
        leaving = set(np.flatnonzero(g.src == compute[t]).tolist())
        holding = set(np.flatnonzero(g.param == index[t]).tolist())
        if leaving != holding:
            return False
    return True


def _clocked_margins(groups: Sequence[ParametricGroup], nominal: Sequence[Fraction],
                     report: Report, index: dict[str, int]) -> list[dict[str, Fraction]]:
    """The bounds of the module docstring for every task of clocked consistent groups."""
    # All searches at once: one forward (Y) per group, one reverse (R) per watched task.
    forward, reverse, jobs = [], [], []
    for g in groups:
        period = report.groups[g.index].period
        assert period is not None
        values = {j: nominal[j] for j in g.params}
        scale, weight, start = _weights(g, values, period)
        labels = np.arange(len(g.src))
        forward.append((g.n_events, g.src, g.dst, labels, weight, start, [0] * g.n_events))
        for w in g.watches:
            start_r: list[int | None] = [None] * g.n_events
            start_r[w.end] = 0
            reverse.append((g.n_events, g.dst, g.src, labels, weight, start_r, [0] * g.n_events))
        jobs.append((g, values, scale, weight))
    ahead = longest_paths(forward)
    behind = iter(longest_paths(reverse))
    out = []
    for (g, values, scale, weight), (y, _) in zip(jobs, ahead):
        # The groups here are live: analyze gave each of their tasks a slack.
        bounds: dict[str, Fraction] = {t: report.tasks[t].slack for t in g.tasks}  # type: ignore[misc]
        for w in g.watches:
            r, _ = next(behind)
            room = g.clocks[w.clock].phase - g.offset(w, values)
            if w.offset_param >= 0:  # the task's own duration ends its activation
                own = g.tasks[[index[t] for t in g.tasks].index(w.offset_param)]
                # y[w.end] is set: every event of a live group lies downstream of a marked
                # place (its task's chain circuit holds a token).
                end = Fraction(y[w.end], scale)  # type: ignore[arg-type]
                bounds[own] = min(bounds[own], room - end)
            for t in g.tasks:
                best = _longest_through(g, index[t], y, r, weight)
                if best is not None:
                    bounds[t] = min(bounds[t], room - Fraction(best, scale))
        out.append(bounds)
    return out


def _weights(g: ParametricGroup, values: dict[int, Fraction], period: Fraction
             ) -> tuple[int, list[int], list[int | None]]:
    """The forward search of ``g`` at its period: a scale making every figure an
    integer, each place's weight ``(h - m·P)·scale`` and each event's start (the
    latest ``(initial - P)·scale`` of its marked places entering it; None: none)."""
    holdings = g.holdings(values)
    scale = math.lcm(period.denominator, *(h.denominator for h in holdings),
                     *(a.denominator for a in g.initial))
    weight = [int((h - m * period) * scale) for h, m in zip(holdings, g.tokens.tolist())]
    start: list[int | None] = [None] * g.n_events
    for p in np.flatnonzero(g.tokens > 0).tolist():
        v = int((g.initial[p] - period) * scale)
        e = int(g.dst[p])
        old = start[e]
        start[e] = v if old is None else max(old, v)
    return scale, weight, start


def _longest_through(g: ParametricGroup, param: int, y: Sequence[int | None],
                     r: Sequence[int | None], weight: Sequence[int]) -> int | None:
    """The longest ``Y_src(p) + w_p + R(dst(p))`` over the places ``p`` holding
    parameter ``param`` (scaled; None when no such path exists)."""
    best = None
    for p in np.flatnonzero(g.param == param).tolist():
        ahead_u, behind_v = y[int(g.src[p])], r[int(g.dst[p])]
        if ahead_u is not None and behind_v is not None:
            total = ahead_u + weight[p] + behind_v
            best = total if best is None else max(best, total)
    return best
