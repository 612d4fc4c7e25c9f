"""Results -> text, JSON documents, CSV tables, coloured DOT drawings, SVG/PNG plots.

Nothing here computes a figure: each function renders the result it is given.
Each name below is imported on first use: ``analyze --json`` needs the document
alone, not the text report and its tables.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

# name -> module that defines it
_WHERE = {
    "SCHEMA_VERSION": "tegraph.report.document",
    "highlights": "tegraph.report.dot",
    "json_report": "tegraph.report.document",
    "render_text": "tegraph.report.text",
    "to_document": "tegraph.report.document",
    "to_json": "tegraph.report.document",
    "to_json_bytes": "tegraph.report.document",
    "write_csv": "tegraph.report.tables",
}

__all__ = [
    "SCHEMA_VERSION",
    "highlights",
    "json_report",
    "render_text",
    "to_document",
    "to_json",
    "to_json_bytes",
    "write_csv",
]


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        value = getattr(importlib.import_module(_WHERE[name]), name)
        globals()[name] = value  # later lookups skip this function
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_WHERE})


if TYPE_CHECKING:  # static tools see the names where they are defined
    from .document import SCHEMA_VERSION, json_report, to_document, to_json, to_json_bytes
    from .dot import highlights
    from .tables import write_csv
    from .text import render_text
