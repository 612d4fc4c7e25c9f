"""The stated limits on what a model holds, and the checks of texts and numbers read.

A value of any size is either held exactly or refused with a message that
names the value and the limit, never approximated and never left to exhaust
the machine. Every reader of a file (:mod:`tegraph.io`) and every model built
in code applies the same bounds:

===========================  ==============  ============================================
limit                        value           why
===========================  ==============  ============================================
:data:`MAX_DIGITS`           4300            digits of each integer of a number's text
                                             and of its exact value's numerator and
                                             denominator (Python's own limit on
                                             converting text to an int); it bounds the
                                             exponent too: ``1e999999999`` is refused
                                             from its text, never expanded
:data:`MAX_COUNT`            2**63 - 1       tokens, markings, arc weights and rates are
                                             counted in 64-bit integers
:data:`FREE_NODES`           2**20           nodes that no arc names (a declared count,
                                             a skipped index) beyond the file's size in
                                             bytes
:data:`DEFAULT_MAX_FIRINGS`  10**7           firings of an SDF graph's homogeneous
                                             expansion (a parameter, ``max_firings``)
===========================  ==============  ============================================

Times are exact rationals of any size within the first bound (a time of
4300 digits, or ``1e4299``, is held exactly). The bound is defined once, with the
number grammar, by :mod:`maxplus.scalar` (the lowest floor, which every reader,
option and library call converts through); this module re-exports it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from maxplus.scalar import MAX_DIGITS, display_text

from .budgets import DEFAULT_MAX_FIRINGS, MAX_EVENT_BUDGET

__all__ = ["DEFAULT_MAX_FIRINGS", "FREE_NODES", "MAX_COUNT", "MAX_DIGITS", "event_budget_problem",
           "count_problem", "denominator_problem", "node_count_problem",
           "shown", "text_problem", "written"]

MAX_COUNT = 2**63 - 1
"""Largest token count, marking, arc weight or rate: they are held as 64-bit integers."""

FREE_NODES = 2**20
"""Nodes no arc names that a file may declare beyond its own size in bytes."""

_MAX_BITS = int(MAX_DIGITS * math.log2(10)) + 1
_SHOWN = 40


def shown(text: Any, quote: bool = True) -> str:
    """A value for a message: its ``repr`` (or its text), cut to 40 characters with its length.

    >>> shown("7/3"), shown(7, quote=False), shown("1" * 50)
    ("'7/3'", '7', "'1111111111111111111111111111111111111111...' (50 characters)")
    """
    text = str(text)
    if len(text) <= _SHOWN:
        return repr(text) if quote else text
    cut = f"{text[:_SHOWN]!r}"[:-1] + "...'" if quote else text[:_SHOWN] + "..."
    return f"{cut} ({len(text)} characters)"


def written(value: Any, text: Any = None) -> str:
    """A number for a message as the input wrote it: ``text`` when it is a text (else
    ``value`` when it is one), cut when too long to read; else the exact value as reports print it
    (its decimal when it ends: ``-0.15``, never ``-3/20``).

    >>> from fractions import Fraction
    >>> written(Fraction(-3, 20)), written(Fraction(-3, 20), "-0.15"), written("1e-3")
    ('-0.15', '-0.15', '1e-3')
    >>> written(Fraction(7, 3)), written(-4)
    ('7/3', '-4')
    """
    if not isinstance(text, str) and isinstance(value, str):
        text = value
    if isinstance(text, str):
        return shown(text.strip(), quote=False)
    return shown(display_text(value), quote=False)


def count_problem(value: int, what: str = "a token count") -> str | None:
    """Why an integer count is refused (negative, or above :data:`MAX_COUNT`), or None.

    >>> count_problem(3) is None
    True
    >>> print(count_problem(2**63))
    a token count must be at most 2**63 - 1 = 9223372036854775807 (64-bit), got 9223372036854775808
    """
    if value < 0:
        return f"{what} must be >= 0, got {value}"
    if value > MAX_COUNT:
        return (f"{what} must be at most 2**63 - 1 = {MAX_COUNT} (64-bit), got "
                f"{shown(value, quote=False)}")
    return None


def event_budget_problem(value: Any) -> str | None:
    """Why a budget of event firings (``max_events``) is refused, or None: it is an
    integer from 1 to :data:`~tegraph.model.budgets.MAX_EVENT_BUDGET`.

    >>> event_budget_problem(1000) is None
    True
    >>> print(event_budget_problem(2**63))  # doctest: +NORMALIZE_WHITESPACE
    expected an integer from 1 to 2**63 - 1 = 9223372036854775807 (firings are
    counted in 64 bits), got 9223372036854775808
    >>> event_budget_problem(0).endswith("got 0"), event_budget_problem(True).endswith("True")
    (True, True)
    """
    if isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= MAX_EVENT_BUDGET:
        return None
    return (f"expected an integer from 1 to 2**63 - 1 = {MAX_EVENT_BUDGET} (firings are "
            f"counted in 64 bits), got {shown(repr(value), quote=False)}")


def node_count_problem(count: int, file_bytes: int, what: str = "nodes") -> str | None:
    """Why ``count`` nodes are refused for a file of ``file_bytes`` bytes, or None.

    Every node an arc names costs bytes of the file; nodes declared by a
    header or skipped by an index cost none, so the count may exceed the
    file's size in bytes by at most :data:`FREE_NODES`.

    >>> node_count_problem(10, 100) is None
    True
    >>> print(node_count_problem(50_000_000, 30, "transitions"))  # doctest: +NORMALIZE_WHITESPACE
    50000000 transitions for a file of 30 bytes; at most its size in bytes + 2**20 = 1048606
    are accepted
    """
    limit = file_bytes + FREE_NODES
    if count <= limit:
        return None
    return (f"{shown(count, quote=False)} {what} for a file of {file_bytes} bytes; at most "
            f"its size in bytes + 2**20 = {limit} are accepted")


def denominator_problem(denominators: Iterable[int]) -> str | None:
    """Why the common denominator of exact times is refused (above :data:`MAX_DIGITS` digits).

    Times are held as integers over one common denominator: the times
    ``1/2, 1/3, 1/5, ...`` of a hundred thousand places would need one of
    half a million digits, and every time multiplied by it.

    >>> denominator_problem([2, 3, 10]) is None
    True
    >>> denominator_problem([10**4000, 3**3000])[:60]
    'the times have a common denominator of more than 4300 digits'
    """
    scale = 1
    for d in denominators:
        if scale % d:
            scale = scale * d // math.gcd(scale, d)
            if scale.bit_length() > _MAX_BITS:
                return (f"the times have a common denominator of more than {MAX_DIGITS} digits "
                        f"(times are held over one denominator); write them with fewer "
                        "distinct denominators")
    return None


def text_problem(text: str) -> str | None:
    """Why a name cannot be written to any file (a lone UTF-16 surrogate), or None.

    JSON can spell ``"\\ud800"``, which is no character: it would be read here
    and fail only when written. Such a name is refused where it is read.

    >>> text_problem("MT1") is None
    True
    >>> print(text_problem("a\\ud800"))  # doctest: +NORMALIZE_WHITESPACE
    'a\\ud800' holds a lone surrogate (U+D800 at character 2), which is no character;
    expected text
    """
    try:
        text.encode("utf-8")
    except UnicodeEncodeError as err:
        return (f"{shown(text)} holds a lone surrogate (U+{ord(text[err.start]):04X} at "
                f"character {err.start + 1}), which is no character; expected text")
    return None
