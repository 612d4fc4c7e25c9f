"""The loops of the §4b engine a test can run on, through the switch ``processors._loops``.

``int64`` and ``wide``: the compiled loops (``_engine_kernel``, on int64 times, and
``_engine_kernel_wide``, on 192-bit times), each wherever it covers a part;
``python``: ``_Part.run``, the fallback that serves every other part (affine
times, Fractions, times past 2**189). ``analyze`` tries them in this order.
``use_loop(loop)`` runs a block from that loop on; ``only=True`` on it alone.
"""

from __future__ import annotations

from tegraph.analysis.processors import _loops

LOOPS = list(_loops.LOOPS)

use_loop = _loops.use


def built(loop: str) -> bool:
    """Whether ``loop`` can run here (the compiled ones need ``setup.py build_ext``)."""
    return loop not in _loops.COMPILED or _loops.COMPILED[loop] is not None


def compiled_module(loop: str):
    """The kernel module of a compiled loop."""
    return _loops.COMPILED[loop]
