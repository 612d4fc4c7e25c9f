"""The two responses of a task on processors, and a task that waits for ever (spec v1.3 §4b).

``response`` runs from a job's release (its reads done), ``response_from_tick`` from
its clock's tick (the figure of response-time analyses); and a task whose jobs
wait for a starved task is said to stop, with what it waits for. The engine's
figures are compared with an independent tick-by-tick oracle in
``test_schedule_oracle.py``; here, with values derived by hand.
"""

from __future__ import annotations

import json
from fractions import Fraction as F

from typer.testing import CliRunner

from tegraph import Skeleton, analyze
from tegraph.cli import app
from tegraph.report import render_text


def test_a_release_after_the_tick_makes_the_two_responses_differ():
    # One group (the ASYN/SYN link), so one priority. A (1 ms every 10) runs 0-1 and
    # writes y at 1; B, on its own 10 ms clock, also waits for y: released at 1, it runs
    # 1-3. Each period alike: B's response from release 3 - 1 = 2, from its tick 3 - 0 =
    # 3; A's both 1.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 10, "outputs": ["y"]},
        "B": {"duration": 2, "period": 10, "inputs": ["y"]}},
        "links": [{"from": "A:y", "to": "B:y", "protocol": "ASYN/SYN"}]})
    s = analyze(sk, design=False).schedule
    assert (s.tasks["B"].response, s.tasks["B"].response_from_tick) == (2, 3)
    assert (s.tasks["A"].response, s.tasks["A"].response_from_tick) == (1, 1)


def test_ticks_that_pile_up_have_no_response_from_tick():
    # 3 ms of work every 2 ms: job k is released when job k-1 ends, at 3(k-1), and ends
    # at 3k: 3 from its release, but 3k - 2(k-1) = k + 2 from its tick, without bound.
    sk = Skeleton.from_dict({"tasks": {"T": {"duration": 3, "period": 2}}})
    f = analyze(sk, design=False).schedule.tasks["T"]
    assert f.response == 3 and f.response_from_tick is None and f.overrun_at == 2


# A holds the processor all the time (2 ms every 2 ms, the more urgent: rate-monotonic);
# B's job, released at 0, never gets it; C reads B's message (ASYN/SYN): it never gets a
# job at all.
STARVED = {"tasks": {"A": {"duration": 2, "period": 2},
                     "B": {"duration": 1, "period": 4, "outputs": ["y"]},
                     "C": {"duration": 1, "inputs": ["y"]}},
           "links": [{"from": "B:y", "to": "C:y", "protocol": "ASYN/SYN"}]}


def test_a_task_behind_a_starved_one_is_said_to_stop(tmp_path):
    report = analyze(Skeleton.from_dict(STARVED))
    s = report.schedule
    assert s.starved == ["B"] and s.tasks["B"].starved_since == 0
    c = s.tasks["C"]
    assert (c.starved, c.stopped_after, c.waits_for, c.period) == (False, 0, ("B",), None)
    assert s.stopped == ["C"] and s.tasks["A"].stopped_after is None
    # B starved from its release at 0, then its clock's tick 2 at 4 ms finds it running.
    assert [(p.kind, p.task, p.at) for p in s.problems] == [
        ("starved", "B", F(0)), ("overrun", "B", F(4))]
    text = render_text(report)
    assert ("stopped on processors: C never runs again from the start (no job at all): it "
            "waits, through the graph's places, for B, starved") in text
    path = tmp_path / "starved.yaml"
    path.write_text(json.dumps(STARVED))
    doc = json.loads(CliRunner().invoke(app, ["analyze", str(path), "--json"]).output)
    assert doc["tasks"]["C"]["on_processors"]["stopped_after"] == 0
    assert doc["tasks"]["C"]["on_processors"]["waits_for"] == ["B"]
    assert doc["tasks"]["B"]["on_processors"]["stopped_after"] is None
