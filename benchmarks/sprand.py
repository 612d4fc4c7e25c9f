"""SPRAND-style random graphs: a Hamiltonian cycle (so the graph is strongly
connected) plus random arcs, m = 4n, integer weights and token counts.

Cherkassky, Goldberg, Radzik, "Shortest paths algorithms: theory and
experimental evaluation" (1996) describe the SPRAND generator; Dasdan (2004)
uses the same family for cycle-ratio algorithms.
"""

from __future__ import annotations

import numpy as np


def sprand(n: int, arcs_per_node: int = 4, max_weight: int = 10_000, max_tokens: int = 10,
           seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Arrays (src, dst, weight, tokens) of a strongly connected random graph."""
    rng = np.random.default_rng(seed)
    m = arcs_per_node * n
    perm = rng.permutation(n)
    src = np.empty(m, dtype=np.int64)
    dst = np.empty(m, dtype=np.int64)
    src[:n] = perm
    dst[:n] = np.roll(perm, -1)
    src[n:] = rng.integers(0, n, m - n)
    dst[n:] = rng.integers(0, n, m - n)
    weight = rng.integers(1, max_weight + 1, m)
    tokens = rng.integers(1, max_tokens + 1, m)
    return src, dst, weight, tokens
