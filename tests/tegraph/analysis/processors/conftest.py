"""Every test of this directory runs on both loops of the §4b engine.

``compiled``: the Cython loop (``_engine_kernel``) wherever it covers a part (int64
times), as analyze runs it; ``python``: the module handle set to None, so every
part runs ``_Part.run``, the fallback that also serves affine and huge times.
Without a build the compiled runs are skipped (they would repeat the Python ones).
The fixture is module-scoped: hypothesis refuses function-scoped fixtures under
``@given``, and one switch per module and loop is all it takes.
"""

from __future__ import annotations

import pytest

from tegraph.analysis.processors import _engine

LOOPS = ["compiled", "python"]


@pytest.fixture(scope="module", params=LOOPS, autouse=True)
def engine_loop(request):
    """The loop the module's tests run on (its name)."""
    if request.param == "compiled" and _engine._engine_kernel is None:
        pytest.skip("the compiled loop is not built (python setup.py build_ext --inplace)")
    with pytest.MonkeyPatch.context() as mp:
        if request.param == "python":
            mp.setattr(_engine, "_engine_kernel", None)
        yield request.param
