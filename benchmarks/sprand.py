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


def ring_with_chords(n: int = 100_000, skip: int = 5, max_weight: int = 10_000,
                     max_tokens: int = 10, seed: int = 0
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A ring ``0 -> 1 -> ... -> n-1 -> 0`` and a forward chord ``i -> i+skip`` at every node.

    Every circuit goes once around the ring, taking ring arcs or chords, so
    circuits are long: the critical one of the default graph has about
    n / skip = 20,000 arcs (chords carry ``skip`` times the weight range of a
    ring arc, tokens as a ring arc). Long critical circuits are where value
    determination must follow long policy paths.
    """
    rng = np.random.default_rng(seed)
    nodes = np.arange(n, dtype=np.int64)
    src = np.concatenate([nodes, nodes])
    dst = np.concatenate([(nodes + 1) % n, (nodes + skip) % n])
    weight = np.concatenate([rng.integers(1, max_weight + 1, n),
                             rng.integers(1, skip * max_weight + 1, n)])
    tokens = rng.integers(1, max_tokens + 1, 2 * n)
    return src, dst, weight, tokens


def torus_grid(side: int = 316, max_weight: int = 10_000, max_tokens: int = 10, seed: int = 0
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A ``side x side`` torus: ``(r, c)`` has arcs to ``(r, c+1)`` and ``(r+1, c)``, wrapping."""
    rng = np.random.default_rng(seed)
    r, c = np.divmod(np.arange(side * side, dtype=np.int64), side)
    right = r * side + (c + 1) % side
    down = ((r + 1) % side) * side + c
    src = np.concatenate([r * side + c, r * side + c])
    dst = np.concatenate([right, down])
    m = len(src)
    return src, dst, rng.integers(1, max_weight + 1, m), rng.integers(1, max_tokens + 1, m)


def equal_weights(n: int = 100_000, weight: int = 7, tokens: int = 3, seed: int = 0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """SPRAND's arcs with every weight and every token count equal: all circuits tie."""
    src, dst, _, _ = sprand(n, seed=seed)
    return src, dst, np.full(len(src), weight, dtype=np.int64), np.full(len(src), tokens,
                                                                       dtype=np.int64)
