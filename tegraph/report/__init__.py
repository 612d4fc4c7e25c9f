"""Results -> text, JSON documents, CSV tables, coloured DOT drawings, SVG/PNG plots.

Nothing here computes a figure: each function renders the result it is given.
"""

from .document import SCHEMA_VERSION, json_report, to_document, to_json, to_json_bytes
from .dot import highlights
from .tables import write_csv
from .text import render_text

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
