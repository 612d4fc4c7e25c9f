"""The analyze command prints its JSON document byte for byte as ``typer.echo`` did.

``_echo_document`` skips click's scan for ANSI colour codes: a JSON text has none,
since JSON escapes every control character (ESC included). Both are compared on
documents holding what could matter: escapes, non-ASCII names, a lone CR.
"""

import json

import pytest
import typer

from tegraph.cli import _echo_document

DOCUMENTS = [
    {"name": "\x1b[31mred\x1b[0m", "tasks": ["é", "日本", "a\rb", "tab\there"]},
    {"report": "analyze", "period": "7/3", "empty": [], "nested": {"x": None}},
]


@pytest.mark.parametrize("doc", DOCUMENTS)
def test_a_document_prints_as_typer_echo_prints_it(doc, capsys):
    text = json.dumps(doc, indent=2, ensure_ascii=False)
    assert "\x1b" not in text  # JSON escapes it: nothing for click to strip
    typer.echo(text)
    by_typer = capsys.readouterr().out
    _echo_document(text)
    assert capsys.readouterr().out == by_typer == text + "\n"
