"""read/write dispatch, `tegraph convert`, size limits, refusals through the CLI, and
the published JSON schema checked against every JSON output of the command line."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from fractions import Fraction as F

import jsonschema
import pytest
from typer.testing import CliRunner

import tegraph
from tegraph import cycle_time
from tegraph.cli import _size, app
from tegraph.errors import InputError
from tegraph.io import detect_format
from tegraph.model.arcs import ArcList
from tegraph.model.petri import PetriNet
from tegraph.model.sdf import SDFGraph
from tegraph.model.skeleton import Skeleton
from tegraph.model.teg import TimedEventGraph
from tests.paths import REPO

SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())


def run(*args: str) -> subprocess.CompletedProcess:
    """The command line in this process (fast); ``spawn`` runs it as a real process."""
    result = CliRunner().invoke(app, list(args))
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception  # an uncaught error would be a traceback for the user
    return subprocess.CompletedProcess(args, result.exit_code, result.stdout, result.stderr)


def spawn(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args],
                          capture_output=True, text=True, timeout=120, check=False)


def validate(doc: dict) -> None:
    jsonschema.Draft202012Validator(SCHEMA).validate(doc)


@pytest.mark.parametrize("rel,fmt,kind", [
    ("pnml/CircularTrains-PT-012.pnml", "pnml", PetriNet),
    ("sdf/xml/modem.xml", "sdf3", SDFGraph),
    ("sdf/hsdf_edges/modem.hsdf.edges", "edges", ArcList),
    ("teg/Howard2.json", "tpne-json", PetriNet),
    ("teg/SemiHoward.teg", "tpne-teg", TimedEventGraph),
])
def test_read_picks_the_reader_from_the_file(anchors, rel, fmt, kind):
    assert detect_format(anchors / rel) == fmt
    assert isinstance(tegraph.read(anchors / rel), kind)


def test_content_sniffing_without_a_telling_extension(anchors, tmp_path):
    for rel, fmt in (("pnml/CircularTrains-PT-012.pnml", "pnml"), ("sdf/xml/modem.xml", "sdf3"),
                     ("teg/SemiHoward.teg", "tpne-teg"), ("teg/Howard2.json", "tpne-json")):
        copy = tmp_path / f"{fmt}.data"
        copy.write_bytes((anchors / rel).read_bytes())
        assert detect_format(copy) == fmt
    plain = tmp_path / "arcs.txt"
    plain.write_text("# arcs\n0 1 2 0\n1 0 3 1\n")
    assert detect_format(plain) == "edges"
    skeleton = tmp_path / "s.json"
    skeleton.write_text('{"tasks": {"A": {"duration": 1, "period": 2}}}')
    assert isinstance(tegraph.read(skeleton), Skeleton)


def test_size_limit_refuses_large_files_unless_raised(anchors):
    path = anchors / "pnml" / "CircularTrains-PT-048.pnml"  # 37,115 bytes
    with pytest.raises(InputError, match="above the limit of 1024"):
        tegraph.read(path, max_bytes=1024)
    out = run("cycle-time", str(path), "--max-size", "10k")
    assert out.returncode == 2 and "above the limit" in out.stderr and "--max-size" in out.stderr
    assert run("cycle-time", str(path), "--max-size", "1M").returncode == 0
    assert _size("1M", "--max-size") == 2**20
    bad = run("cycle-time", str(path), "--max-size", "12Q")
    assert bad.returncode == 2 and bad.stderr == (
        "tegraph: error: --max-size: expected a size such as 300M or 2G, got '12Q'\n")


# ------------------------------------------------------------------ convert


@pytest.mark.parametrize("rel,period", [
    ("teg/SemiNetherlands.teg", F(143, 3)),    # cases.json
    ("teg/Howard2.json", F(13, 2)),            # cases.json
    ("sdf/xml/modem.xml", F(16)),              # sdf/cases.json
])
@pytest.mark.parametrize("ext", [".pnml", ".edges", ".teg", ".json", ".sdf3"])
def test_conversions_keep_the_period(anchors, tmp_path, rel, period, ext):
    target = tmp_path / f"out{ext}"
    out = run("convert", str(anchors / rel), str(target))
    assert out.returncode == 0, out.stderr
    assert cycle_time(target).period == period


def test_multi_rate_sdf3_stays_multi_rate(anchors, tmp_path):
    target = tmp_path / "modem.sdf3"
    assert run("convert", str(anchors / "sdf/xml/modem.xml"), str(target)).returncode == 0
    assert tegraph.read(target).repetition_vector()["in"] == 16  # sdf/cases.json


def test_a_skeleton_becomes_a_teg_never_the_reverse(tmp_path):
    sk = tmp_path / "s.yaml"
    sk.write_text("tasks:\n  A: {duration: 2, period: 10}\n")
    assert run("convert", str(sk), str(tmp_path / "s.pnml")).returncode == 0
    # the clock self-loop holds the period 10 (spec §2), a's return place 2
    assert cycle_time(tmp_path / "s.pnml").period == 10
    out = run("convert", str(tmp_path / "s.pnml"), str(tmp_path / "back.yaml"))
    assert out.returncode == 2 and "not the other way round" in out.stderr
    assert not (tmp_path / "back.yaml").exists()


def test_a_net_that_is_no_marked_graph_only_goes_to_net_formats(anchors, tmp_path):
    src = str(anchors / "pnml" / "HouseConstruction-PT-00002.pnml")
    out = run("convert", src, str(tmp_path / "h.edges"))
    assert out.returncode == 2 and "not a marked graph" in out.stderr and "p1" in out.stderr
    for ext in (".json", ".dot", ".pnml"):
        assert run("convert", src, str(tmp_path / f"h{ext}")).returncode == 0


def test_convert_never_overwrites_without_force(anchors, tmp_path):
    target = tmp_path / "x.edges"
    target.write_text("keep me")
    src = str(anchors / "teg" / "SemiHoward.teg")
    out = run("convert", src, str(target))
    assert out.returncode == 2 and "--force" in out.stderr and target.read_text() == "keep me"
    assert run("convert", src, str(target), "--force").returncode == 0
    assert tegraph.read(target).n_places == 5


# ------------------------------------------------------------------ refusals via the CLI

PT = 'type="http://www.pnml.org/version-2009/grammar/ptnet"'
GOOD_PLACE = '<place id="p"><initialMarking><text>1</text></initialMarking></place>'
LOL = "".join(f'<!ENTITY l{k} "{f"&l{k - 1};" * 10 if k else "lol"}">' for k in range(10))

NET = f'<pnml><net id="n" {PT}><page id="g">'
END = "</page></net></pnml>"
SDF = '<sdf3 type="sdf"><applicationGraph><sdf name="s">'

MALFORMED = {
    "truncated.pnml": (f'{NET}{GOOD_PLACE}<transition id="t"', "malformed XML"),
    "noid.pnml": (f"{NET}<place/>{END}", "<place> has no id"),
    "unknown.pnml": ((f'{NET}{GOOD_PLACE}<transition id="t"/>'
                     f'<arc id="a" source="p" target="ghost"/>{END}'), "'ghost'"),
    "marking.pnml": ((f'{NET}<place id="p"><initialMarking><text>2.5</text></initialMarking>'
                     f"</place>{END}"), "place[p]: initialMarking must be an integer"),
    "negative.pnml": ((f'{NET}<place id="p"><toolspecific tool="tegraph" version="1">'
                      f"<holding>-1</holding></toolspecific></place>{END}"),
                      "holding must be >= 0"),
    "bomb.pnml": (f'<?xml version="1.0"?><!DOCTYPE pnml [{LOL}]><pnml>&l9;</pnml>', "DOCTYPE"),
    "time.edges": ("0 1 -5 1\n", "holding time must be >= 0"),
    "fields.edges": ("0 1 5\n", "expected 4 fields"),
    "tokens.xml": ((f'{SDF}<actor name="a"><port name="o" type="out" rate="1"/>'
                   '<port name="i" type="in" rate="1"/></actor><channel name="c" srcActor="a" '
                   'srcPort="o" dstActor="a" dstPort="i" initialTokens="x"/></sdf>'
                   "</applicationGraph></sdf3>"), "channel[c]"),
    "exec.xml": ((f'{SDF}<actor name="a"/></sdf><sdfProperties><actorProperties actor="a">'
                 '<processor type="p" default="1"><executionTime time="-3"/></processor>'
                 "</actorProperties></sdfProperties></applicationGraph></sdf3>"),
                 "executionTime must be an integer >= 0"),
    "arc.json": (('{"nets": [{"places": [{"id": 0}], "transitions": [], '
                 '"arcs": [{"from": "P0", "to": "T7"}]}]}'), "nets[0].arcs[0].to"),
    "header.teg": ("TimedEventGraph 2\n0 1: 1 1\n", "header"),
    "empty.edges": ("", None),
}


@pytest.mark.parametrize("name", sorted(MALFORMED))
def test_malformed_files_exit_2_with_one_line_naming_the_element(tmp_path, name):
    text, expect = MALFORMED[name]
    path = tmp_path / name
    path.write_text(text)
    t0 = time.perf_counter()
    # a few in a real process: what the user sees, tracebacks included
    out = (spawn if name in ("bomb.pnml", "truncated.pnml", "time.edges") else run)(
        "cycle-time", str(path))
    if expect is None:  # an empty arc list is a valid graph without circuit
        assert out.returncode == 0, out.stderr
        return
    assert time.perf_counter() - t0 < 30
    assert out.returncode == 2, (out.stdout, out.stderr)
    assert "Traceback" not in out.stderr and out.stderr.count("\n") == 1
    assert out.stderr.startswith("tegraph: error: ") and str(path) in out.stderr
    assert expect in out.stderr
    assert run("convert", str(path), str(tmp_path / "out.pnml")).returncode == 2


def test_unknown_format_and_missing_file_exit_2(tmp_path):
    odd = tmp_path / "x.bin"
    odd.write_bytes(b"\x00\x01garbage")
    out = run("cycle-time", str(odd))
    assert out.returncode == 2 and "cannot tell the format" in out.stderr
    out = run("cycle-time", str(tmp_path / "missing.pnml"))
    assert out.returncode == 2 and "cannot read the file" in out.stderr


# ------------------------------------------------------------------ the JSON schema


def test_schema_is_a_valid_2020_12_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("example", sorted((REPO / "examples").glob("*.yaml")),
                         ids=lambda p: p.stem)
def test_every_analyze_report_matches_the_schema(example):
    out = run("analyze", str(example), "--json")
    assert out.returncode in (0, 1), out.stderr
    doc = json.loads(out.stdout)
    validate(doc)
    assert doc["schema_version"] == 2


@pytest.mark.parametrize("rel", [
    "pnml/CircularTrains-PT-012.pnml", "pnml/HouseConstruction-PT-00002.pnml",
    "teg/Howard2.json", "teg/EventGraph.json", "teg/SemiHoward.teg", "teg/SemiNetherlands.teg",
    "sdf/xml/samplerate.xml", "sdf/hsdf_edges/h263encoder.hsdf.edges",
])
def test_every_cycle_time_report_matches_the_schema(anchors, rel):
    out = run("cycle-time", str(anchors / rel), "--json")
    doc = json.loads(out.stdout)
    validate(doc)
    assert doc["schema_version"] == 2 and doc["report"] == "cycle-time"
    assert out.returncode == (1 if "House" in rel else 0)


def test_deadlock_report_matches_the_schema(tmp_path):
    path = tmp_path / "dead.edges"
    path.write_text("0 1 1 0\n1 0 1 0\n")  # a circuit without token
    out = run("cycle-time", str(path), "--json")
    doc = json.loads(out.stdout)
    validate(doc)
    assert out.returncode == 1 and doc["deadlock"]["token_free_circuit"] in (["0", "1"],
                                                                             ["1", "0"])


@pytest.mark.parametrize("example", sorted((REPO / "examples").glob("*.yaml")),
                         ids=lambda p: p.stem)
@pytest.mark.parametrize("timed", [False, True], ids=["untimed", "timed"])
def test_every_reach_report_matches_the_schema(example, timed):
    out = run("reach", str(example), "--json", "--max-states", "20000",
              *(["--timed"] if timed else []))
    assert out.returncode in (0, 1), out.stderr
    doc = json.loads(out.stdout)
    validate(doc)
    assert doc["report"] == "reach" and doc["mode"] == ("timed" if timed else "untimed")


def test_reach_report_on_a_pnml_net_matches_the_schema(anchors):
    out = run("reach", str(anchors / "pnml" / "HouseConstruction-PT-00002.pnml"), "--json")
    doc = json.loads(out.stdout)
    validate(doc)
    assert out.returncode == 1 and doc["deadlock"] is True


@pytest.mark.parametrize("example", sorted((REPO / "examples").glob("*.yaml")),
                         ids=lambda p: p.stem)
def test_every_rules_report_matches_the_schema(example):
    links = tegraph.read(example).links
    chain = ["--chain", f"{links[0].writer[0]},{links[0].reader[0]}"] if links else []
    out = run("rules", str(example), "--json", *chain)
    assert out.returncode in (0, 1), out.stderr
    doc = json.loads(out.stdout)
    validate(doc)
    assert doc["report"] == "rules" and len(doc["latency"]) >= bool(links)


def test_schema_rejects_a_report_that_breaks_it():
    with pytest.raises(jsonschema.ValidationError):
        validate({"schema_version": 2, "report": "cycle-time", "period": 2.5})
    good = json.loads(run("reach", str(REPO / "examples" / "fig4_pipeline_synchronized.yaml"),
                          "--json").stdout)
    validate(good)
    with pytest.raises(jsonschema.ValidationError):  # an unknown key
        validate({**good, "extra": 1})
    with pytest.raises(jsonschema.ValidationError):  # a float where the count is an integer
        validate({**good, "states": 2.5})
