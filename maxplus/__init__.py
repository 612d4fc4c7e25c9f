"""(max,+) algebra: exact scalars and matrices, closures, spectral theory,
sparse cycle ratios and implicit state equations.

Convention (used everywhere in this package): ``x(k+1) = A ⊗ x(k)``, that is
``x_i(k+1) = max_j (A[i][j] + x_j(k))``, so ``A[i][j]`` is the weight of the arc
``j -> i`` (node i waits for node j). ε = -inf. Right eigenvectors:
``A ⊗ v = λ ⊗ v``.

The package knows nothing of tasks or files: arrays and matrices in, exact
results out.
"""

from typing import Any

from .certificate import CycleRatioCertificate
from .cycle_ratio import CycleRatioResult, max_cycle_ratio
from .dense import (
    identity,
    left_residual,
    oplus,
    otimes,
    plus,
    power,
    right_residual,
    solve,
    star,
)
from .errors import (
    CertificateError,
    MaxPlusError,
    MaxPlusValueError,
    PositiveCircuitError,
    ReducibleMatrixError,
    ZeroTokenCircuitError,
)
from .implicit import ExplicitSystem, simulate, to_explicit
from .scalar import EPS, TOP, exact, exact_matrix, exact_text, exact_vector
from .spectral import (
    CriticalGraph,
    HowardResult,
    critical_graph,
    cycle_time_vector,
    cyclicity,
    eigenspace,
    eigenvalue,
    eigenvector,
    howard,
    is_irreducible,
    karp,
)
from .transient import TrajectoryPeriodicity, trajectory_transient, transient


def __getattr__(name: str) -> Any:
    # The look-up of the installed distribution (and importing importlib.metadata when
    # nothing else has) is paid when the version is asked for, not by every import, as
    # tegraph.__version__.
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("tegraph")
        except PackageNotFoundError:  # a checkout used without installing it
            value = "0+unknown"
        globals()[name] = value  # later lookups skip this function
        return value
    raise AttributeError(f"module 'maxplus' has no attribute {name!r}")

__all__ = [
    # scalars
    "EPS",
    "TOP",
    "exact",
    "exact_matrix",
    "exact_text",
    "exact_vector",
    # dense algebra
    "identity",
    "left_residual",
    "oplus",
    "otimes",
    "plus",
    "power",
    "right_residual",
    "solve",
    "star",
    # spectral theory and transients
    "CriticalGraph",
    "HowardResult",
    "TrajectoryPeriodicity",
    "critical_graph",
    "cycle_time_vector",
    "cyclicity",
    "eigenspace",
    "eigenvalue",
    "eigenvector",
    "howard",
    "is_irreducible",
    "karp",
    "trajectory_transient",
    "transient",
    # sparse cycle ratios
    "CycleRatioCertificate",
    "CycleRatioResult",
    "max_cycle_ratio",
    # implicit state equations
    "ExplicitSystem",
    "simulate",
    "to_explicit",
    # errors
    "CertificateError",
    "MaxPlusError",
    "MaxPlusValueError",
    "PositiveCircuitError",
    "ReducibleMatrixError",
    "ZeroTokenCircuitError",
]
