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
