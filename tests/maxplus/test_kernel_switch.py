"""The kernel switch of maxplus (``maxplus._kernels``): what ``use`` sets, for how long, where.

The kernels' answers are compared elsewhere (``test_howard_kernel``,
``test_howard_brute_force``, the ``every_kernel`` modules); here, the switch
itself: a block's choice and its end, nesting, threads, refusals.
"""
from __future__ import annotations

import threading

import pytest

from maxplus import _kernels, max_cycle_ratio


def test_a_block_sets_the_kernel_and_crossovers_and_its_end_restores_them():
    assert _kernels.current() == _kernels.DEFAULT
    with _kernels.use("numpy", sweep_few=0) as outer:
        assert _kernels.current() is outer
        assert (outer.kernel, outer.sweep_few) == ("numpy", 0)
        assert _kernels.howard_kernel() is None and _kernels.certificate_kernel() is None
        with _kernels.use(walk_in_python=1) as inner:  # the kernel and sweep_few stay
            assert (inner.kernel, inner.sweep_few, inner.walk_in_python) == ("numpy", 0, 1)
        assert _kernels.current() is outer
    assert _kernels.current() == _kernels.DEFAULT


def test_the_default_runs_what_is_built():
    assert _kernels.howard_kernel() is _kernels.COMPILED["maxplus._howard_kernel"]
    assert _kernels.certificate_kernel() is _kernels.COMPILED["maxplus._certificate_kernel"]


def test_another_thread_runs_on_the_defaults():
    seen = []
    with _kernels.use("numpy"):
        worker = threading.Thread(target=lambda: seen.append(_kernels.current().kernel))
        worker.start()
        worker.join()
    assert seen == ["auto"]


def test_an_error_in_the_block_still_restores_the_choice():
    with pytest.raises(KeyError), _kernels.use("numpy"):
        raise KeyError("in the block")
    assert _kernels.current() == _kernels.DEFAULT


def test_unknown_kernels_and_crossovers_are_refused():
    with pytest.raises(ValueError, match="unknown kernel 'lists'"), _kernels.use("lists"):
        pass
    with pytest.raises(ValueError, match="unknown crossover"), _kernels.use(sweep_many=3):
        pass


def test_the_compiled_kernel_is_refused_where_it_is_not_built(monkeypatch):
    # What a machine without a compiler sees (the switch's own table, emptied).
    monkeypatch.setitem(_kernels.COMPILED, "maxplus._howard_kernel", None)
    with pytest.raises(RuntimeError, match=r"not built \(maxplus._howard_kernel missing\)"):
        with _kernels.use("compiled"):
            pass
    assert _kernels.compiled()["maxplus._howard_kernel"] is False


def test_each_kernel_gives_the_circuit_of_ratio_4():
    # Circuit 0 -> 1 -> 0 of weights 5 and 3 (ratio 8/2), a self-loop of 3 on node 1.
    built = all(_kernels.compiled().values())
    for kernel in (k for k in _kernels.KERNELS if k != "compiled" or built):
        with _kernels.use(kernel):
            r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
        assert r.ratio == 4 and r.circuit.tolist() == [0, 1]
