"""PNML: the MCC models, dialects, timing, round trips and every refusal."""

from __future__ import annotations

import json
import time
from fractions import Fraction as F

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import cycle_time
from tegraph.errors import InputError
from tegraph.io._xml import parse_xml
from tegraph.io.pnml import PNML_NAMESPACE, dumps_pnml, parse_pnml, read_pnml
from tegraph.model.petri import PetriNet
from tegraph.model.teg import TimedEventGraph

PT = "http://www.pnml.org/version-2009/grammar/ptnet"


def net_xml(body: str, type_: str = PT, root: str = "<pnml>", end: str = "</pnml>") -> str:
    return f'{root}<net id="n" type="{type_}"><page id="g">{body}</page></net>{end}'


RING = """
<place id="p"><initialMarking><text>1</text></initialMarking></place>
<place id="q"/>
<transition id="a"/><transition id="b"/>
<arc id="1" source="a" target="q"/><arc id="2" source="q" target="b"/>
<arc id="3" source="b" target="p"/><arc id="4" source="p" target="a"/>
"""


@pytest.fixture(scope="module")
def pnml_cases(anchors):
    return {c["file"]: c for c in json.loads((anchors / "pnml" / "cases.json").read_text())
            ["pnml_cases"]}


@pytest.mark.parametrize("name", ["CircularTrains-PT-012.pnml", "CircularTrains-PT-024.pnml",
                                  "CircularTrains-PT-048.pnml", "HouseConstruction-PT-00002.pnml",
                                  "HouseConstruction-PT-00005.pnml"])
def test_mcc_models_have_the_published_sizes(anchors, pnml_cases, name):
    net = read_pnml(anchors / "pnml" / name)
    size = pnml_cases[name]["size"]
    assert len(net.places) == size["places"] and len(net.transitions) == size["transitions"]
    assert int((net.pre > 0).sum() + (net.post > 0).sum()) == size["arcs"]
    assert int(net.marking.sum()) == size["initial_tokens"]
    assert net.holding == []  # MCC models carry no timing
    # MCC MARKED_GRAPH verdicts: true for CircularTrains, false (place p1) for HouseConstruction
    why = net.marked_graph_violation()
    assert (why is None) == name.startswith("CircularTrains")
    if why is not None:
        assert "'p1'" in why


def test_round_trip_keeps_the_net_and_its_ids(anchors):
    net = read_pnml(anchors / "pnml" / "HouseConstruction-PT-00002.pnml")
    text = dumps_pnml(net)
    back = parse_pnml(text)
    assert back.places == net.places and back.transitions == net.transitions
    assert (back.pre != net.pre).nnz == 0 and (back.post != net.post).nnz == 0
    assert np.array_equal(back.marking, net.marking) and back.name == net.name
    root = parse_xml(text.encode())
    assert root.tag == "pnml" and f'xmlns="{PNML_NAMESPACE}"' in text
    assert [n.attrs["type"] for n in root.all("net")] == [PT]
    assert len(list(root.iter("page"))) == 1


def test_timing_round_trip_gives_the_same_figures():
    g = TimedEventGraph("ring")
    for e in ("a", "b", "c"):
        g.add_transition(e)
    g.add_place("a", "b", 0, "7/3", name="ab")
    g.add_place("b", "c", 1, "1/2", initial="1/4", name="bc")
    g.add_place("c", "a", 1, 4, name="ca")
    g.add_place("b", "b", 1, 2, name="loop")
    text = dumps_pnml(g)
    back = parse_pnml(text).to_teg()
    assert [(p.name, p.src, p.dst, p.tokens, p.holding, p.initial) for p in back.places] == \
        [(p.name, p.src, p.dst, p.tokens, p.holding, p.initial) for p in g.places]
    # circuit a -> b -> c -> a: (7/3 + 1/2 + 4) / 2 = 41/12 > 2 (the self-loop)
    assert cycle_time(back).period == cycle_time(g).period == F(41, 12)
    # timing lives in the tool element only; inscription stays the arc weight
    root = parse_xml(text.encode())
    assert not list(root.iter("inscription"))
    tools = list(root.iter("toolspecific"))
    assert len(tools) == 4 and all(t.attrs["tool"] == "tegraph" and t.attrs["version"]
                                   for t in tools)
    assert [t.child("holding").text for t in tools] == ["7/3", "1/2", "4", "2"]


def test_weights_are_written_as_inscriptions_and_make_it_no_marked_graph():
    net = parse_pnml(net_xml(RING.replace('<arc id="4" source="p" target="a"/>',
                                          '<arc id="4" source="p" target="a"><inscription>'
                                          "<text> 3 </text></inscription></arc>")))
    assert net.pre[net.places.index("p"), net.transitions.index("a")] == 3
    back = parse_pnml(dumps_pnml(net))
    assert np.array_equal(back.pre.toarray(), net.pre.toarray())
    assert "weight 3" in net.marked_graph_violation()
    r = cycle_time(net)
    assert not r.applicable and "weight 3" in r.reason and r.exit_status == 1


@pytest.mark.parametrize("doc", [
    net_xml(RING),  # no namespace at all
    net_xml(RING, root=f'<pnml xmlns="{PNML_NAMESPACE}">'),
    f'<p:pnml xmlns:p="{PNML_NAMESPACE}"><p:net id="n" type="{PT}"><p:page id="g">'
    + RING.replace("<", "<p:").replace("<p:/", "</p:") + "</p:page></p:net></p:pnml>",
    net_xml(RING, type_="http://www.pnml.org/version-2009/grammar/pnmlcoremodel"),
])
def test_dialects_read_the_same_net(doc):
    net = parse_pnml(doc)
    assert net.places == ["p", "q"] and net.transitions == ["a", "b"]
    assert net.marking.tolist() == [1, 0]
    assert net.pre.tolist() == [[1, 0], [0, 1]] and net.post.tolist() == [[0, 1], [1, 0]]


def test_several_pages_nested_pages_and_reference_nodes():
    doc = f"""<pnml><net id="n" type="{PT}">
      <page id="g1"><place id="p"><initialMarking><text>1</text></initialMarking></place>
        <transition id="a"/>
        <page id="inner"><transition id="b"/><referencePlace id="rp" ref="p"/></page></page>
      <page id="g2"><place id="q"/><referenceTransition id="ra" ref="a"/>
        <arc id="1" source="ra" target="q"/><arc id="2" source="q" target="b"/>
        <arc id="3" source="b" target="rp"/><arc id="4" source="p" target="a"/></page>
    </net></pnml>"""
    net = parse_pnml(doc)
    assert sorted(net.places) == ["p", "q"] and sorted(net.transitions) == ["a", "b"]
    assert net.marked_graph_violation() is None


def test_unknown_toolspecific_is_ignored_and_names_are_kept():
    doc = net_xml(RING.replace('<place id="q"/>', '<place id="q"><name><text>buffer</text></name>'
                               '<toolspecific tool="other" version="9"><x>junk</x></toolspecific>'
                               "</place>"))
    net = parse_pnml(doc)
    assert net.places == ["p", "buffer"] and net.holding == []
    back = parse_pnml(dumps_pnml(net))
    assert back.places == ["p", "buffer"] and back.attrs["pnml_ids"]["places"] == ["p", "q"]


def test_tina_delay_is_the_firing_time_of_the_transition():
    tina = ('<delay><interval xmlns="http://www.w3.org/1998/Math/MathML" closure="closed">'
            "<cn>2</cn><cn>5</cn></interval></delay>")
    doc = net_xml(RING.replace('<transition id="a"/>', f'<transition id="a">{tina}</transition>'))
    net = parse_pnml(doc)
    # a's output place q holds a's lower bound 2; p holds 0
    assert dict(zip(net.places, net.holding)) == {"p": 0, "q": 2}
    assert cycle_time(net).period == 2  # the single circuit: (2 + 0) / 1 token


def test_written_timing_never_uses_the_tina_element():
    text = dumps_pnml(parse_pnml(net_xml(RING.replace(
        '<transition id="a"/>', '<transition id="a"><delay><interval><cn>3</cn><ci>infty</ci>'
        "</interval></delay></transition>"))))
    assert "<delay>" not in text and "<holding>3</holding>" in text


# ------------------------------------------------------------------ refusals


def refusal(doc: str) -> str:
    with pytest.raises(InputError) as info:
        parse_pnml(doc, "net.pnml")
    return str(info.value)


def test_truncated_xml_names_the_open_element_and_line():
    text = net_xml(RING)
    msg = refusal(text[: text.index("<arc")] + "\n<arc id='9' source='a'")
    assert "net.pnml:" in msg and "malformed XML" in msg and "page[g]" in msg


def test_missing_ids_are_refused():
    assert "<place> has no id" in refusal(net_xml(RING.replace('<place id="q"/>', "<place/>")))
    assert "<arc> has no id" in refusal(net_xml(RING.replace('<arc id="2"', "<arc")))


def test_arcs_to_unknown_nodes_are_refused():
    msg = refusal(net_xml(RING.replace('target="b"/>', 'target="zz"/>', 1)))
    assert "arc[2]" in msg and "'zz'" in msg and "not a place or transition" in msg


def test_arc_between_two_places_is_refused():
    msg = refusal(net_xml(RING + '<arc id="9" source="p" target="q"/>'))
    assert "arc[9]" in msg and "two places" in msg


@pytest.mark.parametrize("marking", ["1.5", "-1", "two"])
def test_non_integer_markings_are_refused(marking):
    msg = refusal(net_xml(RING.replace("<text>1</text>", f"<text>{marking}</text>")))
    assert "place[p]" in msg and "initialMarking" in msg and "net.pnml:" in msg


def test_negative_and_malformed_times_are_refused():
    bad = '<toolspecific tool="tegraph" version="1"><holding>-2</holding></toolspecific>'
    msg = refusal(net_xml(RING.replace('<place id="q"/>', f'<place id="q">{bad}</place>')))
    assert "place[q]" in msg and ">= 0" in msg
    bad = '<toolspecific tool="tegraph" version="1"><holding>soon</holding></toolspecific>'
    assert "exact time" in refusal(net_xml(RING.replace('<place id="q"/>',
                                                        f'<place id="q">{bad}</place>')))
    tina = "<delay><interval><cn>-1</cn><cn>2</cn></interval></delay>"
    msg = refusal(net_xml(RING.replace('<transition id="a"/>',
                                       f'<transition id="a">{tina}</transition>')))
    assert "transition[a]/delay" in msg


def test_other_structural_refusals():
    assert "holds 2 nets" in refusal(f'<pnml><net id="x" type="{PT}"/><net id="y" type="{PT}"/>'
                                     "</pnml>")
    assert "not supported" in refusal(net_xml(RING, type_="http://x/symmetricnet"))
    assert "duplicate id" in refusal(net_xml(RING + '<place id="a"/>'))
    assert "expected <pnml>" in refusal("<petri/>")


def test_entity_expansion_bomb_is_refused_quickly():
    lol = ['<!ENTITY lol0 "lol">'] + [f'<!ENTITY lol{k} "{f"&lol{k - 1};" * 10}">'
                                      for k in range(1, 10)]
    bomb = f'<?xml version="1.0"?><!DOCTYPE pnml [{"".join(lol)}]><pnml>&lol9;</pnml>'
    t0 = time.perf_counter()
    msg = refusal(bomb)
    assert time.perf_counter() - t0 < 1
    assert "DOCTYPE" in msg and "refused" in msg


def test_external_entity_is_never_fetched(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("do not read me")
    doc = (f'<?xml version="1.0"?><!DOCTYPE pnml [<!ENTITY x SYSTEM "file://{secret}">]>'
           "<pnml>&x;</pnml>")
    msg = refusal(doc)
    assert "DOCTYPE" in msg and "do not read me" not in msg


@st.composite
def nets(draw):
    n_p, n_t = draw(st.integers(1, 4)), draw(st.integers(1, 4))
    pre = np.array(draw(st.lists(st.lists(st.integers(0, 2), min_size=n_t, max_size=n_t),
                                 min_size=n_p, max_size=n_p)), dtype=np.int64)
    post = np.array(draw(st.lists(st.lists(st.integers(0, 2), min_size=n_t, max_size=n_t),
                                  min_size=n_p, max_size=n_p)), dtype=np.int64)
    marking = np.array(draw(st.lists(st.integers(0, 5), min_size=n_p, max_size=n_p)),
                       dtype=np.int64)
    timed = draw(st.booleans())
    hold = [F(draw(st.integers(0, 20)), draw(st.integers(1, 7))) for _ in range(n_p)]
    # a name of blanks only reads back as absent (the id is used): not drawn
    names = draw(st.lists(st.text("ab <&>\"'é", min_size=1, max_size=4).filter(str.strip),
                          min_size=n_p + n_t, max_size=n_p + n_t, unique=True))
    return PetriNet("r&d <net>", names[:n_p], names[n_p:], pre, post, marking,
                    hold if timed else [], [F(0)] * n_p if timed else [])


@settings(max_examples=60)
@given(nets())
def test_any_net_round_trips(net):
    back = parse_pnml(dumps_pnml(net))
    assert back.name == net.name and back.places == net.places
    assert back.transitions == net.transitions
    assert (back.pre != net.pre).nnz == 0 and (back.post != net.post).nnz == 0
    assert np.array_equal(back.marking, net.marking) and back.holding == net.holding
