"""Skeleton files at the edges: what aliases add is bounded (not the size of a file), a file
of another format is named, names that no file could hold are refused where they are read,
and only skeleton extensions are written."""

from __future__ import annotations

import json
import subprocess
import sys
import time

import pytest
import yaml
from typer.testing import CliRunner

import tegraph.io._skeleton_yaml as _skeleton_yaml
import tegraph.io.skeleton_file as skeleton_file
from tegraph import Skeleton
from tegraph.cli import app
from tegraph.errors import InputError, SkeletonError
from tegraph.io import dump_skeleton, load_skeleton
from tegraph.model.skeleton.checks import Locator
from tests.paths import ANCHORS, REPO

# ------------------------------------------------------------------ aliases


def test_an_ordinary_file_above_the_alias_budget_is_read(tmp_path, monkeypatch):
    """No anchor, no alias: nothing is expanded, so no budget applies, however large.

    The budget is lowered to 4,000 so that a file of 300 generated tasks (some 4,800
    nodes) stands for the 16 MB file of 100,000 tasks (1.6 million nodes), which the
    budget must not refuse for its plain size ("expands to more than 1000000 elements
    through aliases"): composing a million YAML nodes is slow in PyYAML itself.
    """
    generated = tmp_path / "generated.yaml"  # the generator writes JSON, which is YAML
    subprocess.run([sys.executable, str(REPO / "benchmarks" / "generate_skeleton.py"), "300",
                    "-o", str(generated)], check=True)
    path = tmp_path / "big.yaml"  # the same skeleton in block YAML, for the YAML reader
    path.write_text(yaml.safe_dump(json.loads(generated.read_text()), sort_keys=False))
    assert "&" not in path.read_text() and "*" not in path.read_text()
    expected = load_skeleton(path)
    monkeypatch.setattr(_skeleton_yaml, "_MAX_ELEMENTS", 4_000)
    assert load_skeleton(path) == expected and len(expected.tasks) == 300
    loader = _skeleton_yaml._Loader(path.read_text())
    distinct, built = _skeleton_yaml._expansion(loader.get_single_node())
    loader.dispose()
    assert distinct == built > 4_000  # every node once: nothing added by aliases
    # JSON text in a .yaml file goes to the JSON parser: the same skeleton, faster
    assert load_skeleton(generated) == expected


def test_json_text_in_a_yaml_file_reads_as_yaml_would(tmp_path):
    # exact numbers, names YAML 1.1 would read as booleans, and a refusal with its line
    text = ('{"tasks": {"on": {"duration": 0.1, "period": "7/3", "outputs": ["yes"]},\n'
            '  "B": {"duration": 1e-3, "inputs": ["yes"]}},\n'
            ' "links": [{"from": "on:yes", "to": "B:yes", "protocol": "ASYN/SYN"}]}\n')
    (tmp_path / "a.yaml").write_text(text)
    (tmp_path / "a.json").write_text(text)
    from_yaml = Skeleton.from_dict(skeleton_file._read_yaml(text, Locator()), "a")
    assert load_skeleton(tmp_path / "a.yaml") == from_yaml == load_skeleton(tmp_path / "a.json")
    (tmp_path / "b.yaml").write_text(text.replace('"ASYN/SYN"', '"ASYN"'))
    with pytest.raises(SkeletonError) as info:
        load_skeleton(tmp_path / "b.yaml")
    assert info.value.line == 3 and info.value.where == "links[0].protocol"
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "a.yaml").write_text(text.replace("}}\n", "}}  # YAML, not JSON\n", 1))
    assert load_skeleton(tmp_path / "c" / "a.yaml") == from_yaml  # not JSON: the YAML reader


def billion_laughs(levels: int) -> str:
    """``a0`` is ten texts; each ``a{i}`` ten aliases of the previous: 10**levels texts."""
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]"
              for i in range(1, levels)]
    return "\n".join(lines) + "\ntasks:\n  A: {duration: 1}\n"


def test_an_alias_bomb_is_refused_before_anything_is_built(tmp_path):
    # 10 levels: a_i is built as s_i = 1 + 10 s_(i-1) nodes, s_0 = 11: the repunits of
    # 2 to 11 digits, summing to 12,345,679,010. The other nodes (the root, its 11 keys,
    # the task's 5) are 17, so 12,345,679,027 are built; composed there are 37 (the ten
    # lists, a0's ten texts and those 17): aliases add 12,345,678,990
    path = tmp_path / "bomb.yaml"
    path.write_text(billion_laughs(10))
    t0 = time.perf_counter()
    with pytest.raises(SkeletonError, match="aliases add 12345678990 elements"):
        load_skeleton(path)
    assert time.perf_counter() - t0 < 5  # refused from the count; building it would take hours


def test_aliases_below_the_budget_still_build_and_above_it_are_refused(tmp_path, monkeypatch):
    # 3 levels: built 11 + 111 + 1111 = 1233 nodes, composed 33: aliases add 1200, within
    # twice a budget of 1000, so the builder counts them, one node built again at a time
    path = tmp_path / "laughs.yaml"
    path.write_text(billion_laughs(3))
    with pytest.raises(SkeletonError, match="unknown key 'a0'"):  # built, then refused
        load_skeleton(path)
    monkeypatch.setattr(_skeleton_yaml, "_MAX_ELEMENTS", 1_000)
    with pytest.raises(SkeletonError, match="aliases add more than 1000 elements"):
        load_skeleton(path)


def test_merge_keys_are_an_alias_like_any_other(tmp_path):
    path = tmp_path / "merge.yaml"
    path.write_text("clocks:\n  c: &base {period: 10, phase: 1}\n"
                    "tasks:\n  A: {duration: 1, clock: c}\n"
                    "  B:\n    <<: {duration: 2}\n    clock: c\n")
    sk = load_skeleton(path)
    assert sk.tasks["B"].duration == 2 and sk.clocks["c"].phase == 1


# ------------------------------------------------------------------ other formats

@pytest.mark.parametrize("anchor, what", [
    ("pnml/HouseConstruction-PT-00002.pnml", "this is a PNML net"),
    ("sdf/xml/modem.xml", "this is an SDF3 graph"),
    ("teg/Howard2.json", "this is a TimedPetriNetEditor net (JSON)"),
    ("teg/SemiHoward.teg", "this is a TimedPetriNetEditor timed event graph (.teg)"),
    ("sdf/hsdf_edges/modem.hsdf.edges", "this is an arc list (.edges)"),
])
def test_a_file_of_another_format_is_named_with_the_commands_that_read_it(
        anchor, what, tmp_path):
    # before: "got the text '<?xml ...'" for PNML, "missing tasks" for the JSON net...
    source = ANCHORS / anchor
    for path in (source, tmp_path / "renamed.yaml"):
        if path != source:
            path.write_bytes(source.read_bytes())
        with pytest.raises(InputError) as info:
            load_skeleton(path)
        assert str(info.value) == (f"{path}: {what}, not a skeleton file; `tegraph "
                                   "cycle-time` and `tegraph reach` read it "
                                   "(tegraph.io.read in Python)")
    out = CliRunner().invoke(app, ["analyze", str(source)])
    assert out.exit_code == 2 and out.stderr.count("\n") == 1 and what in out.stderr


def test_a_skeleton_that_merely_mentions_other_formats_is_read(tmp_path):
    # a task called nets, a comment with <pnml>: the file is a skeleton, read as one
    path = tmp_path / "mention.json"
    path.write_text('{"tasks": {"nets": {"duration": 1}}, "name": "<pnml> and revision"}')
    assert set(load_skeleton(path).tasks) == {"nets"}


# ------------------------------------------------------------------ surrogates

@pytest.mark.parametrize("text, where", [
    ('{"tasks": {"A\\ud800": {"duration": 1}}}', "tasks.A\\ud800"),
    ('{"name": "x\\udfff", "tasks": {"A": {"duration": 1}}}', "name"),
    ('{"tasks": {"A": {"duration": 1, "inputs": ["\\ud800"]}}}', "tasks.A.inputs[0]"),
    ('{"unit": "m\\udc00s", "tasks": {"A": {"duration": 1}}}', "unit"),
])
def test_a_lone_surrogate_in_a_skeleton_is_refused_where_it_is_read(tmp_path, text, where):
    # before: read, then UnicodeEncodeError when the report was printed or written
    path = tmp_path / "s.json"
    path.write_text(text)
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    assert info.value.where == where and "lone surrogate" in str(info.value)
    str(info.value).encode("utf-8")  # the message itself can be printed anywhere


def test_check_name_refuses_a_surrogate_given_in_code():
    with pytest.raises(SkeletonError, match=r"the task name .* lone surrogate"):
        Skeleton.from_dict({"tasks": {"A\ud800": {"duration": 1}}})


# ------------------------------------------------------------------ extensions

@pytest.mark.parametrize("name", ["x.txt", "x.yaml.bak", "noext"])
def test_dump_skeleton_refuses_other_extensions(tmp_path, name):
    # before: YAML written into x.txt
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4}}})
    with pytest.raises(SkeletonError, match=r"a skeleton file is \.yaml, \.yml or \.json"):
        dump_skeleton(sk, tmp_path / name)
    assert not (tmp_path / name).exists()


def test_fix_refuses_an_output_that_is_no_skeleton_file(tmp_path):
    out = CliRunner().invoke(app, ["fix", str(REPO / "examples" / "fig7b_wrong_order.yaml"),
                                   "-o", str(tmp_path / "x.txt")])
    assert out.exit_code == 2 and ".yaml, .yml or .json" in out.stderr
    assert not (tmp_path / "x.txt").exists()
