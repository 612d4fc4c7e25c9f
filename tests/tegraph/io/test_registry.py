"""The table of formats (:data:`tegraph.io.FORMATS`) is the one every part reads.

Each record's reader and writer must exist, no extension may select two formats,
a shared extension must be told apart (by content when read, by model when
written), and the command line's help must name what the table holds.
"""

from __future__ import annotations

import inspect

import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton
from tegraph.cli import app
from tegraph.io import FORMATS, detect_format, format_for_writing, read, sniff_format
from tegraph.io.formats import _resolve, readable, writable
from tegraph.model.sdf import SDFGraph


@pytest.mark.parametrize("fmt", FORMATS.values(), ids=lambda f: f.name)
def test_each_reader_and_writer_is_a_function_of_its_module(fmt):
    if fmt.reader is not None:
        assert "max_bytes" in inspect.signature(_resolve(fmt.reader)).parameters
    if fmt.writer is not None:
        params = inspect.signature(_resolve(fmt.writer)).parameters
        assert "overwrite" in params and (("highlights" in params) == fmt.draws)


def test_an_extension_selects_one_format_or_is_told_apart():
    owned = [e for f in FORMATS.values() for e in f.suffixes]
    assert len(owned) == len(set(owned))
    shared = {e for f in FORMATS.values() for e in f.shared}
    assert not shared & set(owned)
    for ext in shared:
        sharing = [f for f in FORMATS.values() if ext in f.shared]
        assert len(sharing) >= 2
        # Written: at most one format is the fallback, the others name their model.
        assert sum(f.model is None for f in sharing) == 1
        # Read: every one but the skeleton (JSON that no other format claims) sniffs.
        assert all(f.sniff is not None for f in sharing if f.name != "skeleton")


def test_a_shared_extension_is_written_as_the_model_it_gets():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1}}})
    assert format_for_writing(sk, "a.json") == "skeleton"
    assert format_for_writing(object(), "a.json") == "tpne-json"
    sdf = SDFGraph.__new__(SDFGraph)
    assert format_for_writing(sdf, "a.xml") == "sdf3"
    assert format_for_writing(object(), "a.xml") == "pnml"
    with pytest.raises(InputError, match=r"extension '\.txt'.*\.yaml, \.yml, \.json"):
        format_for_writing(sk, "a.txt")


def test_content_tells_the_formats_of_a_shared_extension_apart():
    assert detect_format("n.xml", b"  <?xml version='1.0'?>\n<pnml>") == "pnml"
    assert detect_format("n.xml", b"<sdf3 type='sdf'>") == "sdf3"
    assert detect_format("n.json", b'{"revision": 3, "nets": []}') == "tpne-json"
    assert detect_format("n.json", b'{"tasks": {}}') == "skeleton"
    # A .json file is only one of the formats that share .json: lines of four
    # numbers in it are not taken for an arc list.
    assert detect_format("n.json", b"0 1 2 0\n") == "skeleton"
    with pytest.raises(InputError, match="neither <pnml> nor <sdf3>"):
        detect_format("n.xml", b"<graph/>")


def test_a_drawing_is_recognised_and_refused_for_reading(tmp_path):
    path = tmp_path / "g.txt"
    path.write_text("digraph g { a -> b }\n")
    assert sniff_format(path.read_bytes()) == detect_format(path) == "dot"
    with pytest.raises(InputError, match="format 'dot' cannot be read; readable: edges, pnml"):
        read(path)


def test_the_command_line_help_names_the_formats_of_the_table():
    runner = CliRunner()
    convert = " ".join(runner.invoke(app, ["convert", "--help"], terminal_width=400)
                       .output.split())
    assert f"({', '.join(writable())})" in convert
    for ext in (e for f in FORMATS.values() for e in f.extensions()):
        assert ext in convert
    cycle = " ".join(runner.invoke(app, ["cycle-time", "--help"], terminal_width=400)
                     .output.split())
    assert f"({', '.join(readable())})" in cycle
