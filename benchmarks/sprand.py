"""SPRAND-style random graphs: a Hamiltonian cycle (so the graph is strongly
connected) plus random arcs, m = 4n, integer weights and token counts.

SPRAND lays the cycle out as 0 -> 1 -> ... -> n-1 -> 0 (``layout="canonical"``);
this module also offers the cycle along a random permutation
(``layout="permuted"``, its original and default layout).

Cherkassky, Goldberg, Radzik, "Shortest paths algorithms: theory and
experimental evaluation" (1996) describe the SPRAND generator; Dasdan (2004)
uses the same family for cycle-ratio algorithms.
"""

from __future__ import annotations

import numpy as np


def sprand(n: int, arcs_per_node: int = 4, max_weight: int = 10_000, max_tokens: int = 10,
           seed: int = 0, layout: str = "permuted"
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Arrays (src, dst, weight, tokens) of a strongly connected random graph.

    Parameters
    ----------
    layout : {"canonical", "permuted"}
        Where the Hamiltonian cycle runs. ``"canonical"`` is SPRAND's own
        (Cherkassky, Goldberg, Radzik): arcs ``0 -> 1 -> ... -> n-1 -> 0``
        first, then the random arcs. ``"permuted"`` runs the cycle along a
        random permutation of the nodes (this module's original layout):
        the same family up to a relabelling of the nodes, but a solver that
        walks adjacency lists in node order loses its memory locality on it
        (Boost's solve takes about 3x longer at n = 10^5). Both are fair
        graphs; a table must say which one it used.

    Examples
    --------
    >>> src, dst, w, t = sprand(4, arcs_per_node=2, layout="canonical", seed=1)
    >>> src[:4].tolist(), dst[:4].tolist(), len(src)
    ([0, 1, 2, 3], [1, 2, 3, 0], 8)
    """
    if layout not in LAYOUTS:
        raise ValueError(f"layout: expected one of {', '.join(LAYOUTS)}, got {layout!r}")
    rng = np.random.default_rng(seed)
    m = arcs_per_node * n
    # The permutation is drawn in both layouts, so the random arcs, weights and
    # tokens of a seed are the same in both: only the cycle's labels differ.
    perm = rng.permutation(n)
    if layout == "canonical":
        perm = np.arange(n, dtype=np.int64)
    src = np.empty(m, dtype=np.int64)
    dst = np.empty(m, dtype=np.int64)
    src[:n] = perm
    dst[:n] = np.roll(perm, -1)
    src[n:] = rng.integers(0, n, m - n)
    dst[n:] = rng.integers(0, n, m - n)
    weight = rng.integers(1, max_weight + 1, m)
    tokens = rng.integers(1, max_tokens + 1, m)
    return src, dst, weight, tokens


LAYOUTS = ("canonical", "permuted")
"""Hamiltonian-cycle layouts of :func:`sprand`."""


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


def equal_weights(n: int = 100_000, weight: int = 7, tokens: int = 3, seed: int = 0,
                  layout: str = "permuted"
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """SPRAND's arcs with every weight and every token count equal: all circuits tie."""
    src, dst, _, _ = sprand(n, seed=seed, layout=layout)
    return src, dst, np.full(len(src), weight, dtype=np.int64), np.full(len(src), tokens,
                                                                       dtype=np.int64)
