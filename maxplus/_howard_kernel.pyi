"""Types of the compiled kernel :mod:`maxplus._howard_kernel` (``_howard_kernel.pyx``)."""

import numpy as np

def howard(
    src: np.ndarray, dst: np.ndarray, w: np.ndarray, t: np.ndarray, n: int, sweep_few: int,
    scan_min_share: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int] | None: ...
def policy_circuit(start: int, policy: np.ndarray, src: np.ndarray) -> np.ndarray | None: ...
