"""Renderers registered by the dotted name of the result type, imported on first use.

:func:`functools.singledispatch` needs the class, so registering every renderer
that way imports every result module (explore, timeline, sensitivity, the
reachability baselines) before any report is written; ``tegraph analyze``
loaded all of them. Here a renderer is named ``"module:function"`` beside the
result's dotted type name, and both are resolved only when such a result is
rendered. The lookup walks the result's MRO, as singledispatch does.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any

__all__ = ["Renderers"]


class Renderers:
    """A table ``dotted type name -> "module:function"`` resolved on first use.

    Parameters
    ----------
    what : str
        What the functions make, for the error message (``"text rendering"``).
    table : mapping of str to str
        ``"package.module.Class"`` -> ``"package.module:function"``.

    Examples
    --------
    >>> r = Renderers("length", {"builtins.str": "builtins:len"})
    >>> r.find("abc")("abc")
    3
    >>> r.find(1.5)
    Traceback (most recent call last):
    ...
    TypeError: no length for a float
    """

    def __init__(self, what: str, table: Mapping[str, str]) -> None:
        self.what = what
        self.table = dict(table)
        self._found: dict[type, Callable[..., Any]] = {}

    def find(self, result: Any) -> Callable[..., Any]:
        """The function registered for ``result``'s type or its nearest base class."""
        kind = type(result)
        known = self._found.get(kind)
        if known is not None:
            return known
        for cls in kind.__mro__:
            target = self.table.get(f"{cls.__module__}.{cls.__qualname__}")
            if target is not None:
                module, _, name = target.partition(":")
                function = getattr(importlib.import_module(module), name)
                self._found[kind] = function
                return function
        raise TypeError(f"no {self.what} for a {kind.__name__}")
