"""Values of any size through every reader: held exactly, or refused naming the value and
the limit (``tegraph.model.limits``); never a traceback, a hang or a huge allocation.

Each input here is written by hand; the expected figures are derived in the comments.
"""

from __future__ import annotations

import json
from fractions import Fraction as F
from pathlib import Path

import pytest

import tegraph
from tegraph.errors import InputError
from tegraph.io import read
from tegraph.model.convert import as_petri_net, as_teg_like
from tegraph.model.sdf import SDFChannel, SDFGraph

MAX_COUNT = 2**63 - 1  # the largest token count (tegraph.model.limits.MAX_COUNT)
BIG = MAX_COUNT + 1
HUGE_TIME = 2**70 + 1  # a time past 64 bits, kept exact


def teg_file(duration: str, tokens: str) -> str:
    return f"TimedEventGraph 1 1\n0 0: {duration} {tokens}\n"


def tpne_json(tokens: object = 1, duration: str = "1", caption: str = '"P0"',
              name: str = '"n"') -> str:
    return ('{"revision": 4, "type": "Timed event graph", "nets": [{"name": ' + name
            + ', "places": [{"id": 0, "caption": ' + caption + f', "tokens": {tokens}'
            + '}], "transitions": [{"id": 0, "caption": "T0"}], "arcs": [{"from": "T0", '
            + f'"to": "P0", "duration": {duration}' + '}, {"from": "P0", "to": "T0"}]}]}')


def pnml_file(marking: str = "1", holding: str = "1") -> str:
    return ('<pnml><net id="n" type="http://www.pnml.org/version-2009/grammar/ptnet">'
            '<page id="g"><place id="p"><initialMarking><text>' + marking
            + '</text></initialMarking><toolspecific tool="tegraph" version="1"><holding>'
            + holding + '</holding></toolspecific></place><transition id="t"/>'
            '<arc id="a1" source="p" target="t"/><arc id="a2" source="t" target="p"/>'
            '</page></net></pnml>')


def sdf3_file(tokens: str = "1", time: str = "5", prod: str = "1", cons: str = "1") -> str:
    """Actor a -> b (rates prod, cons) and b -> a (rates cons, prod) holding the tokens."""
    return ('<sdf3 type="sdf"><applicationGraph name="x"><sdf name="x">'
            f'<actor name="a"><port name="o" type="out" rate="{prod}"/>'
            f'<port name="i" type="in" rate="{prod}"/></actor>'
            f'<actor name="b"><port name="o" type="out" rate="{cons}"/>'
            f'<port name="i" type="in" rate="{cons}"/></actor>'
            '<channel name="ab" srcActor="a" srcPort="o" dstActor="b" dstPort="i"/>'
            '<channel name="ba" srcActor="b" srcPort="o" dstActor="a" dstPort="i" '
            f'initialTokens="{tokens}"/></sdf><sdfProperties><actorProperties actor="a">'
            f'<processor type="p" default="true"><executionTime time="{time}"/></processor>'
            '</actorProperties></sdfProperties></applicationGraph></sdf3>')


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def refused(path: Path, *expected: str) -> InputError:
    with pytest.raises(InputError) as info:
        read(path)
    for text in (str(path), *expected):
        assert text in str(info.value)
    return info.value


# ------------------------------------------------------------------ big counts

@pytest.mark.parametrize("name, text, where", [
    ("big.teg", teg_file("1", str(BIG)), "tokens"),
    ("big.json", tpne_json(tokens=BIG), "nets[0].places[0].tokens"),
    ("big.pnml", pnml_file(marking=str(BIG)), "place[p]"),
    ("big.sdf3", sdf3_file(tokens=str(BIG)), "channel[ba]"),
    ("big.edges", f"0 0 1 {BIG}\n", "tokens"),
    ("rate.sdf3", sdf3_file(prod=str(BIG)), "actor[a]/port[o]"),
], ids=lambda v: v if isinstance(v, str) and len(v) < 12 else "")
def test_token_counts_above_64_bits_are_refused_naming_the_limit(tmp_path, name, text, where):
    # before: OverflowError "Python int too large to convert to C long" (a traceback)
    error = refused(write(tmp_path, name, text), str(BIG), "2**63 - 1")
    assert error.where == where


def test_the_largest_token_count_is_exact(tmp_path):
    # one place T0 -> T0 holding 3 with 2**63 - 1 tokens: period 3 / (2**63 - 1)
    for name, text in (("top.teg", teg_file("3", str(MAX_COUNT))),
                       ("top.json", tpne_json(tokens=MAX_COUNT, duration="3"))):
        r = tegraph.cycle_time(write(tmp_path, name, text))
        assert r.period == F(3, MAX_COUNT) and r.certificate_verified


@pytest.mark.parametrize("name, text", [
    ("t.teg", teg_file(str(HUGE_TIME), "1")),
    ("t.json", tpne_json(duration=str(HUGE_TIME))),
    ("t.pnml", pnml_file(holding=str(HUGE_TIME))),
    ("t.sdf3", sdf3_file(time=str(HUGE_TIME))),  # before: OverflowError in the expansion
    ("t.edges", f"0 0 {HUGE_TIME} 1\n"),
], ids=lambda v: v if len(v) < 12 else "")
def test_times_past_64_bits_stay_exact_through_every_reader(tmp_path, name, text):
    # one token on a circuit whose only timed place holds 2**70 + 1: that is the period
    r = tegraph.cycle_time(write(tmp_path, name, text))
    assert r.period == HUGE_TIME and r.certificate_verified


def test_parallel_pnml_arcs_adding_past_64_bits_are_refused(tmp_path):
    arc = ('<arc id="{}" source="p" target="t"><inscription><text>' + str(MAX_COUNT)
           + "</text></inscription></arc>")
    text = pnml_file().replace("</page>", arc.format("x1") + arc.format("x2") + "</page>")
    refused(write(tmp_path, "w.pnml", text), "weigh", "2**63 - 1", "arc[x1]")


# ------------------------------------------------------------------ lone surrogates

@pytest.mark.parametrize("field, where", [
    ("caption", "nets[0].places[0].caption"), ("name", "nets[0].name")])
def test_a_lone_surrogate_in_a_tpne_name_is_refused_where_it_is_read(tmp_path, field, where):
    # before: read, then UnicodeEncodeError when the report or a converted file was written
    text = tpne_json(**{field: '"P\\ud800"'})
    assert refused(write(tmp_path, "s.json", text), "lone surrogate", "U+D800").where == where


# ------------------------------------------------------------------ deep nesting

def test_deeply_nested_tpne_json_is_refused(tmp_path):
    # before: RecursionError from the JSON parser
    text = '{"nets": ' + "[" * 3000 + "]" * 3000 + "}"
    refused(write(tmp_path, "deep.json", text), "nested too deeply")


def test_a_caption_that_is_no_text_is_refused(tmp_path):
    text = tpne_json(caption="[[1]]")
    assert refused(write(tmp_path, "c.json", text), "expected a text").where == \
        "nets[0].places[0].caption"


# ----------------------------------------------- counts a file declares beyond memory

@pytest.mark.parametrize("name, text, line", [
    # before: MemoryError (an attempt to allocate for 10**11 transitions)
    ("index.edges", "0 99999999999 1 0\n", 1),
    ("header.edges", "# nodes 100000000000\n0 0 1 1\n", 1),
    ("named.edges", "0 0 1 1\n# node 5000000 far\n", 2),
    ("digits.edges", "# node " + "9" * 30 + " far\n0 0 1 1\n", 1),
    # before: 50 million transitions created one by one (minutes, gigabytes)
    ("many.teg", "TimedEventGraph 50000000 1\n0 0: 1 1\n", 1),
], ids=lambda v: v if isinstance(v, str) and len(v) < 14 else "")
def test_node_counts_are_bounded_by_the_file_size(tmp_path, name, text, line):
    error = refused(write(tmp_path, name, text), "2**20")
    assert error.line == line


def test_isolated_nodes_within_the_bound_are_kept(tmp_path):
    # 1000 declared transitions, one place: 999 isolated transitions, as the file says
    g = read(write(tmp_path, "iso.edges", "# nodes 1000\n0 0 1 1\n"))
    assert g.n_transitions == 1000
    g = read(write(tmp_path, "iso.teg", "TimedEventGraph 1000 1\n0 0: 1 1\n"))
    assert g.n_transitions == 1000


# ------------------------------------------------------------------ huge numbers

NUMBERS = {"exponent": "1e999999999", "negative-exponent": "1e-100000000",
           "exponent-5000": "1E+5000", "5000-digits": "9" * 5000}


@pytest.mark.parametrize("kind, number", [
    (kind, number) for kind in ("edges", "teg", "json", "pnml", "sdf3") for number in NUMBERS
    if kind != "sdf3" or number == "5000-digits"])  # SDF3 times are integers
def test_huge_number_texts_are_refused_before_they_are_expanded(tmp_path, kind, number):
    # before: Fraction("1e999999999") builds a billion-digit integer (hours); 5000 digits
    # raised ValueError (a traceback) in the JSON, PNML and .edges readers
    text = NUMBERS[number]
    content = {"edges": f"0 0 {text} 1\n", "teg": teg_file(text, "1"),
               "json": tpne_json(duration=text), "pnml": pnml_file(holding=text),
               "sdf3": sdf3_file(time=text)}[kind]
    # one bound for every reader (maxplus.scalar.MAX_DIGITS), stated by the value's size
    size = {"exponent": "has 1,000,000,000 digits", "negative-exponent":
            "has a denominator of more than 4,300 digits", "exponent-5000": "has 5,001 digits",
            "5000-digits": "has 5,000 digits"}[number]
    error = refused(write(tmp_path, f"n.{kind}", content), size, "at most 4,300 are accepted")
    assert "9" * 100 not in str(error)  # never echoed in full


def test_a_long_integer_in_tpne_json_is_refused_not_a_traceback(tmp_path):
    # before: ValueError "Exceeds the limit (4300 digits)", a traceback
    error = refused(write(tmp_path, "i.json", tpne_json(tokens="9" * 5000)),
                    "5,000 digits; at most 4,300 are accepted")
    assert error.line == 1


def test_an_exponent_within_the_limit_is_exact(tmp_path):
    # 1e3 = 1000 and 25e-2 = 1/4, read exactly by every reader that takes decimals
    for name, text in (("e.teg", teg_file("1e3", "4")), ("e.edges", "0 0 1e3 4\n"),
                       ("e.pnml", pnml_file(marking="4", holding="1e3")),
                       ("e.json", tpne_json(tokens=4, duration="1e3"))):
        assert tegraph.cycle_time(write(tmp_path, name, text)).period == 250
    assert tegraph.cycle_time(write(tmp_path, "q.teg", teg_file("25e-2", "1"))).period == F(1, 4)


def test_a_common_denominator_beyond_the_limit_is_refused(tmp_path):
    # 1/p for the first 1600 primes: their product has more than 4300 digits
    primes, k = [], 2
    while len(primes) < 1600:
        if all(k % p for p in primes if p * p <= k):
            primes.append(k)
        k += 1
    text = "".join(f"0 0 1/{p} 1\n" for p in primes)
    refused(write(tmp_path, "den.edges", text), "common denominator", "4300")
    places = "".join(f'<place id="p{p}"><toolspecific tool="tegraph" version="1"><holding>1/{p}'
                     "</holding></toolspecific></place>" for p in primes)
    text = pnml_file().replace("</page>", places + "</page>")
    refused(write(tmp_path, "den.pnml", text), "common denominator", "4300")


# ------------------------------------------------------------------ SDF expansion

def test_an_sdf_expansion_above_max_firings_is_refused_from_the_repetition_vector(tmp_path):
    # a -> b at rates 10**8 : 1: q = (1, 10**8), 100,000,001 firings an iteration
    # expanded, it would end in a MemoryError
    path = write(tmp_path, "wide.sdf3", sdf3_file(prod="100000000", cons="1"))
    g = read(path)
    assert g.repetition_vector() == {"a": 1, "b": 10**8}
    with pytest.raises(InputError) as info:
        tegraph.cycle_time(path)
    assert info.value.where == "max_firings" and info.value.file == str(path)
    assert "100000001 firings" in str(info.value) and "10000000" in str(info.value)


def test_coprime_rates_of_a_billion_are_refused_at_once(tmp_path):
    # rates 10**9 and 10**9 + 1 are coprime: q = (10**9 + 1, 10**9), 2 * 10**9 + 1
    # firings and 10**18 + 10**9 token transfers an iteration (before: a hang)
    path = write(tmp_path, "coprime.sdf3", sdf3_file(prod=str(10**9), cons=str(10**9 + 1)))
    assert read(path).expansion_size() == (2 * 10**9 + 1, 2 * (10**9 + 1) * 10**9)
    for target in ("out.pnml", "out.edges"):
        with pytest.raises(InputError, match="2000000001 firings"):
            tegraph.write(read(path), tmp_path / target)


def test_max_firings_is_a_parameter():
    # a -> b, rates 2 : 1, two tokens back: q = (1, 2), 3 firings, 2 + 2 = 4 transfers
    g = SDFGraph("g", {"a": 1, "b": 1}, [SDFChannel("ab", "a", "b", 2, 1, 0),
                                         SDFChannel("ba", "b", "a", 1, 2, 2)])
    assert g.expansion_size() == (3, 4)
    assert g.to_arcs(max_firings=4).n_transitions == 3
    with pytest.raises(InputError, match="4 token transfers"):
        g.to_arcs(max_firings=3)
    # the conversions pass it on
    assert len(as_petri_net(g, max_firings=4).transitions) == 3
    with pytest.raises(InputError, match="above the limit of 3"):
        as_teg_like(g, max_firings=3)


def test_the_reports_of_huge_values_are_written(tmp_path):
    # a time past 64 bits goes out as exactly as it came in
    g = read(write(tmp_path, "t.json", tpne_json(duration=str(HUGE_TIME))))
    out = tegraph.write(g, tmp_path / "back.json")
    assert json.loads(out.read_text())["nets"][0]["arcs"][0]["duration"] == HUGE_TIME


# ------------------------------------------------------------------ found by the fuzz test

def test_an_unknown_xml_encoding_is_refused(tmp_path):
    # before: LookupError from expat (a traceback)
    text = '<?xml version="1.0" encoding="aTF-8"?>' + pnml_file()
    refused(write(tmp_path, "enc.pnml", text), "unknown encoding", "aTF-8")


@pytest.mark.parametrize("text, where", [
    ("TimedEventGraph " + "9" * 5000 + " 1\n0 0: 1 1\n", "header"),
    ("TimedEventGraph 1 " + "9" * 5000 + "\n0 0: 1 1\n", "header"),
    ("TimedEventGraph 1 1\n0 " + "9" * 5000 + ": 1 1\n", "j"),
], ids=["transitions", "lines", "index"])
def test_teg_numbers_of_thousands_of_digits_are_refused(tmp_path, text, where):
    # before: ValueError "Exceeds the limit (4300 digits)" (a traceback)
    assert refused(write(tmp_path, "d.teg", text), "(5000 characters)").where == where
