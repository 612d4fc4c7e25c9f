"""The loops of the §4b engine a test can run on, and the switch between them.

``int64`` and ``wide``: the compiled loops (``_engine_kernel``, on int64 times, and
``_engine_kernel_wide``, on 192-bit times), each wherever it covers a part;
``python``: ``_Part.run``, the fallback that serves every other part (affine
times, Fractions, times past 2**189). ``analyze`` tries them in this order.
"""

from __future__ import annotations

import pytest

from tegraph.analysis.processors import _engine

LOOPS = ["int64", "wide", "python"]

MODULES = {"int64": _engine._engine_kernel, "wide": _engine._engine_kernel_wide}
"""The kernel module of each compiled loop (None: not built), read before any switch."""


def built(loop: str) -> bool:
    """Whether ``loop`` can run here (the compiled ones need ``setup.py build_ext``)."""
    return MODULES.get(loop, _engine) is not None


def use_loop(mp: pytest.MonkeyPatch, loop: str) -> None:
    """Make ``loop`` the first the engine tries: the handles of those before it set to None."""
    if loop in ("wide", "python"):
        mp.setattr(_engine, "_engine_kernel", None)
    if loop == "python":
        mp.setattr(_engine, "_engine_kernel_wide", None)


def compiled_module(loop: str):
    """The kernel module of a compiled loop."""
    return MODULES[loop]
