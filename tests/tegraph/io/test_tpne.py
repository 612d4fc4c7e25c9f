"""TimedPetriNetEditor JSON and .teg files: the editor's examples, round trips, refusals."""

from __future__ import annotations

import json
from fractions import Fraction as F

import numpy as np
import pytest

from tegraph import cycle_time
from tegraph.errors import InputError
from tegraph.io.tpne import (
    dumps_tpne_json,
    dumps_tpne_teg,
    parse_tpne_json,
    parse_tpne_teg,
    read_tpne_json,
    read_tpne_teg,
)
from tegraph.model.teg import TimedEventGraph


def test_howard2_json_structure(anchors):
    net = read_tpne_json(anchors / "teg" / "Howard2.json")
    # the file: P0 holds 2 tokens; durations T0->P0 5, T2->P2 3, T1->P1 5, T2->P4 1, T3->P3 1
    assert net.places == ["P0", "P1", "P2", "P3", "P4"]
    assert net.marking.tolist() == [2, 0, 0, 0, 0]
    assert net.holding == [5, 5, 3, 1, 1]
    assert net.marked_graph_violation() is None


def test_captions_name_the_transitions(anchors):
    net = read_tpne_json(anchors / "teg" / "EventGraph.json")
    assert net.transitions == ["u", "x1", "x2", "y"]
    # arcs use keys (T0, P0...), not captions: u = T0 feeds P0 and P1
    u = net.transitions.index("u")
    assert [net.places[p] for p in np.flatnonzero(net.post.toarray()[:, u])] == ["P0", "P1"]


def test_semi_netherlands_teg_file(anchors):
    g = read_tpne_teg(anchors / "teg" / "SemiNetherlands.teg")
    assert g.n_transitions == 8 and g.n_places == 12
    # first line "0 1:   61    2": in the matrix orientation, a place T1 -> T0
    p = g.places[0]
    assert (g.transition_names[p.src], g.transition_names[p.dst], p.holding, p.tokens) == \
        ("T1", "T0", 61, 2)


def test_json_round_trip_keeps_net_and_positions(anchors):
    net = read_tpne_json(anchors / "teg" / "Howard2.json")
    text = dumps_tpne_json(net)
    back = parse_tpne_json(text)
    assert back.places == net.places and back.transitions == net.transitions
    assert (back.pre != net.pre).nnz == 0 and (back.post != net.post).nnz == 0
    assert back.holding == net.holding and back.marking.tolist() == net.marking.tolist()
    doc = json.loads(text)
    assert doc["revision"] == 4 and doc["type"] == "Timed event graph"
    original = json.loads((anchors / "teg" / "Howard2.json").read_text())["nets"][0]
    assert [(p["x"], p["y"]) for p in doc["nets"][0]["places"]] == \
        [(p["x"], p["y"]) for p in original["places"]]
    assert cycle_time(back).period == F(13, 2)  # the editor's test: 6.5


def test_teg_round_trip_and_decimal_durations():
    text = "TimedEventGraph 3 3\n\n0 1: 2.5 1\n1 2: 0 0\n2 0: 4 1\n"
    g = parse_tpne_teg(text)
    assert dumps_tpne_teg(g) == text
    assert [p.holding for p in g.places] == [F(5, 2), 0, 4]


def test_times_without_finite_decimal_form_are_refused():
    g = TimedEventGraph("third")
    g.add_transition("a")
    g.add_place("a", "a", 1, "7/3")
    with pytest.raises(Exception, match="no finite decimal form"):
        dumps_tpne_teg(g)
    with pytest.raises(Exception, match="no finite decimal form"):
        dumps_tpne_json(g)


@pytest.mark.parametrize("text,expect", [
    ("Timed 2 1\n0 1: 1 1\n", "header"),
    ("TimedEventGraph 2 2\n0 1: 1 1\n", "announces 2 lines"),
    ("TimedEventGraph 2 1\n0 2: 1 1\n", "transition index 0..1"),
    ("TimedEventGraph 2 1\n0 1 1 1\n", "expected '<i> <j>: <duration> <tokens>'"),
    ("TimedEventGraph 2 1\n0 1: -1 1\n", "duration must be >= 0"),
    ("TimedEventGraph 2 1\n0 1: 1 0.5\n", "token count"),
])
def test_teg_refusals(text, expect):
    with pytest.raises(InputError, match=expect) as info:
        parse_tpne_teg(text, "g.teg")
    assert str(info.value).startswith("g.teg:")


def net_json(arcs: str, places: str = '[{"id": 0, "tokens": 1}]') -> str:
    return (f'{{"revision": 4, "type": "Timed event graph", "nets": [{{"name": "n", '
            f'"places": {places}, "transitions": [{{"id": 0}}], "arcs": {arcs}}}]}}')


@pytest.mark.parametrize("doc,expect", [
    ('{"nets": [', "malformed JSON"),
    ('{"revision": 4}', "nets"),
    (net_json('[{"from": "T0", "to": "P9"}]'), "nets[0].arcs[0].to"),
    (net_json('[{"from": "P0", "to": "P0"}]'), "two places"),
    (net_json('[{"from": "T0", "to": "P0", "duration": -3}]'), "duration must be >= 0"),
    (net_json('[{"from": "T0", "to": "P0", "duration": "fast"}]'), "a duration is a number"),
    (net_json("[]", '[{"id": 0, "tokens": 1.5}]'), "nets[0].places[0].tokens"),
    (net_json("[]", '[{"caption": "P0"}]'), "nets[0].places[0].id"),
])
def test_json_refusals(doc, expect):
    with pytest.raises(InputError) as info:
        parse_tpne_json(doc, "n.json")
    assert expect in str(info.value) and "n.json" in str(info.value)
