"""Every test of this directory runs on each loop of the §4b engine (``engine_loops``).

``int64``: the compiled loops as analyze runs them; ``wide``: the 192-bit compiled
loop first; ``python``: the Python loop alone. Without a build the compiled runs
are skipped (they would repeat the Python ones). The fixture is module-scoped:
hypothesis refuses function-scoped fixtures under ``@given``, and one switch per
module and loop is all it takes.
"""

from __future__ import annotations

import pytest

from tests.tegraph.analysis.processors.engine_loops import LOOPS, built, use_loop


@pytest.fixture(scope="module", params=LOOPS, autouse=True)
def engine_loop(request):
    """The loop the module's tests run on (its name)."""
    if not built(request.param):
        pytest.skip(f"the {request.param} loop is not built (python setup.py build_ext --inplace)")
    with pytest.MonkeyPatch.context() as mp:
        use_loop(mp, request.param)
        yield request.param
