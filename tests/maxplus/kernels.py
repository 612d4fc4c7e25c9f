"""The kernels of max_cycle_ratio a test can run on, through the switch ``maxplus._kernels``.

``numpy`` is the reference; ``compiled`` the C kernel, where setup.py built it
(``KERNELS`` lists it only then, so a test over ``KERNELS`` compares what is there).
:func:`kernel` runs a block on one of them at every size.
"""
from __future__ import annotations

from maxplus import _kernels
from maxplus.errors import ZeroTokenCircuitError

NUMPY, COMPILED = "numpy", "compiled"

BUILT = all(_kernels.compiled().values())
"""Whether the compiled modules of maxplus are built (``setup.py build_ext``)."""

KERNELS = [NUMPY] + ([COMPILED] if BUILT else [])
"""Every kernel that can run here, the reference first."""

kernel = _kernels.use
"""``with kernel(NUMPY): ...``: the block on that kernel (and any crossovers given)."""


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
