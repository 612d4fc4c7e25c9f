"""Which loop of the §4b engine runs a part: the one switch of the schedule engine.

:func:`._engine.simulate_part` runs each part on the first of its loops that
covers the part's times and finishes within its bound:

``"int64"``
    The loop compiled on int64 times (``_engine_kernel``, built by ``setup.py``
    where a C compiler is found), for times below ``2**62``.
``"wide"``
    The same loop compiled on 192-bit times (``_engine_kernel_wide``), for the
    parts int64 cannot hold.
``"python"``
    :meth:`._engine._Part.run`, the reference, on any numbers the rules can add
    and compare (affine times of the sensitivity analysis, Fractions, times
    past ``2**189``).

All three fire in the same order and give the same result. Tests run a part
on one loop with :func:`use` (``only=True``: on that loop to its end, or an
error), instead of patching the engine's module globals.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from types import ModuleType
from typing import Any, Literal, TypeAlias

# The compiled loops (setup.py); without them every part runs the Python loop.
try:
    from . import _engine_kernel
except ImportError:  # pragma: no cover - depends on the build
    _engine_kernel = None  # type: ignore[assignment]
try:
    from . import _engine_kernel_wide
except ImportError:  # pragma: no cover - depends on the build
    _engine_kernel_wide = None  # type: ignore[assignment]

__all__ = ["COMPILED", "LOOPS", "Loop", "LoopChoice", "compiled", "compiled_loops", "current",
           "python_loop", "use"]

Loop: TypeAlias = Literal["int64", "wide", "python"]
"""The loops, in the order the engine tries them."""

LOOPS: tuple[Loop, ...] = ("int64", "wide", "python")


COMPILED: dict[Loop, ModuleType | None] = {"int64": _engine_kernel, "wide": _engine_kernel_wide}
"""The module of each compiled loop (``setup.py`` builds one per ``.pyx``): None where it
is not built."""

_PACKAGE = __name__.rpartition(".")[0]


def compiled() -> dict[str, bool]:
    """Per compiled module of the engine, whether it is built (what ``tegraph --version`` says).

    >>> [name.rpartition(".")[2] for name in compiled()]
    ['_engine_kernel', '_engine_kernel_wide']
    """
    return {f"{_PACKAGE}._engine_kernel": _engine_kernel is not None,
            f"{_PACKAGE}._engine_kernel_wide": _engine_kernel_wide is not None}


@dataclass(frozen=True)
class LoopChoice:
    """The first loop tried, and whether the part must run on it alone."""

    first: Loop = "int64"
    only: bool = False


DEFAULT = LoopChoice()

_CHOICE: ContextVar[LoopChoice] = ContextVar("tegraph_engine_loop")


def current() -> LoopChoice:
    """The loop choice in force (the default, or that of the innermost :func:`use`)."""
    return _CHOICE.get(DEFAULT)


@contextmanager
def use(first: Loop, *, only: bool = False) -> Iterator[LoopChoice]:
    """Run the parts of the block from the loop ``first`` on (those before it skipped).

    Parameters
    ----------
    first : {"int64", "wide", "python"}
        The first loop tried; the loops after it serve the parts it does not cover.
    only : bool
        The part must run on ``first`` to its end: a part it does not cover, or
        whose times pass its bound, raises :class:`RuntimeError` instead of
        running on the next loop.

    Raises
    ------
    ValueError
        An unknown loop.
    RuntimeError
        A compiled loop that is not built.

    Examples
    --------
    >>> with use("python") as choice:
    ...     choice.first, choice.only
    ('python', False)
    """
    if first not in LOOPS:
        raise ValueError(f"unknown loop {first!r}; expected one of {', '.join(LOOPS)}")
    if first in COMPILED and COMPILED[first] is None:
        raise RuntimeError(f"the {first} loop is not built: python setup.py build_ext --inplace")
    token = _CHOICE.set(LoopChoice(first, only))
    try:
        yield _CHOICE.get()
    finally:
        _CHOICE.reset(token)


def compiled_loops(d: Any) -> Iterator[Any]:
    """The compiled loop modules that may run part ``d``, in order (each covers it).

    Under ``use(..., only=True)``, a compiled loop that does not cover ``d``
    raises, and :func:`python_loop` refuses the fallback.
    """
    choice = current()
    start = LOOPS.index(choice.first)
    for loop in LOOPS[start:start + 1] if choice.only else LOOPS[start:]:
        module = COMPILED.get(loop)
        if module is None:
            continue
        if module.covers(d):
            yield module
        elif choice.only:
            raise RuntimeError(f"the {loop} loop does not cover this part")


def python_loop() -> None:
    """Check that the Python loop may run (refused under ``only`` for a compiled loop)."""
    choice = current()
    if choice.only and choice.first != "python":
        raise RuntimeError(f"the {choice.first} loop did not run the part to its end")
