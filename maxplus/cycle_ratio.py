"""Maximum cycle ratio and cycle-time vector of large sparse graphs, certified.

Arrays in, arrays out, in the style of :mod:`scipy.sparse.csgraph`: a graph
is given by arc arrays ``src``, ``dst``, ``weight`` and ``tokens``. An arc
``j -> i`` with weight ``w`` and ``t`` tokens is the (max,+) dependency
``x_i(k) >= x_j(k - t) + w``. The *cycle ratio* of a circuit is
``Σ weight / Σ tokens``; the cycle time of node ``i``,
``χ_i = lim x_i(k) / k``, is the largest cycle ratio among the circuits from
which ``i`` can be reached ([1]_, Thm 3.112; for a matrix, all tokens are 1
and this is the maximum cycle mean [2]_).

The kernel is Howard's multichain policy iteration [3]_, run entirely in
**exact integer arithmetic**: weights are scaled to integers by their common
denominator, the bias of a node is kept multiplied by the token count of its
policy circuit, and ratios are compared by cross-multiplication. Every step is a
numpy operation on whole arrays (pointer doubling for the policy graph,
segmented reductions for the improvement), so the cost per iteration is
``O(m + n log n)`` with no Python loop over nodes or arcs. Where the compiled
kernel :mod:`maxplus._howard_kernel` is built, int64 data run that same
iteration in C, step for step, with the same result, and the checks around it
too (the numpy kernel stays the reference, and the fallback past int64): on
graphs of a few arcs the fixed cost of numpy's calls would outweigh the work.
The choice, and every crossover between strategies, is :mod:`maxplus._kernels`.

The result carries a certificate that :meth:`CycleRatioResult.verify` checks
independently, in exact arithmetic: the returned circuit attains the ratio,
and integer potentials show that no circuit exceeds any node's cycle time.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992.
.. [2] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
.. [3] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
import numpy.typing as npt
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components, depth_first_order

from . import _kernels
from ._arrays import (
    INT64_SAFE,
    abs_max,
    argmax_ratio,
    exact_ints,
    find_circuit,
    gcd_arrays,
    int_array,
)
from ._params import unmasked, whole_number
from .certificate import CycleRatioCertificate, CycleRatioClaim, verify_cycle_ratio
from .errors import MaxPlusValueError, ZeroTokenCircuitError
from .policy_iteration import howard_arrays
from .scalar import exact

__all__ = [
    "CycleRatioCertificate",
    "CycleRatioResult",
    "argmax_ratio",
    "find_circuit",
    "max_cycle_ratio",
]


# Keyword-only: ten fields, six of them arrays; a positional call cannot be read.
@dataclass(kw_only=True)
class CycleRatioResult:
    """Cycle ratio, critical circuit and cycle times of a graph.

    Attributes
    ----------
    ratio : Fraction or None
        Maximum over all circuits of ``Σ weight / Σ tokens``; None without circuit.
    circuit : numpy.ndarray
        Arc indices of one circuit attaining ``ratio``, in order (empty when none).
    cycle_time_num, cycle_time_den : numpy.ndarray
        Per node, ``χ_i = num/den`` in lowest terms; ``den == 0`` for a node that
        no circuit reaches (its cycle time is None).
    certificate : CycleRatioCertificate
        The exact proof of the cycle times.
    iterations : int
        Howard iterations (value determinations) run; 0 without circuit.

    See Also
    --------
    max_cycle_ratio : computes it.
    CycleRatioCertificate : what :meth:`verify` checks.

    Examples
    --------
    >>> r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3])
    >>> r.ratio, r.circuit.tolist(), r.bias
    (Fraction(4, 1), [0, 1], [Fraction(0, 1), Fraction(1, 1)])
    """

    ratio: Fraction | None
    circuit: np.ndarray
    cycle_time_num: np.ndarray
    cycle_time_den: np.ndarray
    certificate: CycleRatioCertificate
    src: np.ndarray = field(repr=False)
    dst: np.ndarray = field(repr=False)
    weight: np.ndarray = field(repr=False)
    tokens: np.ndarray = field(repr=False)
    iterations: int = 0
    _cycle_times: list[Fraction | None] | None = field(default=None, repr=False)

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return len(self.cycle_time_num)

    @property
    def cycle_times(self) -> list[Fraction | None]:
        """Cycle time of every node (Fraction), None where no circuit reaches it."""
        if self._cycle_times is None:
            # One Fraction per distinct value (nodes of a component share theirs):
            # a Fraction per node costs a gcd each, on graphs of 100,000 nodes.
            distinct: dict[tuple[int, int], Fraction] = {}
            times: list[Fraction | None] = []
            for n, d in zip(self.cycle_time_num.tolist(), self.cycle_time_den.tolist()):
                if d == 0:
                    times.append(None)
                    continue
                value = distinct.get((n, d))
                if value is None:
                    value = distinct[n, d] = Fraction(int(n), int(d))
                times.append(value)
            self._cycle_times = times
        return self._cycle_times

    @property
    def policy(self) -> np.ndarray:
        """Per node, the index of its chosen in-arc (-1 for nodes without cycle time)."""
        return self.certificate.policy

    @property
    def bias(self) -> list[Fraction | None]:
        """Per node, the bias (potential) ``v`` with ``v_i >= v_j + w - χ_i t``.

        Equality holds on policy arcs; arcs ``j -> i`` with ``χ_j < χ_i`` are
        not constrained.
        """
        c = self.certificate
        return [
            None if d == 0 else Fraction(int(p), c.scale * int(d))
            for p, d in zip(c.potential.tolist(), c.ratio_den.tolist())
        ]

    def policy_circuit(self, node: int) -> np.ndarray:
        """Arcs of the circuit that ``node``'s policy leads back to, in forward order.

        Its ratio is the cycle time of ``node`` (a critical circuit for it).

        Parameters
        ----------
        node : int
            A node with a cycle time, in ``range(n_nodes)``.

        Returns
        -------
        numpy.ndarray of int
            Arc indices of the circuit, in forward order.

        Raises
        ------
        MaxPlusValueError
            ``node`` is not a whole number in range, or has no cycle time.

        Examples
        --------
        >>> r = max_cycle_ratio([0, 1, 1, 1], [1, 0, 1, 2], [5, 3, 3, 0])
        >>> r.policy_circuit(2).tolist(), r.cycle_times[2]
        ([1, 0], Fraction(4, 1))
        """
        k = whole_number(node, "node")
        if k >= self.n_nodes:
            raise MaxPlusValueError(f"expected a node below n_nodes={self.n_nodes}, got {k}",
                                    "node")
        if self.certificate.policy[k] < 0:
            raise MaxPlusValueError(f"node {k} has no cycle time: no circuit reaches it", "node")
        return _policy_circuit(k, self.certificate.policy, self.src)

    @property
    def circuit_nodes(self) -> list[int]:
        """Nodes of the critical circuit: the source of each of its arcs, in order."""
        nodes: list[int] = self.src[self.circuit].tolist()
        return nodes

    def verify(self) -> bool:
        """Check the certificate exactly; return True or raise CertificateError.

        Returns
        -------
        bool
            True when the certificate proves the claimed cycle times.

        Raises
        ------
        CertificateError
            Naming the arc, node or circuit where the proof fails.

        See Also
        --------
        maxplus.certificate.verify_cycle_ratio : the checker this calls.

        Examples
        --------
        >>> max_cycle_ratio([0, 1], [1, 0], [3, 4], [1, 1]).verify()
        True
        """
        claim = CycleRatioClaim(self.ratio, self.circuit, self.cycle_time_num,
                                self.cycle_time_den, self.certificate)
        verify_cycle_ratio(self.src, self.dst, self.weight, self.tokens, claim)
        return True


def max_cycle_ratio(
    src: Any,
    dst: Any,
    weight: Any,
    tokens: Any = None,
    n_nodes: int | None = None,
) -> CycleRatioResult:
    """Maximum cycle ratio, critical circuit and cycle-time vector, certified.

    Parameters
    ----------
    src, dst : array_like of int
        Arc ``a`` goes from node ``src[a]`` to node ``dst[a]``.
    weight : array_like
        Exact weights: ints, Fractions, decimal or fraction strings, floats
        (read by their shortest decimal text). Negative weights are allowed.
    tokens : array_like of int, optional
        Non-negative token counts (default 1 on every arc: the maximum cycle mean).
    n_nodes : int, optional
        Number of nodes (default ``max(src, dst) + 1``), at most
        ``2 * len(src) + MAX_SPARE_NODES`` (2**20): every result has one entry
        per node, so nodes are not relabelled but bounded by what the arcs can
        touch, which keeps memory proportional to the input. A graph whose
        node numbers are sparse (say up to 10**12) is to be numbered from 0
        first (``numpy.unique(..., return_inverse=True)`` does it).

    Masked arrays are accepted when nothing is masked. Every bad argument
    raises :class:`~maxplus.errors.MaxPlusValueError` naming it.

    Returns
    -------
    CycleRatioResult
        ``.ratio`` (exact), ``.circuit`` (arc indices), ``.cycle_times`` (per
        node), ``.certificate`` and ``.verify()``.

    Raises
    ------
    MaxPlusValueError
        Mismatched array lengths or shapes, a masked entry, a node index out of
        range or beyond the bound above, ``n_nodes`` not a whole number, a weight
        that is not a finite number, a negative or fractional token count.
    ZeroTokenCircuitError
        A circuit whose arcs carry no token (its ratio is infinite); the
        exception names the circuit's arcs and nodes.

    See Also
    --------
    CycleRatioResult.verify : checks the returned certificate exactly.
    maxplus.certificate.verify_cycle_ratio : the independent checker.
    find_circuit : one circuit among a set of arcs.

    Notes
    -----
    Howard's multichain policy iteration (Cochet-Terrasson et al. [3]_) in
    exact integer arithmetic, compiled where it is built, on numpy arrays
    otherwise (the same steps and result); the cycle-time
    vector of a reducible graph is ``χ_i = max`` over the strongly connected
    classes upstream of ``i`` of their maximum ratio ([1]_, Thm 3.112). With
    all tokens 1 the ratio is
    Karp's maximum cycle mean [2]_. Howard's algorithm was the fastest in
    practice in Dasdan's comparison of cycle-ratio algorithms [4]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.
    .. [2] R. M. Karp, "A characterization of the minimum cycle mean in a
       digraph", Discrete Mathematics 23(3), 309–311, 1978.
    .. [3] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.
    .. [4] A. Dasdan, "Experimental analysis of the fastest optimum cycle ratio
       and mean algorithms", ACM Transactions on Design Automation of
       Electronic Systems 9(4), 385–418, 2004.

    Examples
    --------
    Two circuits, ``0 -> 1 -> 0`` with ratio (5+3)/2 = 4 and the self-loop on
    node 1 with ratio 3/1:

    >>> r = max_cycle_ratio([0, 1, 1], [1, 0, 1], [5, 3, 3], [1, 1, 1])
    >>> r.ratio, r.circuit_nodes, r.cycle_times, r.verify()
    (Fraction(4, 1), [0, 1], [Fraction(4, 1), Fraction(4, 1)], True)
    """
    src_a, dst_a, n = _validate_arcs(src, dst, n_nodes)
    w_int, scale = _validate_weights(weight, len(src_a))
    t_int = _validate_tokens(tokens, len(src_a))
    _refuse_zero_token_circuits(src_a, dst_a, t_int, n)
    return _solve(src_a, dst_a, w_int, t_int, scale, n)


# --------------------------------------------------------------------------- validation


MAX_SPARE_NODES = 2**20
"""Nodes that no arc touches, allowed beyond the two per arc (see :func:`max_cycle_ratio`)."""


def _validate_arcs(src: Any, dst: Any, n_nodes: Any) -> tuple[np.ndarray, np.ndarray, int]:
    src_a = _index_array(src, "src")
    dst_a = _index_array(dst, "dst")
    if len(src_a) != len(dst_a):
        raise MaxPlusValueError(
            f"src has {len(src_a)} arcs but dst has {len(dst_a)}", "dst"
        )
    # Every result array has one entry per node: the node count is bounded by
    # what the arcs can touch, so that memory stays proportional to the input.
    limit = 2 * len(src_a) + MAX_SPARE_NODES
    bound = (f"at most {limit} nodes for {len(src_a)} arcs (2 per arc + {MAX_SPARE_NODES}); "
             "number the nodes the arcs use from 0")
    src_top, dst_top = int(src_a.max(initial=-1)), int(dst_a.max(initial=-1))
    top = max(src_top, dst_top)

    def where() -> str:  # the first arc naming the largest node (only for a message)
        name = "src" if src_top == top else "dst"
        return f"{name}[{int(np.argmax(src_a if name == 'src' else dst_a))}]" if top >= 0 else ""

    if n_nodes is None:
        if top >= limit:
            raise MaxPlusValueError(f"node {top} is out of range: {bound}", where())
        n = top + 1
    else:
        n = whole_number(n_nodes, "n_nodes")
        if n > limit:
            raise MaxPlusValueError(f"n_nodes={n} is too large: {bound}", "n_nodes")
        if top >= n:
            raise MaxPlusValueError(f"node {top} is out of range for n_nodes={n}", where())
    # int32 node indices (when they fit) halve the memory every pass and every
    # gather over the arcs moves; contiguous copies read faster than strided views.
    index = np.int32 if max(n, len(src_a)) < 2**31 else np.int64
    return (np.ascontiguousarray(src_a, dtype=index), np.ascontiguousarray(dst_a, dtype=index), n)


def _vector(values: Any, name: str) -> np.ndarray:
    """A 1-D array of the values, as given: no masked entry, no int rounded to a float."""
    values = unmasked(values, name)
    if isinstance(values, np.ndarray):
        arr = values
    else:
        try:
            arr = np.asarray(values)
        except ValueError:  # ragged nesting
            raise MaxPlusValueError("expected a 1-D array (one value per arc), got nested "
                                    "sequences of different lengths", name) from None
        if arr.dtype.kind == "f":
            # numpy 2 turns Python ints past uint64 into floats (2**64 + 1 becomes
            # 2.0**64): keep the objects, exact, and read each one.
            arr = np.asarray(values, dtype=object)
    if arr.ndim != 1:
        raise MaxPlusValueError(f"expected a 1-D array (one value per arc), got shape "
                                f"{arr.shape}", name)
    return arr


def _index_array(values: Any, name: str) -> np.ndarray:
    arr = _vector(values, name)
    if arr.dtype.kind in "iu":
        out = arr
        if arr.dtype.kind == "u" and len(arr) and int(arr.max()) > np.iinfo(np.int64).max:
            k = int(np.argmax(arr))
            raise MaxPlusValueError(f"node index {arr[k]} is too large", f"{name}[{k}]")
    else:
        out = np.empty(len(arr), dtype=np.int64)
        for k, v in enumerate(arr.tolist()):
            integral = isinstance(v, int) or (isinstance(v, float) and v.is_integer())
            if isinstance(v, bool) or not integral:
                raise MaxPlusValueError(f"expected a node index, got {v!r}", f"{name}[{k}]")
            if v >= 2**63:  # beyond any n_nodes allowed, and beyond int64
                raise MaxPlusValueError(f"node index {int(v)} is too large", f"{name}[{k}]")
            out[k] = int(v)
    if len(out) and out.min() < 0:
        k = int(np.flatnonzero(out < 0)[0])
        raise MaxPlusValueError(f"expected a node index >= 0, got {out[k]}", f"{name}[{k}]")
    return out


def _validate_weights(weight: Any, m: int) -> tuple[np.ndarray, int]:
    """Scale exact weights to integers; returns (int64 or object array, scale)."""
    arr = _vector(weight, "weight")
    if len(arr) != m:
        raise MaxPlusValueError(
            f"expected {m} weights (one per arc), got shape {np.shape(arr)}", "weight"
        )
    if arr.dtype.kind in "iu":
        # Contiguous: every pass of the solver and of verify() gathers from it (a
        # column of an (m, 4) table gathered 2.5x slower than its copy).
        return np.ascontiguousarray(exact_ints(arr)), 1
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise MaxPlusValueError(
                f"expected a finite weight, got {arr[k]}", f"weight[{k}]"
            )
        if np.all(arr == np.round(arr)) and (m == 0 or np.abs(arr).max() < 2**53):
            return arr.astype(np.int64), 1
    items = arr.tolist()
    if arr.dtype == object and all(type(v) is int for v in items):
        # Scaled integers too large for int64 (tegraph's holdings over a big common
        # denominator) are exact already: skip one Fraction per arc.
        return int_array(items), 1
    values = [exact(v, f"weight[{k}]", allow_eps=False) for k, v in enumerate(items)]
    scale = 1
    for v in values:
        scale = math.lcm(scale, v.denominator)
    return int_array([int(v * scale) for v in values]), scale


def _validate_tokens(tokens: Any, m: int) -> np.ndarray:
    if tokens is None:
        return np.ones(m, dtype=np.int64)
    arr = _vector(tokens, "tokens")
    if len(arr) != m:
        raise MaxPlusValueError(
            f"expected {m} token counts (one per arc), got shape {np.shape(arr)}", "tokens"
        )
    if arr.dtype.kind in "iu":
        arr = np.ascontiguousarray(exact_ints(arr))
    else:
        counts = []
        for k, v in enumerate(arr.tolist()):
            try:
                f = Fraction(v) if not isinstance(v, float) else Fraction(repr(v))
            except (TypeError, ValueError):
                raise MaxPlusValueError(f"expected a whole number of tokens, got {v!r}",
                                        f"tokens[{k}]") from None
            if isinstance(v, bool) or f.denominator != 1:
                raise MaxPlusValueError(f"expected a whole number of tokens, got {v!r}",
                                        f"tokens[{k}]")
            counts.append(int(f))
        arr = int_array(counts)  # Python ints past int64: token counts of any size
    if m and arr.min() < 0:
        k = int(np.flatnonzero(arr < 0)[0])
        raise MaxPlusValueError(f"expected a token count >= 0, got {arr[k]}", f"tokens[{k}]")
    return arr


def _refuse_zero_token_circuits(src: np.ndarray, dst: np.ndarray, tokens: np.ndarray,
                                n: int) -> None:
    compiled = _kernels.howard_kernel()
    if compiled is not None and tokens.dtype == np.int64 and src.dtype in _INDEX_DTYPES:
        # Kahn's algorithm in C says whether there is one; only then is it found and named.
        if compiled.off_circuits(src, dst, n, tokens)[1] == n:
            return
    zero = np.flatnonzero(tokens == 0)
    circuit = find_circuit(src, dst, n, zero)
    if circuit:
        raise ZeroTokenCircuitError(circuit, src[circuit].tolist())


# --------------------------------------------------------------------------- Howard


def _solve(src: np.ndarray, dst: np.ndarray, w: np.ndarray, t: np.ndarray, scale: int,
           n: int) -> CycleRatioResult:

    live = _nodes_reached_by_circuits(src, dst, n)
    num = np.zeros(n, dtype=np.int64)
    den = np.zeros(n, dtype=np.int64)
    potential = np.zeros(n, dtype=np.int64)
    policy = np.full(n, -1, dtype=np.int64)
    circuit = np.zeros(0, dtype=np.int64)
    ratio: Fraction | None = None
    iterations = 0
    if live is None or live.any():
        nodes: slice | np.ndarray
        if live is None:  # every node: no relabelling, no copies
            nodes = slice(None)
            solution = howard_arrays(src, dst, w, t, n)
            s_pol = solution.policy
        else:
            keep = np.flatnonzero(live[src] & live[dst])
            nodes = np.flatnonzero(live)
            relabel = np.full(n, -1, dtype=np.int64)
            relabel[nodes] = np.arange(len(nodes))
            solution = howard_arrays(relabel[src[keep]], relabel[dst[keep]], w[keep], t[keep],
                                     len(nodes))
            s_pol = keep[solution.policy]
        iterations = solution.iterations
        if solution.ratio_num.dtype == object:
            num, den, potential = (np.zeros(n, dtype=object) for _ in range(3))
        num[nodes] = solution.ratio_num
        den[nodes] = solution.ratio_den
        potential[nodes] = solution.potential
        policy[nodes] = s_pol
        compiled = _kernels.howard_kernel()
        if compiled is not None and solution.ratio_num.dtype == np.int64:
            best = compiled.first_largest_ratio(solution.ratio_num, solution.ratio_den)
        else:
            best = argmax_ratio(solution.ratio_num, solution.ratio_den)
        if isinstance(nodes, np.ndarray):  # relabelled (live is not None): the caller's node
            best = int(nodes[best])
        circuit = _policy_circuit(best, policy, src)
        ratio = Fraction(int(num[best]), scale * int(den[best]))
    # Cycle times in lowest terms, with the weight scale folded in (in Python
    # ints when den * scale could leave int64).
    if scale == 1:
        # Howard's ratios are in lowest terms already (each circuit's W/T is
        # reduced) and nodes without a cycle time hold 0/0: what _reduce would
        # give, without its gcd per node (3.5 ms at 10^5 nodes).
        ct_num, ct_den = num.copy(), den.copy()
    else:
        scaled_den = (den * scale if abs_max(den) * scale < INT64_SAFE
                      else den.astype(object) * scale)
        ct_num, ct_den = _reduce(num, scaled_den, den != 0)
    cert = CycleRatioCertificate(scale, num, den, potential, policy, circuit)
    return CycleRatioResult(ratio=ratio, circuit=circuit, cycle_time_num=ct_num,
                            cycle_time_den=ct_den, certificate=cert, src=src, dst=dst,
                            weight=w, tokens=t, iterations=iterations)


def _nodes_reached_by_circuits(src: np.ndarray, dst: np.ndarray, n: int) -> np.ndarray | None:
    """Boolean mask of the nodes downstream of (or on) some circuit; None for all nodes.

    When every node has an in-arc, a walk backwards along in-arcs never stops,
    so it repeats a node: every node lies downstream of a circuit, and no
    strongly connected components are needed.
    """
    if len(src) == 0:
        return np.zeros(n, dtype=bool)
    compiled = _kernels.howard_kernel()
    if compiled is not None and src.dtype in _INDEX_DTYPES:
        off, count = compiled.off_circuits(src, dst, n)
        return None if count == 0 else ~off
    if n and np.bincount(dst, minlength=n).min() > 0:
        return None
    graph = sp.csr_matrix((np.ones(len(src), dtype=np.int8), (src, dst)), shape=(n, n))
    n_comp, labels = connected_components(graph, directed=True, connection="strong")
    sizes = np.bincount(labels, minlength=n_comp)
    cyclic: npt.NDArray[np.bool_] = sizes[labels] > 1
    cyclic[src[src == dst]] = True
    if not cyclic.any():
        return cyclic
    # Breadth-first search from a virtual root joined to every cyclic node.
    roots = np.flatnonzero(cyclic)
    big = sp.csr_matrix(
        (np.ones(len(src) + len(roots), dtype=np.int8),
         (np.concatenate([src, np.full(len(roots), n)]), np.concatenate([dst, roots]))),
        shape=(n + 1, n + 1),
    )
    order = breadth_first_order(big, n, directed=True, return_predecessors=False)
    reached = np.zeros(n + 1, dtype=bool)
    reached[order] = True
    return reached[:n]


def _reduce(num: np.ndarray, den: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    g = gcd_arrays(num, den)
    g = np.where(mask & (g != 0), g, 1)
    out_num = np.where(mask, num // g, 0)
    out_den = np.where(mask, den // g, 0)
    return out_num, out_den


def _policy_circuit(start: int, policy: np.ndarray, src: np.ndarray) -> np.ndarray:
    """Arcs of the policy circuit reached backwards from ``start``, in forward order.

    Each node has one policy predecessor: the walk ``start, pred(start), ...``
    runs until a node repeats (or has no policy arc), and closes on the
    predecessor of its last node. The walk is followed node by node while it
    is short: it is as long as the circuit and the path to it, whereas a
    graph of all n nodes per call cost O(n) each time (one call per group of
    a skeleton: quadratic). The compiled kernel walks it in ``O(walk)`` time
    and no memory per node (:func:`maxplus._howard_kernel.policy_circuit`);
    without it, a walk longer than ``walk_in_python`` steps (a critical
    circuit through most of the graph, a step of Python per node) is
    finished in C by a depth-first search of the policy graph, a cost
    proportional to n that only a walk of that length pays.
    """
    compiled = _kernels.howard_kernel()
    if (compiled is not None and policy.dtype == np.int64 and src.dtype in _INDEX_DTYPES
            and policy.flags.c_contiguous and src.flags.c_contiguous):
        found: np.ndarray | None = compiled.policy_circuit(int(start), policy, src)
        if found is not None:
            return found
    seen: set[int] = set()
    walk_list: list[int] = []
    node = int(start)
    walk_in_python = _kernels.current().walk_in_python
    while node not in seen:
        if len(walk_list) == walk_in_python:
            return _policy_circuit_in_c(start, policy, src)
        seen.add(node)
        walk_list.append(node)
        arc = int(policy[node])
        if arc < 0:
            break
        node = int(src[arc])
    walk = np.array(walk_list, dtype=np.int64)
    entry = int(src[policy[walk[-1]]])
    cycle_nodes = walk[int(np.flatnonzero(walk == entry)[0]):]
    return policy[cycle_nodes][::-1].copy()


_INDEX_DTYPES = (np.dtype(np.int32), np.dtype(np.int64))
"""The node index types of the compiled walk (those :func:`_validate_arcs` gives)."""


def _policy_circuit_in_c(start: int, policy: np.ndarray, src: np.ndarray) -> np.ndarray:
    """:func:`_policy_circuit` by one depth-first search of the policy graph (node -> pred).

    Every node has at most one successor there, so the search from ``start``
    visits exactly the walk, in order, and stops where it would repeat.
    """
    n = len(policy)
    has = policy >= 0
    pred = np.where(has, src[np.where(has, policy, 0)], 0)
    graph = sp.csr_matrix((np.ones(int(has.sum()), dtype=np.int8),
                           (np.flatnonzero(has), pred[has])), shape=(n, n))
    walk = depth_first_order(graph, int(start), directed=True, return_predecessors=False)
    entry = int(pred[walk[-1]])
    cycle_nodes = walk[int(np.flatnonzero(walk == entry)[0]):]
    arcs: npt.NDArray[np.int64] = policy[cycle_nodes][::-1].astype(np.int64)
    return arcs
