"""The timeline's marks of blocking on a non-preemptive processor (spec §4d)."""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from tegraph import Skeleton
from tegraph.design.timeline import simulate_timeline
from tegraph.report import render_text
from tegraph.report.plot import matplotlib_available, timeline_figure


def can(preemptive: bool) -> Skeleton:
    tasks = {"F1": {"duration": 1, "period": 2.5, "priority": 3, "processor": "can0"},
             "F2": {"duration": 1, "period": 3.5, "priority": 2, "processor": "can0"},
             "F3": {"duration": 1, "period": 3.5, "priority": 1, "processor": "can0"}}
    return Skeleton.from_dict({"tasks": tasks,
                               "processors": {"can0": {"preemptive": preemptive}}})


def test_the_can_frames_blocked_by_less_urgent_frames():
    # By hand (the bus sends F1 0-1, F2 1-2, F3 2-3, F1 3-4, F2 4-5, F1 5-6, F3 6-7,
    # F2 7-8, F1 8-9, F3 9-10, F1 10-11, F2 11-12, F3 12-13, ...): F1's second frame,
    # queued at 2.5 while F3#1 is on the bus, waits to 3; F1#4 (7.5) waits for F2#3 to
    # 8; F1#6 (12.5) for F3#4 to 13. F2's frames queued at 3.5 (F1#2 on the bus, more
    # urgent) and at 7 (bus free... F2#3 starts at 7) are not blocked.
    tl = simulate_timeline(can(False))
    got = [(b.task, b.k, b.start, b.end, b.by, b.by_k) for b in tl.blocking]
    assert got == [("F1", 2, F(5, 2), 3, "F3", 1), ("F1", 4, F(15, 2), 8, "F2", 3),
                   ("F1", 6, F(25, 2), 13, "F3", 4)]
    text = render_text(tl)
    assert "F1#2 on can0: 2.5 - 3 ms (0.5 ms), by F3#1" in text
    assert "non-preemptive; A = F1" in text


def test_no_blocking_under_preemption():
    assert simulate_timeline(can(True)).blocking == []


@pytest.mark.skipif(not matplotlib_available(), reason="matplotlib is an extra")
def test_the_picture_marks_the_blocking_and_the_lane():
    fig = timeline_figure(simulate_timeline(can(False)))
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "blocked by a less urgent job (non-preemptive)" in legend
    labels = [t.get_text() for t in fig.axes[0].get_yticklabels()]
    assert "can0 (non-preemptive)" in labels and "F1 waits" in labels
