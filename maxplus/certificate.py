"""Independent, exact checking of cycle-ratio certificates.

A certificate (see :class:`maxplus.cycle_ratio.CycleRatioCertificate`) claims
a cycle time per node, potentials and a policy. It proves the cycle times when

1. along every arc ``j -> i`` between nodes with cycle times, ``χ_i >= χ_j``,
   and when they are equal, ``X_i >= X_j + w·T - W·t`` (``χ = W/T`` in lowest
   terms, ``X`` the potential scaled by ``T``): summed around any circuit this
   gives ``Σw / Σt <= χ`` (the potential argument of Karp [1]_ and of
   Cochet-Terrasson et al. [2]_);
2. every node's policy arc comes from a node of the same cycle time and is
   tight, so following it backwards reaches a circuit of ratio exactly ``χ_i``;
3. no arc leaves the nodes with a cycle time, and the other nodes span no circuit.

This module recomputes all of that from the arcs with integer arithmetic and
trusts nothing computed by the solver but the claimed numbers.

References
----------
.. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np

from ._arrays import INT64_SAFE, abs_max, argmax_ratio, compare_ratios, find_circuit, gcd_arrays
from .errors import CertificateError

if TYPE_CHECKING:
    from .cycle_ratio import CycleRatioResult

__all__ = ["verify_cycle_ratio"]


def verify_cycle_ratio(result: CycleRatioResult) -> None:
    """Check the certificate of a cycle-ratio result in exact arithmetic.

    Checks, with integer arithmetic only, that the potentials are feasible
    on every arc (so no circuit exceeds the claimed cycle times), that every
    policy arc is tight (so the claimed cycle times are reached), and that
    the reported critical circuit has exactly the claimed ratio. This is the
    potential argument behind Karp's theorem [1]_ and Howard's policy
    iteration [2]_.

    Parameters
    ----------
    result : CycleRatioResult
        A result of :func:`maxplus.cycle_ratio.max_cycle_ratio`, with its
        certificate; nothing computed by the solver is trusted but the
        claimed numbers.

    Returns
    -------
    None
        When the certificate proves the claimed cycle times.

    Raises
    ------
    CertificateError
        Naming the arc, node or circuit where the proof fails.

    See Also
    --------
    maxplus.cycle_ratio.max_cycle_ratio : computes the result and certificate.
    maxplus.cycle_ratio.CycleRatioCertificate : what is being checked.

    References
    ----------
    .. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
       digraph", Discrete Mathematics 23(3), 309–311, 1978.
    .. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    >>> from maxplus.cycle_ratio import max_cycle_ratio
    >>> r = max_cycle_ratio([0, 1], [1, 0], [3, 4], [1, 1])
    >>> verify_cycle_ratio(r) is None
    True
    """
    c = result.certificate
    src, dst = np.asarray(result.src), np.asarray(result.dst)
    n = result.n_nodes
    W, T, X, w, t = (np.asarray(a) for a in (c.ratio_num, c.ratio_den, c.potential,
                                             result.weight, result.tokens))
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
    _verify_circuit(result, one_ratio)


def _arc(k: int, everywhere: bool, live: np.ndarray, src: np.ndarray, dst: np.ndarray) -> int:
    """Arc index of the ``k``-th checked arc (all arcs, or those between live nodes)."""
    return int(k) if everywhere else int(np.flatnonzero(live[src] & live[dst])[k])


def _exact_sum(values: np.ndarray) -> int:
    """Sum of integers as a Python int, in int64 when it cannot overflow."""
    values = np.asarray(values)
    if values.dtype != object and abs_max(values) * max(len(values), 1) < INT64_SAFE:
        return int(values.sum())
    return sum(map(int, values.tolist()))


def _verify_circuit(result: CycleRatioResult, one_ratio: bool) -> None:
    c = result.certificate
    arcs = np.asarray(result.circuit, dtype=np.int64)
    live = c.ratio_den != 0
    if result.ratio is None:
        if live.any() or len(arcs):
            raise CertificateError("no ratio is claimed, but some node has a cycle time")
        return
    if len(arcs) == 0:
        raise CertificateError("a ratio is claimed without a circuit")
    src, dst = result.src, result.dst
    if not np.array_equal(dst[arcs], src[np.roll(arcs, -1)]):
        raise CertificateError(f"arcs {arcs.tolist()} do not form a circuit")
    total_w = _exact_sum(result.weight[arcs])
    total_t = _exact_sum(result.tokens[arcs])
    if total_t == 0 or Fraction(total_w, c.scale * total_t) != result.ratio:
        raise CertificateError(
            f"circuit {arcs.tolist()} has ratio "
            f"{Fraction(total_w, c.scale * max(total_t, 1))}, not {result.ratio}"
        )
    claimed_num = np.asarray(result.cycle_time_num)
    claimed_den = np.asarray(result.cycle_time_den)
    if one_ratio:
        # Every node has the certificate's one cycle time: so must every claim.
        top = Fraction(int(c.ratio_num[0]), c.scale * int(c.ratio_den[0]))
        if top != result.ratio:
            raise CertificateError(f"the cycle time is {top}, not the claimed {result.ratio}")
        same = (claimed_num == claimed_num[0]) & (claimed_den == claimed_den[0])
        if not same.all() or claimed_den[0] <= 0 or Fraction(int(claimed_num[0]),
                                                              int(claimed_den[0])) != top:
            k = int(np.flatnonzero(~same)[0]) if not same.all() else 0
            raise CertificateError(f"the cycle time of node {k} disagrees with its certificate")
        return
    nodes = np.flatnonzero(live)
    best = argmax_ratio(c.ratio_num[nodes], c.ratio_den[nodes])
    top = Fraction(int(c.ratio_num[nodes[best]]), c.scale * int(c.ratio_den[nodes[best]]))
    if top != result.ratio:
        raise CertificateError(f"the largest cycle time is {top}, not the claimed {result.ratio}")
    # Claimed cycle times: a/b == ratio_num / (scale * ratio_den) by exact
    # cross-multiplication, all nodes at once; none claimed where none is proven.
    wrong = np.flatnonzero(claimed_den[~live] != 0)
    if len(wrong):
        k = int(np.flatnonzero(~live)[wrong[0]])
        raise CertificateError(f"node {k} claims a cycle time that its certificate does not prove")
    den = np.asarray(c.ratio_den)[nodes]
    scaled = den * c.scale if abs_max(den) * c.scale < INT64_SAFE else den.astype(object) * c.scale
    b = claimed_den[nodes]
    bad = b <= 0
    ok = ~bad
    bad[ok] = compare_ratios(claimed_num[nodes][ok], b[ok], np.asarray(c.ratio_num)[nodes][ok],
                             scaled[ok]) != 0
    if bad.any():
        k = int(nodes[np.flatnonzero(bad)[0]])
        raise CertificateError(f"the cycle time of node {k} disagrees with its certificate")
