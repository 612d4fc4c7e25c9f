"""Sphinx configuration of tegraph's documentation (``docs/``, built by the test suite).

Pages are Markdown (MyST); the API reference comes from the numpydoc docstrings
(autodoc + numpydoc), the command-line reference from typer's own command tree
(``_ext/tegraph_cli.py`` over ``typer.main.get_command``). The build runs with warnings as
errors (``-W``) in ``tests/test_docs.py``: a broken cross-reference (``nitpicky``),
a public name without a docstring (``_ext/tegraph_api.py``) or a page outside every
table of contents fails the suite.
"""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS.parent))  # the checkout, not an installed copy
sys.path.insert(0, str(DOCS / "_ext"))

project = "tegraph"
author = "the tegraph engineers"
copyright = "the tegraph engineers"  # noqa: A001  (Sphinx's name)

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "numpydoc",
    "tegraph_api",
    "tegraph_cli",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "**/_build", "README.md"]

# Quotes and ellipses only: "--max-events" stays two hyphens (an en dash would
# not be the option a reader copies).
smartquotes_action = "qe"

myst_enable_extensions = ["colon_fence", "deflist", "dollarmath"]
myst_heading_anchors = 4

# Every reference must resolve. The standard library's and the dependencies' own
# types cannot (their inventories are on the network, which the build never uses):
# only those are let through, so a broken reference into tegraph or maxplus fails.
nitpicky = True
nitpick_ignore_regex = [
    # A private name is not in the reference: a reference to one reads as code.
    (r"py:.*", r"(.*\.)?_[A-Za-z].*"),
    (r"py:.*", r"(builtins|fractions|typing|collections|pathlib|os|io|enum|dataclasses"
               r"|contextlib|abc|numbers|functools|decimal|re|types)(\..*)?"),
    (r"py:.*", r"(numpy|np|scipy|sp|networkx|nx|sympy|typer|click|yaml|distributed|dask"
               r"|matplotlib|pyarrow|tabulate|orjson)(\..*)?"),
    (r"py:.*", r"(int|str|float|bool|bytes|list|dict|tuple|set|frozenset|object|type|None"
               r"|callable|iterable|sequence|mapping|path-like|array_like|ndarray|Fraction"
               r"|Any|Path|Iterator|Iterable|Sequence|Mapping|Callable|optional|default)"),
]

autodoc_default_options = {"show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "none"  # numpydoc's Parameters say the types, in words
autodoc_preserve_defaults = True

numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# A public name without a docstring is caught by tegraph_api (numpydoc's GL08 reads an
# attribute's value, not its docstring, and so flags every documented dataclass field).
numpydoc_xref_param_type = False

# A References entry that the text does not cite is numpydoc's usual style, not an error.
suppress_warnings = ["ref.citation"]

html_theme = "furo"
html_title = "tegraph"
html_static_path: list[str] = []
html_show_sourcelink = False
