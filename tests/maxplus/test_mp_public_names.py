"""``import maxplus`` offers every public name; ``__version__`` is looked up on first use.

The names are written out here, so that a name dropped from ``maxplus/__init__.py``
fails; each must be the very object its module defines (``maxplus.transient`` is
the function, not the module of the same name).
"""

import importlib

import pytest

import maxplus

PUBLIC = {
    "maxplus.scalar": ["EPS", "TOP", "exact", "exact_matrix", "exact_text", "exact_vector"],
    "maxplus.dense": ["identity", "left_residual", "oplus", "otimes", "plus", "power",
                      "right_residual", "solve", "star"],
    "maxplus.spectral": ["CriticalGraph", "HowardResult", "critical_graph",
                         "cycle_time_vector", "cyclicity", "eigenspace", "eigenvalue",
                         "eigenvector", "howard", "is_irreducible", "karp"],
    "maxplus.transient": ["TrajectoryPeriodicity", "trajectory_transient", "transient"],
    "maxplus.certificate": ["CycleRatioCertificate"],
    "maxplus.cycle_ratio": ["CycleRatioResult", "max_cycle_ratio"],
    "maxplus.implicit": ["ExplicitSystem", "simulate", "to_explicit"],
    "maxplus.errors": ["CertificateError", "MaxPlusError", "MaxPlusValueError",
                       "PositiveCircuitError", "ReducibleMatrixError", "ZeroTokenCircuitError"],
}


def test_all_lists_every_public_name():
    assert sorted(maxplus.__all__) == sorted(n for names in PUBLIC.values() for n in names)
    assert set(maxplus.__all__) <= set(dir(maxplus))


@pytest.mark.parametrize("module, name", [(m, n) for m, names in PUBLIC.items() for n in names])
def test_each_name_is_its_module_s_object(module, name):
    assert getattr(maxplus, name) is getattr(importlib.import_module(module), name)


def test_star_import_and_unknown_names():
    scope: dict = {}
    exec("from maxplus import *", scope)
    assert {n for n in scope if not n.startswith("__")} == set(maxplus.__all__)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        maxplus.nothing  # noqa: B018
    assert isinstance(maxplus.__version__, str) and "__version__" in vars(maxplus)
