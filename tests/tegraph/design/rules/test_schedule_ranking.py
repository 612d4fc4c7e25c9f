"""Advice ranked by the exact schedule it leads to, and clock periods that keep it decidable.

The advisor's candidates for a finding of Rules 1-3 are ranked first by the §4b
verdict of the skeleton once each is made (schedulable first), on the part the
change touches; a clock that a change adds gets a period taken from the
skeleton's own periods (``tegraph.design.rules.periods``), checked the same way.
"""

from __future__ import annotations

from fractions import Fraction as F

import tegraph
from tegraph import Skeleton
from tegraph.design.rules import Change, apply_change, check_rules
from tegraph.design.rules.findings import FindingKind
from tests.tegraph.design.test_one_verdict import QUAD


def _finding(findings, kind, key):
    return next(f for f in findings if f.kind is kind and f.key == key)


def test_rule1_advice_keeps_the_logger_schedulable():
    sk = Skeleton.from_dict(QUAD)
    f = _finding(check_rules(sk), FindingKind.RULE1_NO_SYNC, "logger")
    # Two ways for the logger to wait for a message, both bringing no finding and keeping
    # every clock's period with a processor per task: att_est:q (first in its inputs)
    # and gps:fix. The advice is the one whose schedule stays schedulable.
    assert f.change == Change((("gps:fix", "logger:fix", "ASYN/SYN"),))
    assert (f.schedule.before, f.schedule.after) == (True, True)
    assert "NOT SCHEDULABLE" not in f.advice
    # With gps: {gps, logger} 5.5 ms of work every 100 ms at gps's priority, below
    # pos_ctrl: 0.3 + 0.16 + 0.1 + 0.055 < 1, each level meets its period.
    after = tegraph.analyze(apply_change(sk, f.change), design=False)
    assert after.schedulable is True and after.schedule.tasks["logger"].period == 100
    # The other one, by hand: {imu, att_est, logger} needs 0.1 + 0.2 + 0.5 = 0.8 of
    # every 1 ms at the top priority, the rate loop 0.4 of every 2.5 ms: 0.96 of the
    # processor, 0.04 left, 0.8 ms in 20 ms for pos_ctrl's 2 ms: its job 1 has not ended
    # at its tick 2 (20 ms), and gps (below it, its job released at 0) never runs.
    other = tegraph.analyze(apply_change(sk, Change((("att_est:q", "logger:q", "ASYN/SYN"),))),
                            design=False)
    assert other.schedulable is False
    assert [(p.kind, p.task, p.at) for p in other.schedule.problems[:2]] == [
        ("starved", "gps", 0), ("overrun", "pos_ctrl", 20)]
    # Without the schedule (a processor per task) nothing tells the two apart: the first.
    plain = _finding(check_rules(sk, processors=False), FindingKind.RULE1_NO_SYNC, "logger")
    assert plain.change == Change((("att_est:q", "logger:q", "ASYN/SYN"),))


def test_rule3_proposes_a_divisor_of_the_hyperperiod_around_the_group():
    sk = Skeleton.from_dict(QUAD)
    f = _finding(check_rules(sk), FindingKind.RULE3_NO_CLOCK, ("logger",))
    # The logger reads att_est (1 ms) and gps (100 ms); the loops on its processor run
    # at 2.5 and 20 ms: hyperperiod 100 ms. The longest period that divides it, is no
    # neighbour's (Rule 2 would ask to synchronize the two) and is at least the
    # logger's cycle time (0.5 ms) is 50 ms (max + 1 = 101 ms made it 10,100 ms and
    # the schedule undecided within the advice's budget).
    assert f.change.add_clock == ("logger",) and f.change.period == 50
    assert "of period 50 ms" in f.advice and "it divides 100 ms" in f.advice
    assert (f.schedule.before, f.schedule.after) == (True, True)
    # Checked: the skeleton with it is schedulable on its processor, and follows Rule 3.
    changed = apply_change(sk, f.change)
    assert changed.clocks["logger.clock"].period == 50
    assert tegraph.analyze(changed, design=False).schedulable is True
    assert not [g for g in check_rules(changed) if g.kind is FindingKind.RULE3_NO_CLOCK]
    assert f.change.to_dict()["period"] == "50"


def test_rule3_period_beside_a_huge_clock_keeps_the_schedule_decidable():
    # A GPS at 10^12 ms and a 20 ms loop; a logger reads the GPS, with no clock. The
    # period no group has, 10^12 + 1, gives a hyperperiod of about 10^24: undecided.
    # Half the GPS's period divides 10^12 (which stays the hyperperiod): 5 * 10^11.
    sk = Skeleton.from_dict({"tasks": {
        "gps": {"duration": 1, "period": 10**12, "outputs": ["fix"]},
        "loop": {"duration": 1, "period": 20},
        "logger": {"duration": 1, "inputs": ["fix"]}},
        "links": [{"from": "gps:fix", "to": "logger:fix", "protocol": "ASYN/ASYN"}]})
    f = _finding(check_rules(sk), FindingKind.RULE3_NO_CLOCK, ("logger",))
    assert f.change.period == F(5 * 10**11)
    assert f.schedule.after is True  # decided (by the critical instant: independent tasks)
    assert tegraph.analyze(apply_change(sk, f.change), design=False).schedulable is True
    # The period the check assumes (10^12 + 1) is what the advice used to propose.
    assert apply_change(sk, Change(add_clock=("logger",)), 10**12 + 1).clocks[
        "logger.clock"].period == 10**12 + 1
