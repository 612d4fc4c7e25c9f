"""Arc lists: the SDF3 reference files, every syntax, round trips, refusals, speed."""

from __future__ import annotations

import json
import time
from fractions import Fraction as F

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.errors import InputError
from tegraph.io.edges import dumps_edges, parse_edges, read_edges, write_edges
from tegraph.model.arcs import ArcList
from tegraph.model.teg import TimedEventGraph


def holdings(g: ArcList) -> list[F]:
    return [g.holding_time(p) for p in range(g.n_places)]


def test_sdf3_reference_edge_list(anchors):
    cases = {c["name"]: c for c in json.loads((anchors / "sdf" / "cases.json").read_text())
             ["cases"]}
    g = read_edges(anchors / "sdf" / "hsdf_edges" / "modem.hsdf.edges")
    assert g.n_transitions == cases["modem"]["hsdf_actors"] == 48
    assert g.n_places == cases["modem"]["hsdf_arcs"] == 109
    # the file's own header lines: "# node 0 fork1_0", ..., first arc "0 1 1 0"
    assert g.name_of(0) == "fork1_0" and g.name_of(9) == "in_0"
    assert (g.src[0], g.dst[0], g.holding_time(0), g.tokens[0]) == (0, 1, 1, 0)


@pytest.mark.parametrize("text", [
    "0 1 7/3 0\n1 0 2 1\n",
    "0 1 7/3 0\r\n1 0 2 1\r\n",                    # CRLF
    "\n# header\n\n0\t1\t7/3\t0   # trailing comment\n\n1 0 2 1",  # tabs, blanks, no final \n
    "0 1 14/6 0\n1 0 2.0 1\n",                      # unreduced fraction, decimal
    "0 1 7/3 0\n1 0 2e0 1\n",                      # exponent: the general path
])
def test_syntax_variants_read_the_same_graph(text):
    g = parse_edges(text)
    assert g.src.tolist() == [0, 1] and g.dst.tolist() == [1, 0] and g.tokens.tolist() == [0, 1]
    assert holdings(g) == [F(7, 3), F(2)]


def test_decimals_are_exact():
    g = parse_edges("0 1 0.05 0\n1 0 12.345 1\n2 2 5. 1\n")
    assert holdings(g) == [F(1, 20), F(12345, 1000), F(5)]
    assert g.scale == 200  # lcm of 20 and 200


def test_names_and_declared_node_count():
    g = parse_edges("# node 0 alpha\n# node 2 gamma beta\n# nodes 4\n0 2 1 1\n")
    assert g.transition_names == ("alpha", "1", "gamma beta", "3") and g.n_transitions == 4
    back = parse_edges(dumps_edges(g))
    assert back.transition_names == g.transition_names and back.n_transitions == 4


def test_round_trip_of_a_timed_event_graph(tmp_path):
    teg = TimedEventGraph("t")
    for e in ("in", "out"):
        teg.add_transition(e)
    teg.add_place("in", "out", 0, "7/3")
    teg.add_place("out", "in", 2, "0.5")
    path = write_edges(teg, tmp_path / "t.edges")
    back = read_edges(path).to_teg()
    assert back.transition_names == ("in", "out")
    assert [(p.src, p.dst, p.tokens, p.holding) for p in back.places] == \
        [(0, 1, 0, F(7, 3)), (1, 0, 2, F(1, 2))]
    with pytest.raises(FileExistsError):
        write_edges(teg, path)


def test_availability_times_cannot_be_written():
    teg = TimedEventGraph("c")
    teg.add_transition("tick")
    teg.add_place("tick", "tick", 1, 4, initial=1, name="clock")
    with pytest.raises(Exception, match="available at 1"):
        dumps_edges(teg)


@pytest.mark.parametrize("text,line,expect", [
    ("0 1 2\n", 1, "expected 4 fields"),
    ("0 1 2 3\n0 1 2 3 4\n", 2, "expected 4 fields"),
    ("0 1 2 3\n# ok\n0 1 -2 3\n", 3, "holding: a holding time must be >= 0"),
    ("0 1 x 3\n", 1, "holding: expected an exact time"),
    ("0 1 2/0 3\n", 1, "holding: expected an exact time"),
    ("1.5 2 3 4\n", 1, "src: expected a transition index"),
    ("0 -1 2 3\n", 1, "dst: expected a transition index"),
    ("0 1 2 3\n1 2 3 4.5\n", 2, "tokens: expected a token count"),
    ("0 1 2 99999999999999999999\n", 1, "tokens: a token count must be at most 2**63 - 1"),
    ("# node 0 a\n# node 1 a\n0 1 2 3\n", 2, "both named 'a'"),
])
def test_malformed_lines_are_named(text, line, expect):
    with pytest.raises(InputError) as info:
        parse_edges(text, "g.edges")
    assert info.value.line == line and expect in str(info.value)
    assert str(info.value).startswith(f"g.edges:{line}:")


def test_huge_holding_times_stay_exact():
    g = parse_edges("0 0 99999999999999999999/7 1\n")
    assert g.holding_time(0) == F(99999999999999999999, 7)
    assert parse_edges(dumps_edges(g)).holding_time(0) == F(99999999999999999999, 7)


@st.composite
def arc_lists(draw):
    m = draw(st.integers(0, 30))
    n = draw(st.integers(1, 8))
    ints = st.integers(0, n - 1)
    scale = draw(st.sampled_from([1, 2, 3, 10, 12]))
    return ArcList(np.array(draw(st.lists(ints, min_size=m, max_size=m)), dtype=np.int64),
                   np.array(draw(st.lists(ints, min_size=m, max_size=m)), dtype=np.int64),
                   np.array(draw(st.lists(st.integers(0, 10**12), min_size=m, max_size=m)),
                            dtype=np.int64),
                   np.array(draw(st.lists(st.integers(0, 9), min_size=m, max_size=m)),
                            dtype=np.int64), scale, None, n, "r")


@settings(max_examples=80)
@given(arc_lists())
def test_write_then_read_gives_the_same_arrays(g):
    back = parse_edges(dumps_edges(g))
    assert back.src.tolist() == g.src.tolist() and back.dst.tolist() == g.dst.tolist()
    assert back.tokens.tolist() == g.tokens.tolist() and back.n_transitions == g.n_transitions
    assert holdings(back) == holdings(g)


def test_half_a_million_lines_are_read_and_written_quickly(tmp_path):
    rng = np.random.default_rng(0)
    m = 500_000
    g = ArcList(rng.integers(0, 10**5, m), rng.integers(0, 10**5, m), rng.integers(0, 10**4, m),
                rng.integers(0, 9, m), 1, None, 10**5, "big")
    path = tmp_path / "big.edges"
    t0 = time.perf_counter()
    write_edges(g, path)
    back = read_edges(path)
    elapsed = time.perf_counter() - t0
    assert np.array_equal(back.holding, g.holding) and np.array_equal(back.src, g.src)
    # a Python loop per line takes several seconds here; the array path well under one
    assert elapsed < 5
