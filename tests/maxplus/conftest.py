"""Fixtures that run a test module on one kernel of max_cycle_ratio, or on both."""
from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.maxplus.kernels import LISTS, NUMPY, kernel


@pytest.fixture(params=[NUMPY, LISTS], ids=["numpy", "lists"])
def both_kernels(request: pytest.FixtureRequest) -> Iterator[None]:
    """The test once on the numpy kernel, once on the list kernel (whatever the size)."""
    with kernel(request.param):
        yield


@pytest.fixture
def numpy_kernel() -> Iterator[None]:
    """The numpy kernel at every size: for tests of its own strategies and internals."""
    with kernel(NUMPY):
        yield
