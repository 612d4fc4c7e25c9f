"""(max,+) algebra: exact scalars and matrices, closures, spectral theory,
sparse cycle ratios and implicit state equations.

Convention (used everywhere in this package): ``x(k+1) = A ⊗ x(k)``, that is
``x_i(k+1) = max_j (A[i][j] + x_j(k))``, so ``A[i][j]`` is the weight of the arc
``j -> i`` (node i waits for node j). ε = -inf. Right eigenvectors:
``A ⊗ v = λ ⊗ v``.
"""

from .errors import (
    CertificateError,
    MaxPlusError,
    MaxPlusValueError,
    PositiveCircuitError,
    ReducibleMatrixError,
    ZeroTokenCircuitError,
)
from .scalar import EPS, TOP, exact, exact_matrix, exact_vector

__all__ = [
    "EPS",
    "TOP",
    "exact",
    "exact_matrix",
    "exact_vector",
    "MaxPlusError",
    "MaxPlusValueError",
    "PositiveCircuitError",
    "ZeroTokenCircuitError",
    "ReducibleMatrixError",
    "CertificateError",
]

# Dense algebra, spectral theory and implicit systems (maxplus.dense,
# maxplus.spectral, maxplus.implicit).
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
from .implicit import ExplicitSystem, simulate, to_explicit
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

__all__ += [
    "identity",
    "oplus",
    "otimes",
    "power",
    "star",
    "plus",
    "solve",
    "left_residual",
    "right_residual",
    "CriticalGraph",
    "HowardResult",
    "TrajectoryPeriodicity",
    "eigenvalue",
    "cycle_time_vector",
    "eigenvector",
    "eigenspace",
    "critical_graph",
    "cyclicity",
    "transient",
    "trajectory_transient",
    "karp",
    "howard",
    "is_irreducible",
    "ExplicitSystem",
    "to_explicit",
    "simulate",
]
