"""Types of the compiled checks :mod:`maxplus._certificate_kernel` (``_certificate_kernel.pyx``)."""

import numpy as np

ALL_HOLD: int
ONE_RATIO: int

def arc_checks(
    src: np.ndarray, dst: np.ndarray, w: np.ndarray, t: np.ndarray, W: np.ndarray,
    T: np.ndarray, X: np.ndarray, policy: np.ndarray,
) -> int: ...
