"""Forcing one kernel of max_cycle_ratio: numpy arrays or Python lists (small graphs).

``max_cycle_ratio`` reads the crossover ``maxplus._small_howard.SMALL_GRAPH_ARCS``
at each call, so a test sets it to run either kernel at any size. :data:`NUMPY`
is the numpy kernel itself: it also sets the compiled kernel's handle
``maxplus.policy_iteration._howard_kernel`` to None (the tests of the compiled
kernel set it back inside, ``tests/maxplus/test_howard_kernel.py``).
"""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import maxplus._small_howard as small
import maxplus.policy_iteration as policy_iteration

NUMPY, LISTS = -1, 10**9
"""Values of ``SMALL_GRAPH_ARCS`` that force the numpy kernel and the list kernel."""


@contextmanager
def kernel(arcs_limit: int) -> Iterator[None]:
    """Run max_cycle_ratio with the small-graph crossover at ``arcs_limit`` arcs."""
    saved = small.SMALL_GRAPH_ARCS, policy_iteration._howard_kernel
    small.SMALL_GRAPH_ARCS = arcs_limit
    if arcs_limit == NUMPY:
        policy_iteration._howard_kernel = None
    try:
        yield
    finally:
        small.SMALL_GRAPH_ARCS, policy_iteration._howard_kernel = saved
