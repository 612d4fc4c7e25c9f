"""The analyze command prints its JSON document byte for byte as ``typer.echo`` did.

``_echo_document`` skips click's scan for ANSI colour codes: a JSON text has none,
since JSON escapes every control character (ESC included), and writes the UTF-8
bytes of the document to the binary stream. Both are compared on documents
holding what could matter: escapes and non-ASCII names.
"""

import io
import json
import sys

import pytest
import typer

from tegraph.cli import _echo_document

DOCUMENTS = [
    # (json.dumps escapes the CR and the ESC: the text printed holds neither)
    {"name": "\x1b[31mred\x1b[0m", "tasks": ["é", "日本", "a\rb", "tab\there"]},
    {"report": "analyze", "period": "7/3", "empty": [], "nested": {"x": None}},
]


@pytest.mark.parametrize("doc", DOCUMENTS)
def test_a_document_prints_as_typer_echo_prints_it(doc, capsysbinary):
    text = json.dumps(doc, indent=2, ensure_ascii=False)
    assert "\x1b" not in text  # JSON escapes it: nothing for click to strip
    typer.echo(text)  # the text, as the command printed it before it wrote bytes
    by_typer = capsysbinary.readouterr().out
    _echo_document(text.encode())
    assert capsysbinary.readouterr().out == by_typer == (text + "\n").encode()


@pytest.mark.parametrize("doc", DOCUMENTS)
def test_a_text_only_stream_gets_the_same_text(doc, monkeypatch):
    # An embedding program may put a plain text stream in sys.stdout (no .buffer).
    text = json.dumps(doc, indent=2, ensure_ascii=False)
    stream = io.StringIO()
    monkeypatch.setattr(sys, "stdout", stream)
    _echo_document(text.encode())
    assert stream.getvalue() == text + "\n"
