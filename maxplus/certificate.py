"""Independent, exact checking of cycle-ratio claims.

A claim (:class:`CycleRatioClaim`) states a maximum cycle ratio, a circuit
attaining it and a cycle time per node; its proof (:class:`CycleRatioCertificate`)
adds potentials and a policy. The proof holds when

1. along every arc ``j -> i`` between nodes with cycle times, ``χ_i >= χ_j``,
   and when they are equal, ``X_i >= X_j + w·T - W·t`` (``χ = W/T`` in lowest
   terms, ``X`` the potential scaled by ``T``): summed around any circuit this
   gives ``Σw / Σt <= χ`` (the potential argument of Karp [1]_ and of
   Cochet-Terrasson et al. [2]_);
2. every node's policy arc comes from a node of the same cycle time and is
   tight, so following it backwards reaches a circuit of ratio exactly ``χ_i``;
3. no arc leaves the nodes with a cycle time, and the other nodes span no circuit.

This module recomputes all of that from the arc arrays with integer
arithmetic. It owns the claim types and imports nothing of the solver
(:mod:`maxplus.cycle_ratio` builds a claim and calls :func:`verify_cycle_ratio`;
an import-linter contract keeps the arrow one way, type-only imports
included), so nothing the solver computed is trusted but the claimed numbers.

References
----------
.. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from . import _kernels
from ._arrays import INT64_SAFE, abs_max, argmax_ratio, compare_ratios, find_circuit, gcd_arrays
from .errors import CertificateError

__all__ = ["CycleRatioCertificate", "CycleRatioClaim", "verify_cycle_ratio"]


@dataclass(frozen=True)
class CycleRatioCertificate:
    """Exact proof of the cycle times of a graph.

    All numbers are integers. For a node ``i`` with a cycle time,
    ``χ_i = ratio_num[i] / (scale * ratio_den[i])`` and its potential is
    ``potential[i] / (scale * ratio_den[i])``.

    The proof (checked by :func:`verify_cycle_ratio`):

    1. along every arc ``j -> i`` between nodes with cycle times, ``χ_i >= χ_j``,
       and when ``χ_i == χ_j``, ``potential_i >= potential_j + w·T - W·t``
       (``W/T`` the reduced ratio): so every circuit has ratio at most the
       common cycle time of its nodes;
    2. every node's ``policy`` arc attains that inequality with equality and
       comes from a node of the same cycle time, so following the policy
       backwards reaches a circuit of ratio exactly ``χ_i``;
    3. no arc leads from a node with a cycle time to one without, and the
       nodes without a cycle time span no circuit.

    Attributes
    ----------
    scale : int
        Common denominator by which the weights were scaled to integers.
    ratio_num, ratio_den : numpy.ndarray of int
        Per node, the reduced cycle time times ``scale``; ``ratio_den == 0``
        for a node without cycle time.
    potential : numpy.ndarray of int
        Per node, the potential scaled by ``scale * ratio_den``.
    policy : numpy.ndarray of int
        Per node, its chosen in-arc (-1 for a node without cycle time).
    circuit : numpy.ndarray of int
        Arcs of one critical circuit, in order.

    See Also
    --------
    verify_cycle_ratio : checks it, with the rest of a :class:`CycleRatioClaim`.
    maxplus.cycle_ratio.CycleRatioResult.verify : checks a solver's result.

    Examples
    --------
    >>> from maxplus.cycle_ratio import max_cycle_ratio
    >>> c = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3]).certificate
    >>> c.scale, c.ratio_num.tolist(), c.ratio_den.tolist(), c.potential.tolist()
    (1, [4, 4], [1, 1], [0, 1])
    """

    scale: int
    ratio_num: np.ndarray
    ratio_den: np.ndarray
    potential: np.ndarray
    policy: np.ndarray
    circuit: np.ndarray


@dataclass(frozen=True)
class CycleRatioClaim:
    """What a cycle-ratio solver claims about a graph, with its proof.

    Attributes
    ----------
    ratio : Fraction or None
        The maximum cycle ratio; None for a graph without circuit.
    circuit : array_like of int
        Arc indices of a circuit attaining ``ratio``, in order (empty when none).
    cycle_time_num, cycle_time_den : array_like of int
        Per node, its cycle time ``num/den`` (``den == 0``: none); their
        length is the number of nodes.
    certificate : CycleRatioCertificate
        The potentials and policy that prove them.

    See Also
    --------
    verify_cycle_ratio : checks a claim against the arcs.
    """

    ratio: Fraction | None
    circuit: Any
    cycle_time_num: Any
    cycle_time_den: Any
    certificate: CycleRatioCertificate


def verify_cycle_ratio(src: Any, dst: Any, weight: Any, tokens: Any,
                       claim: CycleRatioClaim) -> None:
    """Check a cycle-ratio claim against the arcs of its graph, in exact arithmetic.

    Checks, with integer arithmetic only, that the potentials are feasible
    on every arc (so no circuit exceeds the claimed cycle times), that every
    policy arc is tight (so the claimed cycle times are reached), and that
    the claimed critical circuit has exactly the claimed ratio. This is the
    potential argument behind Karp's theorem [1]_ and Howard's policy
    iteration [2]_.

    Parameters
    ----------
    src, dst : array_like of int
        Arc ``a`` goes from node ``src[a]`` to node ``dst[a]``.
    weight : array_like of int
        The arc weights times ``claim.certificate.scale``, integers.
    tokens : array_like of int
        The token count of each arc.
    claim : CycleRatioClaim
        The claimed ratio, circuit and cycle times, and their certificate:
        the only numbers of a solver that this function reads.

    Returns
    -------
    None
        When the certificate proves the claimed cycle times.

    Raises
    ------
    CertificateError
        Naming the arc, node or circuit where the proof fails, or the array
        whose length disagrees with the others.

    See Also
    --------
    maxplus.cycle_ratio.max_cycle_ratio : a solver that makes such claims.
    maxplus.cycle_ratio.CycleRatioResult.verify : checks a result of it.

    References
    ----------
    .. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
       digraph", Discrete Mathematics 23(3), 309–311, 1978.
    .. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    The circuit ``0 -> 1 -> 0`` (arcs 0 and 1, weights 3 and 5, one token
    each) has ratio 8/2 = 4. Potentials 0 and -1 make both arcs tight:
    ``X_1 = X_0 + 3 - 4`` and ``X_0 = X_1 + 5 - 4``.

    >>> import numpy as np
    >>> from fractions import Fraction
    >>> proof = CycleRatioCertificate(scale=1, ratio_num=np.array([4, 4]),
    ...     ratio_den=np.array([1, 1]), potential=np.array([0, -1]),
    ...     policy=np.array([1, 0]), circuit=np.array([0, 1]))
    >>> claim = CycleRatioClaim(Fraction(4), [0, 1], [4, 4], [1, 1], proof)
    >>> verify_cycle_ratio([0, 1], [1, 0], [3, 5], [1, 1], claim) is None
    True
    >>> verify_cycle_ratio([0, 1], [1, 0], [3, 6], [1, 1], claim)
    Traceback (most recent call last):
    ...
    maxplus.errors.CertificateError: arc 1 (1 -> 0) violates the potential inequality: ...
    """
    c = claim.certificate
    src, dst, weight, tokens = _arc_arrays(src, dst, weight, tokens)
    n = _node_count(src, dst, claim)
    one_ratio = _compiled_checks(src, dst, weight, tokens, c)
    if one_ratio is not None:  # every arc and policy check below holds: the circuit is left
        _verify_circuit(src, dst, weight, tokens, claim, one_ratio)
        return
    W, T, X, w, t = (np.asarray(a) for a in (c.ratio_num, c.ratio_den, c.potential,
                                             weight, tokens))
    live = T != 0
    everywhere = bool(live.all())
    W_live, T_live = (W, T) if everywhere else (W[live], T[live])
    if (T_live < 0).any():
        raise CertificateError("a ratio denominator is negative")
    if len(T_live) and (gcd_arrays(W_live, T_live) != 1).any():
        raise CertificateError("cycle-time fractions in a certificate must be in lowest terms")
    # Both fractions reduced and T > 0: equal ratios have equal (W, T), so each
    # check below needs only one product of a ratio part and an arc datum.
    big_ratio = abs_max(W) * abs_max(T)
    big_value = abs_max(X) + abs_max(w) * abs_max(T) + abs_max(W) * abs_max(t)
    # The arrays themselves must fit too: a graph without circuit has T = 0,
    # which would hide a weight beyond int64 from the products above.
    big_entry = max(abs_max(a) for a in (W, T, X, w, t))
    dtype = np.int64 if 2 * max(big_ratio, big_value, big_entry) < INT64_SAFE else object
    W, T, X, w, t = (a.astype(dtype, copy=False) for a in (W, T, X, w, t))
    if everywhere:
        i, j, w_arc, t_arc = dst, src, w, t
    else:
        live_src, live_dst = live[src], live[dst]
        leak = np.flatnonzero(live_src & ~live_dst)
        if len(leak):
            a = int(leak[0])
            raise CertificateError(
                f"arc {a} ({src[a]} -> {dst[a]}) leaves a node with a cycle time for one without"
            )
        loop = find_circuit(src, dst, n, np.flatnonzero(~live_src & ~live_dst))
        if loop:
            raise CertificateError(f"circuit of arcs {loop} has no cycle time in the certificate")
        a_idx = np.flatnonzero(live_src & live_dst)
        i, j, w_arc, t_arc = dst[a_idx], src[a_idx], w[a_idx], t[a_idx]
    one_ratio = bool(everywhere and len(W) and (W == W[0]).all() and (T == T[0]).all())
    if one_ratio:
        # One cycle time everywhere: no arc goes from a larger one to a smaller
        # one, and the potential inequality holds with the same W/T on every arc.
        broken = X[j] + (w_arc * T[0] - W[0] * t_arc) > X[i]
    else:
        slower = W[j] * T[i] > W[i] * T[j]
        if slower.any():
            a = _arc(np.flatnonzero(slower)[0], everywhere, live, src, dst)
            raise CertificateError(
                f"arc {a} ({src[a]} -> {dst[a]}) goes from a larger cycle time to a smaller one"
            )
        same = (W[j] == W[i]) & (T[j] == T[i])
        broken = same & (X[j] + w_arc * T[i] - W[i] * t_arc > X[i])
    if broken.any():
        a = _arc(np.flatnonzero(broken)[0], everywhere, live, src, dst)
        raise CertificateError(
            f"arc {a} ({src[a]} -> {dst[a]}) violates the potential inequality: "
            "some circuit through it may exceed the claimed cycle time"
        )
    nodes = np.arange(n) if everywhere else np.flatnonzero(live)
    pol = np.asarray(c.policy) if everywhere else np.asarray(c.policy)[nodes]
    if len(nodes):
        if (pol < 0).any() or (pol >= len(src)).any() or (dst[pol] != nodes).any():
            raise CertificateError("a policy arc does not end at its node")
        j = src[pol]
        if not live[j].all():
            raise CertificateError("a policy arc comes from a node without cycle time")
        if one_ratio:
            tight = X[j] + (w[pol] * T[0] - W[0] * t[pol]) == X
        else:
            i = nodes
            tight = (W[j] == W[i]) & (T[j] == T[i]) & (X[j] + w[pol] * T[i] - W[i] * t[pol] == X[i])
        bad = np.flatnonzero(~tight)
        if len(bad):
            k = int(nodes[bad[0]])
            raise CertificateError(f"the policy arc of node {k} is not tight")
    _verify_circuit(src, dst, weight, tokens, claim, one_ratio)


def _compiled_checks(src: np.ndarray, dst: np.ndarray, weight: np.ndarray, tokens: np.ndarray,
                     c: CycleRatioCertificate) -> bool | None:
    """The arc and policy checks of :func:`verify_cycle_ratio` in one compiled pass.

    None when they were not made (no compiled module, arrays not all of signed
    integers, a node without cycle time, products that may leave int64) or one
    fails: the numpy checks then run and name what fails. Otherwise whether
    every node has the same cycle time (what :func:`_verify_circuit` asks).
    """
    compiled = _kernels.certificate_kernel()
    if compiled is None:
        return None
    arrays = [np.asarray(a) for a in (src, dst, weight, tokens, c.ratio_num, c.ratio_den,
                                      c.potential, c.policy)]
    if any(a.dtype.kind != "i" for a in arrays):  # object arrays hold big integers
        return None
    # The ends stay int32 where the solver keeps them so (a copy of 4 m entries less).
    ends = np.int32 if src.dtype == dst.dtype == np.int32 else np.int64
    held: int = compiled.arc_checks(
        *(np.ascontiguousarray(a, dtype=ends) for a in arrays[:2]),
        *(np.ascontiguousarray(a, dtype=np.int64) for a in arrays[2:]))
    return None if not held else held == compiled.ONE_RATIO


def _arc_arrays(src: Any, dst: Any, weight: Any, tokens: Any) -> tuple[np.ndarray, ...]:
    """The four arc arrays, refused unless they are one-dimensional and of one length."""
    arrays = tuple(np.asarray(a) for a in (src, dst, weight, tokens))
    if any(a.ndim != 1 for a in arrays) or len({len(a) for a in arrays}) != 1:
        shapes = ", ".join(f"{name} {a.shape}" for name, a in
                           zip(("src", "dst", "weight", "tokens"), arrays))
        raise CertificateError(f"expected src, dst, weight and tokens of one length, got {shapes}")
    return arrays


def _node_count(src: np.ndarray, dst: np.ndarray, claim: CycleRatioClaim) -> int:
    """The number of nodes: every per-node array of the claim has it, every arc ends below it."""
    c = claim.certificate
    if isinstance(c.scale, bool) or not isinstance(c.scale, (int, np.integer)) or c.scale <= 0:
        raise CertificateError(f"the claim's scale is {c.scale!r}; expected an integer > 0")
    n = len(claim.cycle_time_num) if np.ndim(claim.cycle_time_num) == 1 else -1
    per_node = {"cycle_time_num": claim.cycle_time_num, "cycle_time_den": claim.cycle_time_den,
                "ratio_num": c.ratio_num, "ratio_den": c.ratio_den, "potential": c.potential,
                "policy": c.policy}
    for name, values in per_node.items():
        if np.ndim(values) != 1 or len(values) != n:
            raise CertificateError(f"the claim's {name} has shape {np.shape(values)}; "
                                   "expected one entry per node (as many as cycle_time_num)")
    for name, ends in (("src", src), ("dst", dst)):
        out = np.flatnonzero((ends < 0) | (ends >= n))
        if len(out):
            a = int(out[0])
            raise CertificateError(f"arc {a} has {name} {ends[a]}, not a node of the claim "
                                   f"(expected 0 to {n - 1})")
    return n


def _arc(k: int, everywhere: bool, live: np.ndarray, src: np.ndarray, dst: np.ndarray) -> int:
    """Arc index of the ``k``-th checked arc (all arcs, or those between live nodes)."""
    return int(k) if everywhere else int(np.flatnonzero(live[src] & live[dst])[k])


def _exact_sum(values: np.ndarray) -> int:
    """Sum of integers as a Python int, in int64 when it cannot overflow."""
    values = np.asarray(values)
    if values.dtype != object and abs_max(values) * max(len(values), 1) < INT64_SAFE:
        return int(values.sum())
    return sum(map(int, values.tolist()))


def _verify_circuit(src: np.ndarray, dst: np.ndarray, weight: np.ndarray, tokens: np.ndarray,
                    claim: CycleRatioClaim, one_ratio: bool) -> None:
    c = claim.certificate
    ratio_num, ratio_den = np.asarray(c.ratio_num), np.asarray(c.ratio_den)
    arcs = np.asarray(claim.circuit, dtype=np.int64)
    live = ratio_den != 0
    if claim.ratio is None:
        if live.any() or len(arcs):
            raise CertificateError("no ratio is claimed, but some node has a cycle time")
        return
    if len(arcs) == 0:
        raise CertificateError("a ratio is claimed without a circuit")
    if arcs.ndim != 1 or (arcs < 0).any() or (arcs >= len(src)).any():
        raise CertificateError(f"the circuit {arcs.tolist()} names an arc that does not exist "
                               f"(expected arc indices below {len(src)})")
    if not np.array_equal(dst[arcs], src[np.roll(arcs, -1)]):
        raise CertificateError(f"arcs {arcs.tolist()} do not form a circuit")
    total_w = _exact_sum(weight[arcs])
    total_t = _exact_sum(tokens[arcs])
    if total_t == 0 or Fraction(total_w, c.scale * total_t) != claim.ratio:
        raise CertificateError(
            f"circuit {arcs.tolist()} has ratio "
            f"{Fraction(total_w, c.scale * max(total_t, 1))}, not {claim.ratio}"
        )
    claimed_num = np.asarray(claim.cycle_time_num)
    claimed_den = np.asarray(claim.cycle_time_den)
    if one_ratio:
        # Every node has the certificate's one cycle time: so must every claim.
        top = Fraction(int(ratio_num[0]), c.scale * int(ratio_den[0]))
        if top != claim.ratio:
            raise CertificateError(f"the cycle time is {top}, not the claimed {claim.ratio}")
        same = (claimed_num == claimed_num[0]) & (claimed_den == claimed_den[0])
        if not same.all() or claimed_den[0] <= 0 or Fraction(int(claimed_num[0]),
                                                              int(claimed_den[0])) != top:
            k = int(np.flatnonzero(~same)[0]) if not same.all() else 0
            raise CertificateError(f"the cycle time of node {k} disagrees with its certificate")
        return
    nodes = np.flatnonzero(live)
    best = argmax_ratio(ratio_num[nodes], ratio_den[nodes])
    top = Fraction(int(ratio_num[nodes[best]]), c.scale * int(ratio_den[nodes[best]]))
    if top != claim.ratio:
        raise CertificateError(f"the largest cycle time is {top}, not the claimed {claim.ratio}")
    # Claimed cycle times: a/b == ratio_num / (scale * ratio_den) by exact
    # cross-multiplication, all nodes at once; none claimed where none is proven.
    wrong = np.flatnonzero(claimed_den[~live] != 0)
    if len(wrong):
        k = int(np.flatnonzero(~live)[wrong[0]])
        raise CertificateError(f"node {k} claims a cycle time that its certificate does not prove")
    den = ratio_den[nodes]
    scaled = den * c.scale if abs_max(den) * c.scale < INT64_SAFE else den.astype(object) * c.scale
    b = claimed_den[nodes]
    bad = b <= 0
    ok = ~bad
    bad[ok] = compare_ratios(claimed_num[nodes][ok], b[ok], ratio_num[nodes][ok],
                             scaled[ok]) != 0
    if bad.any():
        k = int(nodes[np.flatnonzero(bad)[0]])
        raise CertificateError(f"the cycle time of node {k} disagrees with its certificate")
