"""Fixtures that run a test module on one kernel of max_cycle_ratio, or on each."""
from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.maxplus.kernels import KERNELS, NUMPY, kernel


@pytest.fixture(params=KERNELS)
def every_kernel(request: pytest.FixtureRequest) -> Iterator[str]:
    """The test once on each kernel built here (whatever the size)."""
    with kernel(request.param):
        yield request.param


@pytest.fixture
def numpy_kernel() -> Iterator[None]:
    """The numpy kernel at every size: for tests of its own strategies and internals."""
    with kernel(NUMPY):
        yield
