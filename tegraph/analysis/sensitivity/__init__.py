"""Sensitivity of a skeleton's figures to its parameters (``tegraph sensitivity``).

One module an idea:

- :mod:`.parameters`: the parameters (durations, periods, delays) and
  ``--vary``; :mod:`.parametric`: the groups as (max,+) linear systems in them;
- :mod:`.oracle`: one point's exact evaluation, with the certificate of its
  critical circuits; :mod:`.polyhedra`: the regions they bound;
- :mod:`.line`: exact breakpoints along a line of parameters; :mod:`.margins`:
  each duration alone (also ``analyze``'s "can grow by" column);
- :mod:`.formulas`: each group's period as a formula; :mod:`.region`: the
  consistent region of two parameters;
- on the processors (spec §4b): :mod:`.affine` (times ``c + k·t``),
  :mod:`.walk` (intervals of constant event order, and the sweep of a whole
  range), :mod:`tegraph.analysis.sensitivity.levels` (a part whose groups are
  periodic units, decided along a line by the exact test of units, piece by
  piece), :mod:`.partition` (the schedule's parts, read once off the nominal
  graph), :mod:`.simulation` (a part simulated on affine times, within the
  budgets), :mod:`.parts` (each part decided at a point of a line, by its
  levels or its schedule), :mod:`.on_processors` (the scaling factor and
  margins on processors);
- :mod:`.results`: what is returned; :mod:`.core`: :func:`sensitivity`, the whole.

Nothing else in :mod:`tegraph.analysis` imports this package (an import-linter
contract). The names below resolve on first use: ``analyze`` reads
:mod:`.margins` without loading the rest.
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__all__ = ["SensitivityResult", "duration_margins", "sensitivity"]

_WHERE = {"sensitivity": ".core", "duration_margins": ".margins",
          "SensitivityResult": ".results"}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        return getattr(import_module(_WHERE[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
