"""Checks of the parameters of the public functions, done once at the edge.

Each raises :class:`~maxplus.errors.MaxPlusValueError` naming the parameter
and what is expected, so that no bad argument surfaces later as a TypeError,
an IndexError or a MemoryError from deep inside numpy.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import MaxPlusValueError

__all__ = ["unmasked", "whole_number"]


def whole_number(value: Any, name: str, minimum: int = 0) -> int:
    """``value`` as a Python int, if it is an integer (not a bool) of at least ``minimum``.

    Floats are refused even when integral (``2.5`` would otherwise be truncated
    and ``nan`` fail in ``int``), as :func:`operator.index` does.

    >>> whole_number(np.int64(3), "k")
    3
    >>> whole_number(2.5, "k")
    Traceback (most recent call last):
    ...
    maxplus.errors.MaxPlusValueError: k: expected a whole number >= 0, got 2.5
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise MaxPlusValueError(f"expected a whole number >= {minimum}, got {value!r}", name)
    return int(value)


def unmasked(value: Any, name: str) -> Any:
    """The data of a masked array that masks nothing; ``value`` itself when not masked.

    A masked entry has no value to compute with, and reading the array would
    silently take whatever lies under the mask (or None): it is refused,
    named by its index.

    >>> unmasked(np.ma.masked_array([1, 2], mask=[False, True]), "x")
    Traceback (most recent call last):
    ...
    maxplus.errors.MaxPlusValueError: x[1]: the entry is masked; give plain values ...
    """
    if not isinstance(value, np.ma.MaskedArray):
        return value
    mask = np.ma.getmaskarray(value)
    if mask.any():
        index = "".join(f"[{int(i)}]" for i in np.argwhere(mask)[0])
        raise MaxPlusValueError(
            "the entry is masked; give plain values (e.g. .filled() or .compressed())",
            f"{name}{index}")
    return np.ma.getdata(value)
