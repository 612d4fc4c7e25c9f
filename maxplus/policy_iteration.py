"""Howard's multichain policy iteration for cycle ratios, in exact integers.

The kernel behind :func:`maxplus.cycle_ratio.max_cycle_ratio`. Arrays in,
arrays out; nothing here validates input (that is done once, at the edge).
Where :mod:`maxplus._howard_kernel` is compiled (``pip install .`` builds it
with the machine's C compiler), int64 data run there first: the same
iteration, step for step, with the same result; the numpy kernel below runs
when it is missing, and where it gives up (numbers past its int64 bounds).
Which kernel runs, and the sizes at which the numpy kernel below changes
strategy, are read from :mod:`maxplus._kernels`, the one switch of maxplus.
Only the dtypes may differ: int64 whenever the compiled kernel finishes, where
the numpy kernel may carry the same values as Python ints (its bounds are
computed before the numbers exist).

A *policy* keeps one in-arc per node; following policy arcs backwards from
any node ends on a policy circuit. *Value determination* gives every node the
ratio ``W/T`` of the circuit it reaches (reduced fraction) and a potential
``X`` (the bias multiplied by ``T``) that is tight along policy arcs.
*Policy improvement* switches a node to an in-arc from a node of strictly
larger ratio, or, failing that, to an in-arc of the same ratio with a strictly
larger potential. A larger ratio is passed on at once to every node
downstream (each switch a strict gain over the node's current ratio, so no new
policy circuit can form and the step is a valid improvement): without that,
a long chain below a slow circuit would take one iteration per node. When
nothing improves, the potentials satisfy the optimality inequalities
everywhere: that is the certificate.

Value determination doubles pointers: after ``k`` rounds every node knows the
node ``2**k`` policy arcs upstream of it and the weight and token sums of those
arcs (the tails ride in the packed sums: one gather through the policy per
round). Once those landing nodes all lie on policy circuits (the image of the
landing map is closed under the policy, checked each round), a node's
potential is its landing node's plus the sums, because the potential terms
``w·T - W·t`` add up to zero around a circuit. Only the circuit nodes, usually
few, need their own pass (their smallest node is the root, of potential 0 or
of its previous potential; circuits the policy kept are not walked again).
Policy trees are shallow on most graphs, so this takes a handful of rounds; a
chain of length ``L`` takes ``log2 L``.

Policy improvement takes, per node, the maximum of packed keys over its
in-arcs: by blocks of nodes of equal in-degree (a ``d x k`` array per degree,
an elementwise maximum of its rows) when the degrees take few values, by
``np.maximum.reduceat`` otherwise. A ratio step passes the larger ratio
downstream breadth first; a round reaching many nodes scans all arcs rather
than gathering rows.

Every quantity is an integer: int64 while bounds computed from the data in
each iteration keep every sum and product below ``2**62`` (weight and token
sums travel packed in one int64 when their bound allows), Python ints in
object arrays otherwise; no comparison needs a tolerance.

References
----------
.. [1] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick, J.-P. Quadrat,
   "Numerical computation of spectral elements in max-plus algebra", IFAC
   Conference on System Structure and Control, 1998.
.. [2] A. Dasdan, "Experimental analysis of the fastest optimum cycle ratio and
   mean algorithms", ACM TODAES 9(4), 2004 (the cycle-ratio form).
"""

from __future__ import annotations

from functools import cmp_to_key
from typing import Any, Literal, NamedTuple, TypeAlias

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import depth_first_order

from . import _kernels
from ._arrays import INT64_SAFE, abs_max, compare_ratios, float_ratios, gcd_arrays

__all__ = ["howard_arrays"]


class HowardSolution(NamedTuple):
    """Optimal policy found by :func:`howard_arrays`."""

    ratio_num: np.ndarray
    ratio_den: np.ndarray
    potential: np.ndarray
    policy: np.ndarray
    iterations: int


def howard_arrays(src: np.ndarray, dst: np.ndarray, w: np.ndarray, t: np.ndarray,
                  n: int) -> HowardSolution:
    """Optimal policy of a graph in which every node has at least one in-arc.

    Parameters
    ----------
    src, dst : numpy.ndarray of int
        Arcs; every node in ``range(n)`` must be the ``dst`` of some arc.
    w, t : numpy.ndarray
        Integer weights and token counts (int64, or object for Python ints of
        any size), with no circuit of zero tokens.
    n : int
        Number of nodes.

    Returns
    -------
    HowardSolution
        Per node: the cycle time ``ratio_num/ratio_den`` (lowest terms), the
        potential (bias times ``ratio_den``) and the index of its policy arc;
        the number of value determinations.

    See Also
    --------
    maxplus.cycle_ratio.max_cycle_ratio : validates, solves and certifies.

    Notes
    -----
    **Termination.** Write ``χ`` for the per-node ratios and ``X`` for the
    potentials of a value determination.

    1. *Each step strictly improves.* A policy arc ``j -> i`` joins nodes of
       equal ratio (``i`` reaches the circuit that ``j`` reaches). A ratio
       step switches ``i`` to an in-arc whose tail has a strictly larger
       ratio (the sweep likewise, from nodes it raised; which such arc it
       takes, the last one gathered, does not matter here): backwards from any
       node, the old ratios never decrease along the new policy, so a circuit
       of the new policy switched no arc (around a circuit they cannot rise)
       and is an old one; hence ``χ' >= χ`` everywhere, strictly at the
       switched nodes. A bias step switches ``i`` to an in-arc of the same
       ratio with ``X_j + w·T - W·t > X_i``. A new circuit made of such arcs
       and tight policy arcs has, summing around it (the ``X`` cancel),
       ``Σ(w·T - W·t) > 0``: a ratio strictly above ``W/T``, so ``χ`` rises.
       Otherwise every circuit is an old one and keeps its root's potential
       (:func:`_circuits`; when the circuits are exactly the previous ones,
       their numbers are reused, which is what :func:`_circuits` would
       compute again), and summing along the policy path from it gives
       ``X' >= X``, strictly at the switched nodes. The bias step's
       maximum, taken by blocks of equal in-degree or by ``reduceat``, is
       the same maximum of the same packed keys: the arc chosen does not
       depend on how it is computed.
    2. *No policy comes back.* ``χ`` takes finitely many values and never
       decreases, so it changes finitely often; and a policy fixes ``χ``, so
       a policy of an earlier ``χ`` cannot recur. While ``χ`` stays the
       same, no circuit is created (a created circuit raises ``χ``, step 1),
       so the roots and their potentials stay fixed, ``X`` is a function of
       the policy, and ``X`` rising strictly rules out a repeat. There are
       finitely many policies: the iteration ends.
    3. *Each value determination ends.* After ``k`` doubling rounds every
       node lands ``2**k`` policy arcs upstream; once ``2**k`` exceeds the
       height of the policy trees (below ``n``), the landing nodes are the
       circuit nodes, which the landing map permutes, and the loop stops
       (about ``log2 n`` rounds; the first determination checks from round
       ``min(4, bit_length(n - 1) - 1)`` on, so it never runs past the round
       where ``2**k`` first exceeds the height, and walks stay below ``2n``
       arcs as the int64 bounds assume). In :func:`_circuits`, ``back`` maps every
       circuit node to its predecessor on the circuit (a permutation): the
       minimum propagated over ``bit_length(c)`` doublings covers each whole
       circuit, so every circuit has one root, and pointer jumping doubles
       each node's distance to its root per round until it reaches it (the
       Python walk of small circuits and the depth-first walk of long ones
       visit each circuit node once).

    The proof needs every comparison to be exact: all arithmetic is in
    integers, int64 only below bounds computed from the data, Python ints
    otherwise. The proof is also checked while running: a policy seen
    before (a 128-bit digest of it, :class:`_PolicyDigest`) means a bug, not
    a hard graph; the int64 run then starts again in Python ints, and a
    repeat there raises RuntimeError instead of looping. A digest collision
    (about ``2**-66`` per pair of policies) could only raise a false alarm,
    never hide a repeat: equal policies have equal digests.

    Examples
    --------
    Circuit 0 -> 1 -> 0 of ratio (5+3)/2 and a self-loop of ratio 3 on node 1:

    >>> sol = howard_arrays(np.array([0, 1, 1]), np.array([1, 0, 1]),
    ...     np.array([5, 3, 3]), np.array([1, 1, 1]), 2)
    >>> (sol.ratio_num // sol.ratio_den).tolist(), sol.policy.tolist()
    ([4, 4], [1, 0])
    """
    compiled = _kernels.howard_kernel()
    if compiled is not None and _fits_compiled_kernel(w, t, n, len(src)):
        choice = _kernels.current()
        found = compiled.howard(src, dst, w, t, n, choice.sweep_few, choice.scan_min_share)
        if found is not None:  # None: a potential near 2**62, run in numpy (Python ints)
            return HowardSolution(*found)
    arcs = _InArcs(src, dst, w, t, n)
    if w.dtype != object and t.dtype != object:
        try:
            return _howard(arcs)
        except (_LeavesInt64, _Revisited):
            pass  # the same iteration in Python ints, where nothing is packed or bounded
    try:
        return _howard(arcs.as_object())
    except _Revisited:
        raise RuntimeError("internal error: policy iteration revisited a policy "
                           "(it would loop for ever); please report it") from None


def _fits_compiled_kernel(w: np.ndarray, t: np.ndarray, n: int, m: int) -> bool:
    """Whether :mod:`maxplus._howard_kernel` may run: int64 data, fewer than 2**31 arcs.

    The kernel checks the numpy kernel's own first bound itself
    (``2 n max(|w|, t) < 2**62``, in its first pass over the arcs) and gives
    None beyond it: both kernels would leave int64 from the start, and the
    result is the numpy kernel's, in Python ints.
    """
    return w.dtype == np.int64 and t.dtype == np.int64 and 0 < n and max(n, m) < 2**31


class _LeavesInt64(Exception):
    """A sum or product could leave what int64 arithmetic carries exactly."""


class _Revisited(Exception):
    """The iteration came back to a policy it had left: a bug, caught rather than looped on."""


def stable_order(keys: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Permutation that sorts ``keys`` (ints in ``range(n)``) stably, and the segment offsets.

    A counting sort in C (scipy's COO to CSR conversion, whose column indices
    are the positions: distinct and increasing within a row, so nothing is
    summed or re-sorted), several times faster than a comparison sort.

    >>> order, starts = stable_order(np.array([2, 0, 2, 1]), 3)
    >>> order.tolist(), starts.tolist()
    ([1, 3, 0, 2], [0, 1, 2, 4])
    """
    m = len(keys)
    choice = _kernels.current()
    index = (np.intp if max(n, m) <= choice.intp_max_arcs else np.int32 if max(n, m) < 2**31
             else np.int64)
    positions = np.arange(m, dtype=index)
    if _coo_tocsr is not None and choice.scipy_coo_tocsr:
        # The conversion itself, without the sparse array's checks and copies, which
        # cost more than the conversion (benchmarks/results/constants.md).
        starts, order = np.empty(n + 1, dtype=index), np.empty(m, dtype=index)
        ones = np.ones(m, dtype=np.int8)
        _coo_tocsr(n, m, m, keys.astype(index, copy=False), positions, ones, starts, order,
                   np.empty(m, dtype=np.int8))
        return order, starts
    matrix = sp.csr_array((np.ones(m, dtype=np.int8), (keys, positions)), shape=(n, m))
    return matrix.indices.astype(index, copy=False), matrix.indptr.astype(index, copy=False)


try:  # scipy's own COO to CSR routine (private, in every scipy this project accepts)
    from scipy.sparse._sparsetools import coo_tocsr as _coo_tocsr
except ImportError:  # pragma: no cover - a scipy that moved it: the public conversion
    _coo_tocsr = None


_OutArcs: TypeAlias = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Any]
"""What :meth:`_InArcs.out_arcs` gives; the last item is a scipy sparse array (untyped)."""


class _InArcs:
    """Arcs sorted by head (CSR of in-arcs), built once; the order by tail on demand."""

    def __init__(self, src: np.ndarray | None, dst: np.ndarray | None, w: np.ndarray,
                 t: np.ndarray, n: int,
                 _sorted: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
                 ) -> None:
        self.n = n
        if _sorted is not None:
            self.order, self.s_src, self.s_dst, self.starts = _sorted
        else:
            assert src is not None and dst is not None  # only as_object() gives none (sorted)
            self.order, self.starts = stable_order(dst, n)
            index = self.order.dtype
            self.s_src = src[self.order].astype(index, copy=False)
            self.s_dst = np.repeat(np.arange(n, dtype=index), np.diff(self.starts))
        self.s_w = w[self.order] if _sorted is None else w
        self.s_t = t[self.order] if _sorted is None else t
        self._out: _OutArcs | None = None

    def as_object(self) -> _InArcs:
        return _InArcs(None, None, _objects(self.s_w), _objects(self.s_t), self.n,
                       (self.order, self.s_src, self.s_dst, self.starts))

    def out_arcs(self) -> _OutArcs:
        """Sorted-arc positions grouped by tail, their heads, offsets and counts (for sweeps).

        The last item is the same as a sparse matrix (row: tail, column: head,
        value: position), whose row selection gathers many rows in one C pass.
        """
        if self._out is None:
            out_order, out_starts = stable_order(self.s_src, self.n)
            out_dst = self.s_dst[out_order]
            rows = sp.csr_array((out_order, out_dst, out_starts), shape=(self.n, self.n))
            self._out = (out_order, out_dst, out_starts[:-1], np.diff(out_starts), rows)
        return self._out

    def initial_policy(self) -> np.ndarray:
        """The heaviest in-arc of each node, a good first guess.

        (The in-arc of largest ``w/t`` was measured too and took more
        iterations: 40 against 32 on SPRAND 10^5, 49 against 33 on the torus.)
        """
        firsts = self.starts[:-1]
        seg_max = np.maximum.reduceat(self.s_w, firsts)  # object arrays too (Python ints)
        hit = np.flatnonzero(self.s_w == seg_max[self.s_dst])
        seg = self.s_dst[hit]
        first = np.concatenate(([True], seg[1:] != seg[:-1]))
        return hit[first].astype(self.order.dtype, copy=False)


def _objects(a: np.ndarray) -> np.ndarray:
    out = np.empty(len(a), dtype=object)
    out[:] = a.tolist()
    return out


class _Values(NamedTuple):
    """One value determination: per node ratio ``W/T``, potential ``X``, ratio rank.

    With one ratio everywhere (``n_ranks == 1``), ``W`` and ``T`` are that
    ratio's two integers and ``rank`` is None: no per-node arrays to fill and
    compare in every iteration.
    """

    W: Any
    T: Any
    X: np.ndarray
    rank: np.ndarray | None
    n_ranks: int
    x_max: int  # a bound on abs(X)

    def ratio_at(self, nodes: np.ndarray) -> tuple[Any, Any]:
        if self.n_ranks == 1:
            return self.W, self.T
        return self.W[nodes], self.T[nodes]

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """``W`` and ``T`` per node."""
        if self.n_ranks == 1:
            n = len(self.X)
            return (np.full(n, self.W, dtype=self.X.dtype),
                    np.full(n, self.T, dtype=self.X.dtype))
        return self.W, self.T


class _Bounds:
    """Scratch space, the int64 bounds and the packed arc sums of one Howard run."""

    def __init__(self, arcs: _InArcs) -> None:
        n = arcs.n
        self.wide = arcs.s_w.dtype == object
        self.w_max, self.t_max = abs_max(arcs.s_w), abs_max(arcs.s_t)
        # A landing walk has at most 2**rounds <= 2n arcs (the doubling stops once
        # 2**rounds reaches the height of the policy trees, which is below n).
        if not self.wide and 2 * n * max(self.w_max, self.t_max) >= INT64_SAFE:
            raise _LeavesInt64
        # While a walk has at most 2**packed_rounds arcs, its landing node, token
        # sum and weight sum travel in one int64, w_sum * 2**(L+B) + t_sum * 2**L
        # + land (0 <= land < 2**L, 0 <= t_sum < 2**B): a doubling round is then
        # one gather. The fields are sized for the longest walk that fits.
        self.land_bits = max(1, (n - 1).bit_length())
        self.packed_rounds = 0
        if not self.wide:
            for rounds in range(n.bit_length() + 2):
                t_bits = ((1 << rounds) * self.t_max).bit_length()
                w_bits = ((1 << rounds) * self.w_max).bit_length() + 1
                if self.land_bits + t_bits + w_bits > 62:
                    break
                self.packed_rounds, self.t_bits = rounds, t_bits
        self.packed = None
        if self.packed_rounds:  # per arc: its weight, its tokens and its tail
            self.packed = arcs.s_w << (self.land_bits + self.t_bits)
            self.packed += arcs.s_t << self.land_bits
            self.packed += arcs.s_src
            self.low = np.empty(n, dtype=np.int64)
            self.following = np.empty(n, dtype=np.int64)
        # Of the previous value determination. The first one starts tracking the
        # landing image from round 4 (walks of 16 arcs): earlier, each round's image
        # is about as large as the graph and costs more than the doubling. Never
        # past 2**start <= n - 1, so that a walk stays below 2n arcs (bound above).
        self.rounds_hint, self.circuit_hint = min(5, (n - 1).bit_length()), 64
        self.mark = np.zeros(n, dtype=arcs.order.dtype)
        self.seen = np.zeros(n, dtype=bool)
        # Of the previous value determination: its circuit nodes and arcs, and what
        # _circuits found for them.
        self.circuits: tuple[np.ndarray, np.ndarray, _Circuits] | None = None
        self.local = np.zeros(n, dtype=arcs.order.dtype)

    def unpack(self, packed: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(land, w_sum, t_sum) of packed walks."""
        land = packed & ((1 << self.land_bits) - 1)
        t_sum = (packed >> self.land_bits) & ((1 << self.t_bits) - 1)
        return land, packed >> (self.land_bits + self.t_bits), t_sum

    def check(self, value: int) -> None:
        if not self.wide and value >= INT64_SAFE:
            raise _LeavesInt64


def _howard(arcs: _InArcs) -> HowardSolution:
    s_src, s_dst = arcs.s_src, arcs.s_dst
    bounds = _Bounds(arcs)
    terms = _ArcTerms(arcs, bounds)
    pol = terms.initial_policy() if not bounds.wide else None
    if pol is None:
        pol = arcs.initial_policy()
    iterations = 0
    prev: _Values | None = None
    check_all = True
    digest = _PolicyDigest(arcs.n)
    seen = {digest(pol)}
    while True:
        cur = _value_determination(pol, arcs, prev, bounds)
        iterations += 1
        cand = None
        if not check_all:
            assert prev is not None  # check_all holds in the first iteration
            # An arc between two nodes whose ratio and potential did not change
            # was not improving at the last check and still is not. (Picking
            # those arcs out costs more than it saves when many nodes changed.)
            if cur.n_ranks == 1 and prev.n_ranks == 1:
                changed = (cur.X != prev.X) if (cur.W, cur.T) == (prev.W, prev.T) else None
            else:
                W, T = cur.arrays()
                W_prev, T_prev = prev.arrays()
                changed = (W != W_prev) | (T != T_prev) | (cur.X != prev.X)
            if changed is not None and 8 * np.count_nonzero(changed) < arcs.n:
                cand = np.flatnonzero(changed[s_src] | changed[s_dst])
        prev = cur
        step = _improve(pol, cur, cand, arcs, terms)
        if step is None and cand is not None:
            step = _improve(pol, cur, None, arcs, terms)  # the last word checks every arc
        if step is None:
            return HowardSolution(*cur.arrays(), cur.X, arcs.order[pol], iterations)
        key = digest(pol)
        if key in seen:  # impossible by the proof in howard_arrays: a bug
            raise _Revisited
        seen.add(key)
        # After a ratio improvement, gains were not examined: check all arcs next.
        check_all = step == "ratio"


class _PolicyDigest:
    """128 bits that tell policies apart: two random linear hashes modulo 2**64.

    ``h(p) = Σ R[i] * p[i] mod 2**64`` for random odd ``R``: two different
    policies differ by a vector ``d != 0`` with ``|d[i]| < 2**63``, and
    ``Σ R[i] * d[i]`` vanishes modulo 2**64 for at most a ``2**-(64 - v)``
    share of the ``R`` (``2**v`` the largest power of two dividing some
    ``d[i]``; ``v < 31`` for int32 indices). Two independent rows make a
    collision about ``2**-66`` per pair of policies; a collision would only
    restart the run in Python ints (:func:`howard_arrays`). One matrix-vector
    product, cheaper than hashing the policy's bytes (blake2b) at every iteration.
    """

    def __init__(self, n: int) -> None:
        rng = np.random.default_rng(0x6D61_7870)  # fixed: runs are reproducible
        self.rows = rng.integers(0, 2**64, size=(2, n), dtype=np.uint64) | np.uint64(1)

    def __call__(self, pol: np.ndarray) -> bytes:
        return (self.rows @ pol.astype(np.uint64)).tobytes()


class _ArcTerms:
    """The arc terms ``w*T - W*t`` of the bias test, kept while one ratio holds everywhere.

    Stored, when int64 allows, as packed keys ``term * 2**bits + rank``, where
    ``rank`` orders the in-arcs of a node from the last (0) to the first: then
    ``(X[tail] * 2**bits + key)`` has its maximum over a node's in-arcs at the
    first arc of largest value, and one segmented maximum finds both the best
    value and its arc. A key is not a term (it is ``2**bits`` times larger):
    keys never leave this class (:meth:`best_values` uses them), :meth:`terms`
    always gives terms, so that no caller can take one for the other (reading
    keys as terms made up gains, and the iteration switched between two
    policies for ever).
    """

    def __init__(self, arcs: _InArcs, bounds: _Bounds) -> None:
        self.arcs, self.bounds = arcs, bounds
        self.ratio: tuple[Any, Any] | None = None  # (W, T) of the stored terms
        self.stored: np.ndarray | None = None  # keys (packed) or terms, in sorted-arc order
        self.block_keys: np.ndarray | None = None  # keys in block order (_lay_out_blocks)
        self.packed = False
        self.laid_out = False
        self.term_max = 0
        degrees = np.diff(arcs.starts)
        self.degree_max = int(degrees.max()) if len(degrees) else 1
        self.bits = (self.degree_max - 1).bit_length()
        self.blocks: list[tuple[int, int, int, int]] | None = None

    def _arc_order(self, positions: np.ndarray | slice) -> np.ndarray:
        """Each arc's place among its head's in-arcs, counted from the last (0)."""
        arcs = self.arcs
        where = np.arange(len(arcs.s_dst), dtype=np.int64)[positions]
        order: np.ndarray = arcs.starts[arcs.s_dst[positions]] + (self.degree_max - 1) - where
        return order

    def _store(self, W: Any, T: Any) -> None:
        if self.ratio == (W, T):
            return
        arcs = self.arcs
        self.ratio = (W, T)
        self.term_max = self.bounds.w_max * abs(int(T)) + abs(int(W)) * self.bounds.t_max
        self.packed = not self.bounds.wide and self.term_max << (self.bits + 1) < INT64_SAFE
        self.stored = self.block_keys = None
        if self.packed and not self.laid_out:
            self._lay_out_blocks()
        if self.packed and self.blocks is not None:
            # Keys in block order only; the terms of a few candidate arcs are
            # computed when asked (:meth:`terms`).
            keys = self.block_w * T
            keys -= W * self.block_t
            keys <<= self.bits
            keys += self.block_order
            self.block_keys = keys
            return
        stored = arcs.s_w * T
        stored -= W * arcs.s_t
        if self.packed:
            stored <<= self.bits
            stored += self._arc_order(slice(None))
        self.stored = stored

    def best_values(self, X: np.ndarray, W: Any, T: Any, x_max: int
                    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Nodes whose best packed value ``X[tail] * 2**bits + key`` beats their potential.

        Returns those nodes and their best packed values (value ``>> bits``,
        arc rank ``& (2**bits - 1)``), or None unless packed keys of
        potentials up to ``x_max`` fit int64.
        """
        self._store(W, T)
        if not (self.packed and (self.term_max + x_max) << (self.bits + 1) < INT64_SAFE):
            return None
        if self.blocks is not None:
            return self.block_maxima(X)
        bits, arcs = self.bits, self.arcs
        best = np.maximum.reduceat((X << bits)[arcs.s_src] + self.stored, arcs.starts[:-1])
        nodes = np.flatnonzero((best >> bits) > X)
        return nodes, best[nodes]

    def terms(self, W: Any, T: Any, cand: np.ndarray | None) -> np.ndarray:
        """The terms of the arcs ``cand`` (None: all arcs), never to be written to."""
        self._store(W, T)
        if self.stored is None:  # keys are kept in block order only
            arcs = self.arcs
            sub = slice(None) if cand is None else cand
            out: np.ndarray = arcs.s_w[sub] * T
            out -= W * arcs.s_t[sub]
            return out
        stored = self.stored if cand is None else self.stored[cand]
        # An arithmetic shift floors: (term * 2**bits + rank) >> bits == term, signs included.
        found: np.ndarray = stored >> self.bits if self.packed else stored
        return found

    def _lay_out_blocks(self) -> None:
        """Group the nodes by in-degree, for :meth:`block_maxima`.

        The nodes of in-degree ``d`` form a block; the block lists their first
        in-arcs, then their second ones, ... (a ``d x k`` array, one column per
        node), so that the maximum over each node's in-arcs is a maximum of
        ``d`` rows, elementwise and contiguous. ``np.maximum.reduceat`` does
        the same per node with a per-segment overhead, which costs more than
        the blocks on large graphs. Only when the degrees take few values
        (each block is one numpy call).
        """
        arcs = self.arcs
        self.laid_out = True
        self.blocks = None
        degrees = np.diff(arcs.starts)
        counts = np.bincount(degrees)
        distinct = np.flatnonzero(counts)
        if len(distinct) > _kernels.current().max_degree_blocks:
            return
        index = arcs.order.dtype
        # The nodes by increasing degree (a counting sort): each block is a slice.
        self.block_nodes, node_starts = stable_order(degrees, len(counts))
        first_arcs = self.block_first = arcs.starts[self.block_nodes]
        block_arcs = np.empty(len(arcs.s_src), dtype=index)
        # Row r of a block holds r-th in-arcs: their rank from the last possible
        # in-arc (see _arc_order) is degree_max - 1 - r, whatever the node.
        self.block_order = np.empty(len(arcs.s_src), dtype=index)
        blocks = []
        arc_at = 0
        for d in distinct.tolist():  # a loop over distinct degrees (at most 64)
            node_at, k = int(node_starts[d]), int(counts[d])
            rows = np.arange(d, dtype=index)[:, None]
            np.add(first_arcs[node_at:node_at + k][None, :], rows,
                   out=block_arcs[arc_at:arc_at + d * k].reshape(d, k))
            np.subtract(self.degree_max - 1, rows,
                        out=self.block_order[arc_at:arc_at + d * k].reshape(d, k))
            blocks.append((arc_at, d, node_at, k))
            arc_at += d * k
        self.block_src = arcs.s_src[block_arcs]
        self.block_w, self.block_t = arcs.s_w[block_arcs], arcs.s_t[block_arcs]
        self.blocks = blocks

    def initial_policy(self) -> np.ndarray | None:
        """:meth:`_InArcs.initial_policy` by blocks of equal in-degree; None without blocks.

        The first row of largest weight in a node's column is its first
        heaviest in-arc: one ``argmax`` per block, where the segmented
        maximum, its comparison with every arc and the first hit per node
        took six passes over the arcs (the blocks are laid out here, which
        the bias step would do in its first call anyway).
        """
        if not self.laid_out:
            self._lay_out_blocks()
        if self.blocks is None:
            return None
        pol = np.empty(self.arcs.n, dtype=self.arcs.order.dtype)
        for arc_at, d, node_at, k in self.blocks:
            row = np.argmax(self.block_w[arc_at:arc_at + d * k].reshape(d, k), axis=0)
            row += self.block_first[node_at:node_at + k]
            pol[self.block_nodes[node_at:node_at + k]] = row
        return pol

    def block_maxima(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nodes whose best packed value ``X[tail] * 2**bits + key`` beats their potential.

        Returns those nodes and their best packed values: what the segmented
        maximum over the in-arcs sorted by head gives, by blocks of equal
        in-degree (:meth:`_lay_out_blocks`).
        """
        # Called only once _lay_out_blocks laid them out and _store filled the keys.
        assert self.blocks is not None and self.block_keys is not None
        bits = self.bits
        value = (X << bits)[self.block_src]
        value += self.block_keys
        best = np.empty(len(X), dtype=np.int64)
        for arc_at, d, node_at, k in self.blocks:
            np.maximum.reduce(value[arc_at:arc_at + d * k].reshape(d, k), axis=0,
                              out=best[node_at:node_at + k])
        hit = np.flatnonzero((best >> bits) > X[self.block_nodes])
        return self.block_nodes[hit], best[hit]


_Step: TypeAlias = Literal["ratio", "bias"]
"""A policy improvement: to an arc of larger ratio, or of the same ratio and larger bias."""


def _improve(pol: np.ndarray, cur: _Values, cand: np.ndarray | None, arcs: _InArcs,
             terms: _ArcTerms) -> _Step | None:
    """Switch policy arcs among ``cand`` (None: all arcs); the kind of step taken, or None."""
    s_src, s_dst = arcs.s_src, arcs.s_dst
    W, T, X, rank = cur.W, cur.T, cur.X, cur.rank
    cs, cd = (s_src, s_dst) if cand is None else (s_src[cand], s_dst[cand])
    if cur.n_ranks > 1:
        assert rank is not None  # _Values has a rank array exactly when n_ranks > 1
        rank_src, rank_dst = rank[cs], rank[cd]
        # 1. Ratio improvement: a predecessor whose ratio is strictly larger.
        better = np.flatnonzero(rank_src > rank_dst)
        if len(better):
            chosen, nodes = _best_per_node(better if cand is None else cand[better],
                                           rank_src[better], s_dst)
            pol[nodes] = chosen
            rank[nodes] = rank[s_src[chosen]]
            _sweep_downstream(pol, rank, nodes, arcs)
            return "ratio"
        # 2. Bias improvement among predecessors of the same ratio (then the
        #    potentials share the denominator T, so integers compare directly).
        sub = slice(None) if cand is None else cand
        value = X[cs] + arcs.s_w[sub] * T[cd] - W[cd] * arcs.s_t[sub]
        gain = np.flatnonzero((rank_src == rank_dst) & (value > X[cd]))
    else:
        found = terms.best_values(X, W, T, cur.x_max) if cand is None else None
        if found is not None:
            # One segmented maximum over all arcs: best value and its arc.
            nodes, best = found
            if len(nodes) == 0:
                return None
            offset = (terms.degree_max - 1) - (best & ((1 << terms.bits) - 1))
            pol[nodes] = arcs.starts[nodes] + offset
            return "bias"
        value = X[cs] + terms.terms(W, T, cand)
        gain = np.flatnonzero(value > X[cd])
    if len(gain) == 0:
        return None
    chosen, nodes = _best_per_node(gain if cand is None else cand[gain], value[gain], s_dst)
    pol[nodes] = chosen
    return "bias"


def _sweep_downstream(pol: np.ndarray, rank: np.ndarray, frontier: np.ndarray,
                      arcs: _InArcs) -> None:
    """Pass larger ratio ranks downstream from ``frontier``, switching policies (in place).

    A node switches only to an in-arc whose tail ranks strictly higher, and
    takes that rank, which is then the ratio of the circuit it reaches under
    the new policy. The largest rank goes first, breadth first: a node raised
    once already holds the largest rank that can reach it from the frontier,
    so no node switches twice and the sweep touches each arc about once.
    """
    out_order, out_dst, out_starts, out_counts, rows = arcs.out_arcs()
    n = len(rank)
    choice = _kernels.current()
    few, scan_min_share, rows_min_level = (choice.sweep_few, choice.scan_min_share,
                                           choice.rows_min_level)
    done = np.zeros(n, dtype=bool)
    pending = frontier[np.argsort(-rank[frontier], kind="stable")]  # distinct nodes
    cuts = np.flatnonzero(np.diff(rank[pending])) + 1
    for level in np.split(pending, cuts):
        level = level[~done[level]]
        if len(level) == 0:
            continue
        top = rank[level[0]]
        done[level] = True
        while len(level):
            if len(level) <= few:
                # A deep chain advances a node or two per round: numpy's
                # per-call overhead would dominate, so its rounds are walked in
                # Python for as long as they stay this small.
                level = _sweep_few(level, pol, rank, done, top, out_order, out_dst,
                                   out_starts, out_counts, few)
                continue
            if len(level) * scan_min_share > n:
                # A large share of the nodes: one scan of all arcs in head order
                # (two gathers from node arrays that stay in cache) beats
                # gathering this many rows (5 ms against 1.5 ms for 40,000 of
                # 10^5 nodes); heads with a rank >= top are dropped below.
                in_level = np.zeros(n, dtype=bool)
                in_level[level] = True
                out = np.flatnonzero(in_level[arcs.s_src])
                heads = arcs.s_dst[out]
            elif len(level) > rows_min_level:
                selected = rows[level]
                out, heads = selected.data, selected.indices
            else:
                lengths = out_counts[level]
                offsets = np.repeat(out_starts[level] - (np.cumsum(lengths) - lengths), lengths)
                offsets += np.arange(len(offsets), dtype=offsets.dtype)
                out, heads = out_order[offsets], out_dst[offsets]
            keep = rank[heads] < top  # every tail here holds rank `top`
            level = _raise(pol, rank, done, heads[keep], out[keep], top)


def _sweep_few(level: np.ndarray, pol: np.ndarray, rank: np.ndarray, done: np.ndarray,
               top: Any, out_order: np.ndarray, out_dst: np.ndarray, out_starts: np.ndarray,
               out_counts: np.ndarray, few: int) -> np.ndarray:
    """Sweep rounds of at most ``few`` nodes (the crossover ``sweep_few``), walked in
    Python element by element; returns the first larger round (or an empty one).

    The same switches in the same order as :func:`_raise` on the gathered
    round: the out-arcs of the round's nodes in order, those into a node of
    lower rank kept, the last kept arc into a node its policy, and the next
    round the nodes raised, in the order of their winning arcs.
    """
    top = top.item() if isinstance(top, np.generic) else top
    nodes = level.tolist()
    while nodes and len(nodes) <= few:
        kept: list[tuple[int, int]] = []
        for u in nodes:
            start = out_starts.item(u)
            for k in range(start, start + out_counts.item(u)):
                head = out_dst.item(k)
                if rank.item(head) < top:
                    kept.append((out_order.item(k), head))
        winner = {head: arc for arc, head in kept}  # the last one written stays
        nodes = [head for arc, head in kept if winner[head] == arc]
        for head, arc in winner.items():
            pol[head] = arc
            rank[head] = top
            done[head] = True
    return np.array(nodes, dtype=np.intp)


def _raise(pol: np.ndarray, rank: np.ndarray, done: np.ndarray, heads: np.ndarray,
           arcs: np.ndarray, top: Any) -> np.ndarray:
    """Switch ``heads`` to ``arcs`` (from nodes of rank ``top``) and raise them; the nodes raised.

    Any such in-arc will do; of several for one node, the last written stays.
    """
    pol[heads] = arcs
    level: np.ndarray = heads[pol[heads] == arcs]
    rank[level] = top
    done[level] = True
    return level


def _best_per_node(arcs: np.ndarray, key: np.ndarray, s_dst: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """For each destination among ``arcs`` (sorted by destination), its arc of largest key."""
    d = s_dst[arcs]
    new_node = np.empty(len(d), dtype=bool)
    new_node[0] = True
    np.not_equal(d[1:], d[:-1], out=new_node[1:])
    starts = np.flatnonzero(new_node)
    if len(starts) == len(d):  # one candidate per node: nothing to choose
        return arcs, d
    segment = np.cumsum(new_node) - 1
    top = np.maximum.reduceat(key, starts)
    hit = np.flatnonzero(key == top[segment])
    first = np.concatenate(([True], segment[hit[1:]] != segment[hit[:-1]]))
    return arcs[hit[first]], d[starts]


def _value_determination(pol: np.ndarray, arcs: _InArcs, prev: _Values | None,
                         bounds: _Bounds) -> _Values:
    """Ratio, potential and ratio rank of every node under a policy."""
    n = arcs.n
    # Pointer doubling: land[v] is 2**rounds policy arcs upstream of v, and
    # (sum_w, sum_t) the sums of those arcs; packed in one int64 while they fit.
    # The packed arcs carry their tails: one gather through the policy, not two.
    packed = bounds.packed[pol] if bounds.packed is not None else None
    mask = (1 << bounds.land_bits) - 1
    pred = ((packed & mask).astype(arcs.s_src.dtype, copy=False) if packed is not None
            else arcs.s_src[pol])
    land, sum_w, sum_t = pred, None, None
    # The image of land is tracked once it is likely small (from one round
    # before the previous determination stopped): the image of land∘land is
    # land's image of land's image, a pass over that image, not over all nodes.
    image = None
    rounds = 0
    while True:
        if image is None and rounds >= bounds.rounds_hint - 1:
            image = _distinct_of_all(np.bitwise_and(packed, mask, out=bounds.low)
                                     if packed is not None else land, bounds.seen)
        if image is not None:
            if len(image) <= bounds.circuit_hint and _closed(image, pred, bounds.mark):
                break
            landed = packed[image] & mask if packed is not None else land[image]
            following = _distinct(landed, bounds.mark)
            if len(following) == len(image):
                break  # land permutes its image: all circuit nodes
            image = following
        if packed is not None and rounds < bounds.packed_rounds:
            low = np.bitwise_and(packed, mask, out=bounds.low)
            following = np.take(packed, low, out=bounds.following)
            packed -= low
            packed += following
        else:
            if packed is not None:
                land, sum_w, sum_t = bounds.unpack(packed)
                packed = None
            elif sum_w is None or sum_t is None:  # both are set, or neither
                sum_w, sum_t = arcs.s_w[pol], arcs.s_t[pol]
            sum_w = sum_w + sum_w[land]
            sum_t = sum_t + sum_t[land]
            land = land[land]
        rounds += 1
    bounds.rounds_hint = rounds
    bounds.circuit_hint = max(64, 2 * len(image))
    if packed is not None:
        land, sum_w, sum_t = bounds.unpack(packed)
    elif sum_w is None:
        sum_w, sum_t = arcs.s_w[pol], arcs.s_t[pol]
    if 64 * len(image) > n:  # sorted by a pass over the nodes rather than a sort
        seen = np.zeros(n, dtype=bool)
        seen[image] = True
        cycle_nodes = np.flatnonzero(seen).astype(pred.dtype, copy=False)
    else:
        cycle_nodes = np.sort(image)
    cycle_arcs = pol[cycle_nodes]
    cached = bounds.circuits
    if (cached is not None and prev is not None and np.array_equal(cached[0], cycle_nodes)
            and np.array_equal(cached[1], cycle_arcs)):
        # The previous determination's circuits, unchanged: each keeps its ratio
        # and its root's potential, and its nodes their potentials (tight around
        # the circuit), so _circuits would compute what it computed then (a
        # critical circuit of 12,000 nodes cost half of each determination).
        W_c, T_c, X_c, circuit_of, rank_c = cached[2]
    else:
        found = _circuits(cycle_nodes, pred, arcs.s_w[cycle_arcs], arcs.s_t[cycle_arcs], prev,
                          bounds)
        bounds.circuits = (cycle_nodes, cycle_arcs, found)
        W_c, T_c, X_c, circuit_of, rank_c = found
    walk = 1 << rounds
    T_max, W_max = abs_max(T_c), abs_max(W_c)
    term_max = bounds.w_max * T_max + W_max * bounds.t_max
    x_max = abs_max(X_c) + walk * term_max
    bounds.check(x_max + term_max)  # the bias test adds a term to a potential
    landing = bounds.local[land]  # index among the circuit nodes
    n_ranks = int(rank_c.max()) + 1
    if n_ranks == 1:  # reduced fractions: every circuit has the same W and T
        W, T, rank = W_c[0], T_c[0], None
    else:
        which = circuit_of[landing]
        W, T, rank = W_c[which], T_c[which], rank_c[which]
    # X = X_c[landing] + sum_w * T - W * sum_t, in the arrays unpacking made.
    sum_w *= T
    sum_t *= W
    sum_w -= sum_t
    sum_w += X_c[landing]
    return _Values(W, T, sum_w, rank, n_ranks, x_max)


def _distinct_of_all(nodes: np.ndarray, seen: np.ndarray) -> np.ndarray:
    """The distinct values of ``nodes`` (one per node: a map's image), sorted.

    Marks in a boolean array, one pass over the nodes: three times faster than
    :func:`_distinct` on all nodes (it writes and reads back positions). The
    marks are cleared again, so ``seen`` stays all False between calls.
    """
    seen[nodes] = True
    image = np.flatnonzero(seen).astype(nodes.dtype, copy=False)
    seen[image] = False
    return image


def _distinct(nodes: np.ndarray, scratch: np.ndarray) -> np.ndarray:
    """The distinct values of ``nodes`` (in no particular order), in ``O(len(nodes))``.

    Each value's slot in ``scratch`` remembers the last position that wrote it;
    only that position keeps the value. Nothing needs clearing between calls.
    """
    positions = np.arange(len(nodes), dtype=scratch.dtype)
    scratch[nodes] = positions
    kept: np.ndarray = nodes[scratch[nodes] == positions]
    return kept


def _closed(image: np.ndarray, pred: np.ndarray, scratch: np.ndarray) -> bool:
    """Whether ``image``, an image of an iterate of the policy map ``f``, holds only circuits.

    Such an image contains every circuit node and satisfies ``f(I) ⊆ I``; it
    holds nothing else exactly when ``f`` is one-to-one on it, i.e. when
    ``f(I)`` is as large as ``I``.
    """
    return len(_distinct(pred[image], scratch)) == len(image)


_Circuits: TypeAlias = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""What :func:`_circuits` finds: ``(W_c, T_c, X_c, circuit_of, rank_c)``."""

_Walked: TypeAlias = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
"""Circuits walked: root positions, circuit of each position, weight and token sums."""


def _circuits(cycle_nodes: np.ndarray, pred: np.ndarray, w_cyc: np.ndarray, t_cyc: np.ndarray,
              prev: _Values | None, bounds: _Bounds) -> _Circuits:
    """Per policy circuit its reduced ratio, rank, and the potentials of its nodes.

    ``w_cyc`` and ``t_cyc`` are the weight and tokens of each circuit node's
    policy arc. Returns ``(W_c, T_c, X_c, circuit_of, rank_c)``: ratio and rank per circuit,
    potential and circuit index per circuit node (in the order of
    ``cycle_nodes``, whose positions ``bounds.local`` records).
    """
    index = pred.dtype
    c = len(cycle_nodes)
    local = bounds.local
    local[cycle_nodes] = np.arange(c, dtype=index)
    back = local[pred[cycle_nodes]]  # the predecessor on the circuit, as a position
    # Root of each circuit: its smallest node, i.e. its first position (the
    # circuit nodes are sorted), so that an unchanged circuit keeps its root
    # from one iteration to the next.
    choice = _kernels.current()
    in_python = c <= choice.python_max_circuit_nodes
    walked = None if in_python else _one_circuit(back, w_cyc, t_cyc)
    if walked is None:
        walks = (_walk_circuits if c > choice.walk_min_circuit_nodes else _python_circuits
                 if in_python else _jump_circuits)
        walked = walks(back, w_cyc, t_cyc)
    roots, circuit_of, sum_w, sum_t = walked
    # The circuit of root r: its own policy arc and the path back to r.
    closing = back[roots]
    W_c = w_cyc[roots] + sum_w[closing]
    T_c = t_cyc[roots] + sum_t[closing]
    g = gcd_arrays(W_c, T_c)  # T_c > 0: no circuit without tokens
    W_c, T_c = W_c // g, T_c // g
    rank_c = _rank_ratios(W_c, T_c)
    # A circuit that was already a policy circuit keeps its root's potential
    # (Cochet-Terrasson et al. [1]): potentials then never decrease between
    # iterations of equal ratios, which rules out cycling.
    root_nodes = cycle_nodes[roots]
    if prev is None:
        carry = np.zeros(len(roots), dtype=W_c.dtype)
    else:
        W_prev, T_prev = prev.ratio_at(root_nodes)
        keep = (W_prev == W_c) & (T_prev == T_c)
        carry = np.where(keep, prev.X[root_nodes], 0)
    bounds.check(abs_max(carry) + c * (bounds.w_max * abs_max(T_c)
                                       + abs_max(W_c) * bounds.t_max))
    if len(roots) == 1:
        X_c = carry[0] + sum_w * T_c[0] - W_c[0] * sum_t
    else:
        X_c = carry[circuit_of] + sum_w * T_c[circuit_of] - W_c[circuit_of] * sum_t
    return W_c, T_c, X_c, circuit_of, rank_c


def _python_circuits(back: np.ndarray, w_cyc: np.ndarray, t_cyc: np.ndarray) -> _Walked:
    """:func:`_jump_circuits` for a few circuit nodes, walked in Python."""
    c = len(back)
    following = [0] * c
    for p, b in enumerate(back.tolist()):
        following[b] = p
    w_l, t_l = w_cyc.tolist(), t_cyc.tolist()
    circuit_of = [-1] * c
    sum_w, sum_t = [0] * c, [0] * c
    roots: list[int] = []
    for p in range(c):  # the first position of each circuit is its root
        if circuit_of[p] >= 0:
            continue
        k = len(roots)
        roots.append(p)
        circuit_of[p] = k
        q, acc_w, acc_t = following[p], 0, 0
        while q != p:
            acc_w += w_l[q]
            acc_t += t_l[q]
            sum_w[q], sum_t[q], circuit_of[q] = acc_w, acc_t, k
            q = following[q]
    index = back.dtype
    return (np.array(roots, dtype=index), np.array(circuit_of, dtype=index),
            _like(sum_w, w_cyc), _like(sum_t, t_cyc))


def _like(values: list[int], model: np.ndarray) -> np.ndarray:
    """``values`` as an array of ``model``'s dtype (object arrays hold Python ints)."""
    if model.dtype != object:
        return np.array(values, dtype=model.dtype)
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def _jump_circuits(back: np.ndarray, w_cyc: np.ndarray, t_cyc: np.ndarray) -> _Walked:
    """Roots, circuit index and weight and token sums from the root, by pointer jumping.

    ``back`` maps each circuit node (a position) to its predecessor on its
    circuit. Returns root positions, per position the index of its circuit
    (among the roots) and the sums of the arcs on the path from its root.
    """
    c = len(back)
    positions = np.arange(c, dtype=back.dtype)
    smallest, around = positions, back
    for _ in range(max(1, c.bit_length())):
        smallest = np.minimum(smallest, smallest[around])
        around = around[around]
    is_root = smallest == positions
    sum_w = np.where(is_root, 0, w_cyc)
    sum_t = np.where(is_root, 0, t_cyc)
    jump = np.where(is_root, positions, back)
    active = np.flatnonzero(~is_root[jump])
    while len(active):
        target = jump[active]
        sum_w[active] += sum_w[target]
        sum_t[active] += sum_t[target]
        jump[active] = jump[target]
        active = active[~is_root[jump[active]]]
    roots = np.flatnonzero(is_root)
    slot = np.zeros(c, dtype=back.dtype)
    slot[roots] = np.arange(len(roots), dtype=back.dtype)
    return roots, slot[smallest], sum_w, sum_t


def _one_circuit(back: np.ndarray, w_cyc: np.ndarray, t_cyc: np.ndarray) -> _Walked | None:
    """:func:`_jump_circuits` when the circuit nodes form one circuit; None otherwise.

    One depth-first search in C from position 0 along the circuit: if it
    visits every position, there is one circuit, rooted at 0, and the sums
    from the root are cumulative sums along the visit. A long critical
    circuit is often the only policy circuit (the ring of 10^5 nodes with
    chords: 24,000 nodes in every iteration; all weights equal: 10^5), and
    this costs a fifth of :func:`_walk_circuits` there (whose search runs
    over twice the nodes and three times the arcs, to enter every circuit).
    When there are several circuits, the search stopped at the end of the
    first one: a waste of at most one pass.
    """
    c = len(back)
    index = back.dtype
    following = np.empty(c, dtype=index)
    following[back] = np.arange(c, dtype=index)
    graph = sp.csr_array((np.ones(c, dtype=np.int8), following, np.arange(c + 1, dtype=index)),
                         shape=(c, c))
    order = depth_first_order(graph, 0, directed=True, return_predecessors=False)
    if len(order) < c:
        return None
    sums = []
    for values in (w_cyc, t_cyc):
        along = values[order]
        along[0] = 0  # the root's own arc closes the circuit
        along = np.cumsum(along)
        out = np.empty(c, dtype=along.dtype)
        out[order] = along
        sums.append(out)
    return order[:1], np.zeros(c, dtype=index), sums[0], sums[1]


def _walk_circuits(back: np.ndarray, w_cyc: np.ndarray, t_cyc: np.ndarray) -> _Walked:
    """:func:`_jump_circuits` by a traversal in C: long circuits cost ``O(c)``.

    A depth-first search that tries every position in increasing order enters
    each circuit at its first position (all smaller ones lie on circuits
    already walked) and walks it in order, so the sums from the root are
    cumulative sums. The positions are offered by a chain of virtual nodes
    ``c + i -> (i, c + i + 1)``, not by one virtual node joined to all: scipy's
    search rescans a node's neighbours from the first each time it comes back
    to it, so one node of c neighbours cost O(c) per circuit, quadratic with
    many short circuits (a skeleton of thousands of groups has thousands). The
    virtual nodes are dropped from the order.
    """
    c = len(back)
    index = back.dtype
    positions = np.arange(c, dtype=index)
    following = np.empty(c, dtype=index)
    following[back] = positions
    neighbours = np.empty(3 * c, dtype=index)
    neighbours[:c] = following
    neighbours[c::2] = positions
    neighbours[c + 1::2] = positions + (c + 1)  # the last one, 2c, has no neighbour
    indptr = np.concatenate([np.arange(c + 1, dtype=index),
                             c + 2 * np.arange(1, c + 1, dtype=index), [3 * c]]).astype(index)
    walk = sp.csr_array((np.ones(3 * c, dtype=np.int8), neighbours, indptr),
                        shape=(2 * c + 1, 2 * c + 1))
    order = depth_first_order(walk, c, directed=True, return_predecessors=False)
    order = order[order < c]
    new = np.empty(c, dtype=bool)
    new[0] = True
    np.not_equal(order[1:], following[order[:-1]], out=new[1:])
    starts = np.flatnonzero(new)
    segment = np.cumsum(new, dtype=index)
    segment -= 1
    sums = []
    for values in (w_cyc, t_cyc):
        along = values[order]
        along[starts] = 0  # a root's own arc closes its circuit
        along = np.cumsum(along)
        along -= along[starts][segment]
        out = np.empty(c, dtype=along.dtype)
        out[order] = along
        sums.append(out)
    circuit_of = np.empty(c, dtype=index)
    circuit_of[order] = segment
    return order[starts], circuit_of, sums[0], sums[1]


def _rank_ratios(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """Dense rank of each fraction num/den (den > 0), as int32.

    Floats sort the fractions (an accelerator only); exact cross-multiplication
    then checks every adjacent pair, and decides equality. If floats misordered
    a pair (ratios closer than float precision, or beyond float range), the
    order is redone by exact comparisons.
    """
    k = len(num)
    if k == 1:
        return np.zeros(1, dtype=np.int32)
    order = np.argsort(float_ratios(num, den), kind="stable")
    step = compare_ratios(num[order[1:]], den[order[1:]], num[order[:-1]], den[order[:-1]])
    if (step < 0).any():
        def cmp(i: int, j: int) -> int:
            return (int(num[i]) * int(den[j]) > int(num[j]) * int(den[i])) - (
                int(num[i]) * int(den[j]) < int(num[j]) * int(den[i]))

        # A loop over the distinct policy circuits, not over nodes; reached only
        # when floats cannot order the ratios.
        order = np.array(sorted(range(k), key=cmp_to_key(cmp)), dtype=np.int64)
        step = compare_ratios(num[order[1:]], den[order[1:]], num[order[:-1]], den[order[:-1]])
    rank = np.empty(k, dtype=np.int32)
    rank[order] = np.r_[0, np.cumsum(step != 0)]
    return rank
