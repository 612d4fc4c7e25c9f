"""Every test of this directory runs on each loop of the §4b engine (``engine_loops``).

``int64``: the compiled loops as analyze runs them; ``wide``: the 192-bit compiled
loop first; ``python``: the Python loop alone. Without a build the compiled runs
are skipped (they would repeat the Python ones). The fixture is module-scoped:
hypothesis refuses function-scoped fixtures under ``@given``, and one switch per
module and loop is all it takes. A module that picks the loops itself says
``EVERY_LOOP = True`` and runs once.
"""

from __future__ import annotations

import pytest

from tests.tegraph.analysis.processors.engine_loops import LOOPS, built, use_loop


def pytest_generate_tests(metafunc):
    """Each module once per loop, except one that picks the loops itself (``EVERY_LOOP``)."""
    if "engine_loop" in metafunc.fixturenames and not getattr(metafunc.module, "EVERY_LOOP",
                                                               False):
        metafunc.parametrize("engine_loop", LOOPS, indirect=True, scope="module")


@pytest.fixture(scope="module", autouse=True)
def engine_loop(request):
    """The loop the module's tests run on (its name; None where the module picks them)."""
    loop = getattr(request, "param", None)
    if loop is None:
        yield None
        return
    if not built(loop):
        pytest.skip(f"the {loop} loop is not built (python setup.py build_ext --inplace)")
    with use_loop(loop):
        yield loop
