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
from maxplus.errors import ZeroTokenCircuitError

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


def assert_same(got, ref) -> None:
    """Two kernels' answers (results or ZeroTokenCircuitError) carry the same everything:
    ratio, circuit, cycle times, iterations, certificate and bias (int64 or Python ints
    alike), and both prove themselves."""
    if isinstance(ref, ZeroTokenCircuitError):
        assert isinstance(got, ZeroTokenCircuitError)
        assert (str(got), got.circuit, got.nodes) == (str(ref), ref.circuit, ref.nodes)
        return
    assert not isinstance(got, Exception)
    assert got.ratio == ref.ratio
    assert got.circuit.tolist() == ref.circuit.tolist()
    assert got.cycle_times == ref.cycle_times
    assert got.cycle_time_num.tolist() == ref.cycle_time_num.tolist()
    assert got.cycle_time_den.tolist() == ref.cycle_time_den.tolist()
    assert got.iterations == ref.iterations
    gc, rc = got.certificate, ref.certificate
    assert gc.scale == rc.scale
    for name in ("ratio_num", "ratio_den", "potential", "policy", "circuit"):
        assert getattr(gc, name).tolist() == getattr(rc, name).tolist(), name
    assert got.bias == ref.bias
    assert got.verify() and ref.verify()
