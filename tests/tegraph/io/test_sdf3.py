"""SDF3 XML: SDF3's own reading rules, the expansion against SDF3's, round trips, refusals."""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest

import tegraph
from tegraph import cycle_time
from tegraph.errors import InputError
from tegraph.io.edges import read_edges
from tegraph.io.sdf3 import dumps_sdf3, parse_sdf3, read_sdf3
from tegraph.model.sdf import SDFGraph
from tegraph.model.teg import TimedEventGraph

NAMES = ["h263decoder", "h263encoder", "modem", "mp3decoder_block_parallelism",
         "mp3decoder_granule_parallelism", "mp3playback", "samplerate", "satellite"]


def sdf(actors: str, channels: str, props: str = "") -> str:
    return (f'<sdf3 type="sdf"><applicationGraph name="t"><sdf name="t">{actors}{channels}</sdf>'
            f"<sdfProperties>{props}</sdfProperties></applicationGraph></sdf3>")


A = ('<actor name="a"><port name="o" type="out" rate="2"/><port name="i" type="in" rate="2"/>'
     "</actor>")
B = ('<actor name="b"><port name="i" type="in" rate="3"/><port name="o" type="out" rate="3"/>'
     "</actor>")
AB = ('<channel name="ab" srcActor="a" srcPort="o" dstActor="b" dstPort="i"/>'
      '<channel name="ba" srcActor="b" srcPort="o" dstActor="a" dstPort="i" initialTokens="6"/>')


def props(**times: int) -> str:
    return "".join(f'<actorProperties actor="{a}"><processor type="p" default="true">'
                   f'<executionTime time="{t}"/></processor></actorProperties>'
                   for a, t in times.items())


@pytest.fixture(scope="module")
def cases(anchors):
    return {c["name"]: c for c in json.loads((anchors / "sdf" / "cases.json").read_text())
            ["cases"]}


@pytest.mark.parametrize("name", ["h263encoder", "modem", "mp3decoder_block_parallelism",
                                  "mp3decoder_granule_parallelism", "samplerate"])
def test_repetition_vectors_and_sizes_match_sdf3(anchors, cases, name):
    g = read_sdf3(anchors / "sdf" / "xml" / f"{name}.xml")
    assert g.repetition_vector() == cases[name]["repetition_vector"]
    assert len(g.actors) == cases[name]["sdf_actors"]
    assert len(g.channels) == cases[name]["sdf_channels"]


def test_the_last_default_processor_gives_the_execution_time(anchors):
    g = read_sdf3(anchors / "sdf" / "xml" / "h263decoder.xml")
    # vld: processors arm (26018) then encoder (13009), both default -> the last one
    assert g.actors["vld"] == 13009 and g.actors["mc"] == 5479 and g.actors["iq"] == 559


@pytest.mark.parametrize("name", NAMES)
def test_expansion_equals_sdf3s_own_hsdf(anchors, name):
    """Arc by arc, against sdf3transform-sdf --transform to_hsdf (keeping, between two
    firings, the arc with fewest tokens: the others never constrain)."""
    ours = read_sdf3(anchors / "sdf" / "xml" / f"{name}.xml").to_arcs()
    theirs = read_edges(anchors / "sdf" / "hsdf_edges" / f"{name}.hsdf.edges")
    tightest: dict[tuple[str, str], tuple[int, int]] = {}
    for s, d, h, t in zip(theirs.src.tolist(), theirs.dst.tolist(), theirs.holding.tolist(),
                          theirs.tokens.tolist()):
        key = (theirs.name_of(s), theirs.name_of(d))
        if key not in tightest or tightest[key][1] > t:
            tightest[key] = (h, t)
    mine = {(ours.name_of(s), ours.name_of(d)): (h, t) for s, d, h, t in zip(
        ours.src.tolist(), ours.dst.tolist(), ours.holding.tolist(), ours.tokens.tolist())}
    assert mine == tightest
    assert sorted(ours.transition_names) == sorted(theirs.transition_names)
    # and so the periods agree (the three graphs without a cases.json entry included)
    assert cycle_time(ours).period == cycle_time(theirs).period


@pytest.mark.parametrize("name", NAMES)
def test_round_trip_keeps_the_graph(anchors, name):
    g = read_sdf3(anchors / "sdf" / "xml" / f"{name}.xml")
    back = parse_sdf3(dumps_sdf3(g))
    assert back.actors == g.actors and back.name == g.name
    assert [(c.src, c.dst, c.prod, c.cons, c.tokens) for c in back.channels] == \
        [(c.src, c.dst, c.prod, c.cons, c.tokens) for c in g.channels]


def test_multi_rate_graph_by_hand():
    g = parse_sdf3(sdf(A + B, AB, props(a=2, b=5)))
    # a makes 2 tokens per firing and b takes 3: q = (a: 3, b: 2). With 6 tokens
    # on b -> a (2 per firing of a), the three firings of a start at 0 (no
    # self-loop: concurrent) and end at 2; b_0 takes tokens 0-2 (a_0, a_1), b_1
    # tokens 3-5 (a_1, a_2), both at 2; they end at 7 and return 6 tokens: the
    # next iteration starts at 7, the period is 2 + 5 = 7.
    assert g.repetition_vector() == {"a": 3, "b": 2}
    r = cycle_time(g)
    assert r.period == 7 and r.throughput == F(1, 7)
    assert r.n_transitions == 5


def test_missing_tokens_deadlock():
    g = parse_sdf3(sdf(A + B, AB.replace('initialTokens="6"', 'initialTokens="3"'),
                       props(a=1, b=1)))
    # With 3 tokens on b -> a, a_1 takes initial token 2 and token 3, the first
    # that b_0 makes; b_0 needs a's token 2, made by a_1: a circuit without token.
    r = cycle_time(g)
    assert sorted(r.token_free_circuit) == ["a_1", "b_0"] and r.exit_status == 1


def test_homogeneous_graph_from_a_timed_event_graph():
    teg = TimedEventGraph("pipe")
    for e in "xy":
        teg.add_transition(e)
    teg.add_place("x", "y", 0, 4)
    teg.add_place("y", "x", 2, 6)
    teg.add_place("x", "x", 1, 4)
    g = SDFGraph.from_teg(teg)
    assert g.actors == {"x": 4, "y": 6} and g.repetition_vector() == {"x": 1, "y": 1}
    # (4 + 6) / 2 = 5 > the self-loop's 4
    assert cycle_time(parse_sdf3(dumps_sdf3(teg))).period == cycle_time(teg).period == 5


def test_places_with_their_own_times_get_their_own_actors(tmp_path):
    teg = TimedEventGraph("odd")
    for e in "xy":
        teg.add_transition(e)
    teg.add_place("x", "y", 0, 4)
    teg.add_place("y", "x", 1, 1)
    teg.add_place("x", "x", 1, 7)  # x's places hold 4 and 7: no single actor time
    g = SDFGraph.from_teg(teg)
    assert g.actors == {"x": 0, "y": 1, "place0": 4, "place2": 7}
    # circuits: x -> y -> x (4 + 1) / 1 = 5, x's self-loop 7 / 1 = 7
    assert cycle_time(parse_sdf3(dumps_sdf3(g))).period == cycle_time(teg).period == 7


def test_what_sdf3_cannot_hold_is_refused(tmp_path):
    teg = TimedEventGraph("frac")
    teg.add_transition("x")
    teg.add_place("x", "x", 1, "1/2")
    with pytest.raises(InputError, match="integers"):
        tegraph.write(teg, tmp_path / "frac.sdf3")
    teg = TimedEventGraph("phase")
    teg.add_transition("x")
    teg.add_place("x", "x", 1, 2, initial=1)
    with pytest.raises(InputError, match="available after 0"):
        tegraph.write(teg, tmp_path / "phase.sdf3")


# ------------------------------------------------------------------ refusals


def refusal(doc: str) -> str:
    with pytest.raises(InputError) as info:
        parse_sdf3(doc, "g.xml")
    return str(info.value)


def test_inconsistent_rates_name_a_channel():
    bad = B.replace('rate="3"/><port name="o" type="out" rate="3"',
                    'rate="3"/><port name="o" type="out" rate="2"')  # 2 x 2 != 3 x 2
    msg = refusal(sdf(A + bad, AB, props(a=1, b=1)))
    assert "inconsistent rates" in msg and "channel " in msg


def test_unknown_actor_and_port_are_refused():
    assert "'zz' is not an actor" in refusal(sdf(A + B, AB.replace('dstActor="b"',
                                                                   'dstActor="zz"')))
    assert "'nope' is not a port" in refusal(sdf(A + B, AB.replace('dstPort="i"/>',
                                                                   'dstPort="nope"/>', 1)))
    assert "expected 'in'" in refusal(sdf(A + B, AB.replace('dstPort="i"/>', 'dstPort="o"/>', 1)))


@pytest.mark.parametrize("bad,expect", [
    ('initialTokens="1.5"', "initialTokens must be an integer"),
    ('initialTokens="-1"', "initialTokens must be an integer >= 0"),
])
def test_bad_token_counts_are_refused(bad, expect):
    msg = refusal(sdf(A + B, AB.replace('initialTokens="6"', bad)))
    assert expect in msg and "channel[ba]" in msg and "g.xml:" in msg


def test_negative_execution_time_and_bad_rates_are_refused():
    assert "executionTime must be an integer >= 0, got -4" in refusal(sdf(A + B, AB,
                                                                          props(a=-4)))
    assert "a rate must be an integer >= 1" in refusal(sdf(A.replace('rate="2"', 'rate="0"') + B,
                                                           AB))
    assert "<actor> has no name" in refusal(sdf(A + B + '<actor type="x"/>', AB))
    assert "expected <sdf3>" in refusal("<pnml/>")
    assert "DOCTYPE" in refusal('<!DOCTYPE sdf3 SYSTEM "http://example.invalid/x.dtd"><sdf3/>')
