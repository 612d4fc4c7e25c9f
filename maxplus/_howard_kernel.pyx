# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
"""Howard's policy iteration in C: the iteration of the numpy kernel, compiled.

:func:`howard` runs, step for step, the iteration that
:func:`maxplus.policy_iteration.howard_arrays` runs on numpy arrays: the same
first policy (each node's first heaviest in-arc), the same value
determination (a policy circuit is rooted at its smallest node, whose
potential is kept when its ratio is), the same improvement (a ratio step to
the first in-arc of largest strictly better ratio, passed downstream with the
numpy sweep's order of visits and its "last write wins"; else a bias step to
the first in-arc of largest value) and the same candidate nodes after a bias
step. It returns the same ratios, potentials, policy and iteration count; the
property tests of ``tests/maxplus/test_howard_kernel.py`` check that equality
against the numpy kernel on random graphs.

It values again only the nodes whose policy walk passes a switched node (the
others reach the same circuit by the same path, and that circuit keeps its
ratio and its root's potential), and after a bias step looks only at the
nodes whose value changed and their successors: a late iteration costs what
it changes, not ``O(n + m)``.

Arithmetic is exact: weights, tokens, ratios and potentials are int64, every
product and sum of them is formed in 128 bits, and a potential that would
reach ``2**62`` in absolute value stops the run (:func:`howard` returns None
and the caller runs the numpy kernel, which carries Python ints). The run
needs ``2 * n * max(|w|, t) < 2**62`` (checked while the arcs are sorted;
None otherwise), so circuit sums fit int64 and a cross-multiplication of two
ratios fits 128 bits. A policy seen before (a 128-bit digest of it) also
returns None: by the termination proof of ``howard_arrays`` it is a bug,
which the numpy kernel then reports.
"""

from libc.stdint cimport int32_t, int64_t, uint64_t
from libc.stdlib cimport qsort

import numpy as np

cdef extern from *:
    """
    typedef __int128 i128;
    #define PREFETCH(address) __builtin_prefetch(address)
    """
    ctypedef long long i128
    void PREFETCH(const void *address) noexcept nogil

cdef int64_t SAFE = (<int64_t>1) << 62

cdef int PREFETCH_ARCS = 16

cdef int AFFECTED_SHARE = 4
"""Once more than one node in this many lies below a switch, every node is valued again."""

ctypedef struct Arc:
    # An in-arc, in the order by head: what the improvement reads, in one place.
    int64_t w
    int64_t t
    int32_t src
    int32_t arc  # its index in the caller's arrays

ctypedef struct Val:
    # A node's ratio W/T (reduced) and potential X: read together for every arc's tail.
    int64_t W
    int64_t T
    int64_t X

ARC = np.dtype([("w", np.int64), ("t", np.int64), ("src", np.int32), ("arc", np.int32)])
VAL = np.dtype([("W", np.int64), ("T", np.int64), ("X", np.int64)])

ctypedef struct Link:
    # Weight and tokens of a node's policy arc, by node: the walks read these, not the arcs.
    int64_t w
    int64_t t

ctypedef struct Raised:
    int64_t W
    int64_t T
    int32_t order
    int32_t node


cdef int _by_ratio_down(const void *a, const void *b) noexcept nogil:
    """Larger ratio first, then the earlier entry (a stable sort, as numpy's argsort)."""
    cdef const Raised *x = <const Raised *>a
    cdef const Raised *y = <const Raised *>b
    cdef i128 lhs = <i128>x.W * y.T
    cdef i128 rhs = <i128>y.W * x.T
    if lhs > rhs:
        return -1
    if lhs < rhs:
        return 1
    return (x.order > y.order) - (x.order < y.order)


cdef int _by_value(const void *a, const void *b) noexcept nogil:
    cdef int32_t x = (<const int32_t *>a)[0]
    cdef int32_t y = (<const int32_t *>b)[0]
    return (x > y) - (x < y)


cdef inline uint64_t _mix(uint64_t z) noexcept nogil:
    """splitmix64's finaliser: a bijection of 64 bits that spreads every input bit."""
    z = (z ^ (z >> 30)) * <uint64_t>0xBF58476D1CE4E5B9ULL
    z = (z ^ (z >> 27)) * <uint64_t>0x94D049BB133111EBULL
    return z ^ (z >> 31)


cdef inline int64_t _gcd(int64_t a, int64_t b) noexcept nogil:
    cdef int64_t r
    if a < 0:
        a = -a
    while b:
        r = a % b
        a = b
        b = r
    return a


cdef inline bint _below(int64_t W1, int64_t T1, int64_t W2, int64_t T2) noexcept nogil:
    """W1/T1 < W2/T2 (T1, T2 > 0)."""
    return <i128>W1 * T2 < <i128>W2 * T1


cdef inline int32_t[::1] _cut(int32_t[::1] block, Py_ssize_t *at, Py_ssize_t size,
                              Py_ssize_t room):
    """``size`` slots of ``block`` from ``at[0]``, which then moves on by ``room``."""
    cdef int32_t[::1] piece = block[at[0]:at[0] + size]
    at[0] += room
    return piece


cdef class _Run:
    """The graph (in-arcs by head, out-arcs by tail), the policy, its values and scratch."""

    cdef int32_t n, m
    cdef int32_t sweep_few, scan_min_share
    # In-arcs sorted stably by head, and where each head's start.
    cdef int32_t[::1] in_start
    cdef Arc[::1] arcs
    # The same positions grouped by tail (increasing within a tail), and their heads;
    # built when first needed (a sweep, candidates after a bias step).
    cdef int32_t[::1] out_start, out_pos, out_dst
    cdef bint has_out
    cdef int32_t[::1] pol
    # The tail of each node's policy arc, kept with pol: the walks chase this small array.
    cdef int32_t[::1] pred
    cdef bint every_next
    cdef Link[::1] link
    cdef bint children_ok  # the policy children lists match the policy
    cdef Val[::1] val
    # The numpy arrays under ``arcs``, ``val`` and ``pol``, read back by solve(): np.asarray
    # of a memoryview of structs parses its buffer format in Python, dearer than a small solve.
    cdef object arcs_array, val_array, pol_array
    cdef bint has_prev, fits
    # Policy children as doubly linked lists: first child, next and previous sibling.
    cdef int32_t[::1] child, sib_next, sib_prev
    cdef signed char[::1] state
    cdef int32_t[::1] path, stamp, mark, done, saved_at
    cdef int32_t stamp_now, mark_now, done_now, saved_now
    # Lists, each with its length: changed nodes, candidates, affected nodes.
    cdef int32_t[::1] changed, cand, affected, level, nxt, kept, kept_head, rec_node, rec_old
    cdef int32_t n_changed, n_cand, n_affected, n_rec
    cdef int64_t[::1] save_W, save_T
    cdef int32_t[::1] save_node
    cdef int32_t n_save
    cdef int32_t[::1] bias_node, bias_pos
    cdef uint64_t h1, h2

    def __init__(self, src, dst, w, t, int n, int sweep_few, int scan_min_share):
        cdef int32_t m = len(src)
        self.n, self.m = n, m
        self.sweep_few, self.scan_min_share = sweep_few, scan_min_share
        i32 = np.int32
        cdef const int32_t[::1] s = np.ascontiguousarray(src, dtype=i32)
        cdef const int32_t[::1] d = np.ascontiguousarray(dst, dtype=i32)
        cdef const int64_t[::1] ww = np.ascontiguousarray(w, dtype=np.int64)
        cdef const int64_t[::1] tt = np.ascontiguousarray(t, dtype=np.int64)
        # Every int32 array in one block, cut into slices: an array and its memoryview
        # apiece cost more than a small solve. 17 slices of n + 1 slots (n used by some),
        # 2 n + 1 saved nodes, 2 of m + 1 arcs, 4 counters of n.
        cdef Py_ssize_t at = 0, N = n + 1, M = m + 1
        cdef Py_ssize_t total = 17 * N + (2 * n + 1) + 2 * M + 4 * n
        block_array = np.empty(total, dtype=i32)
        cdef int32_t[::1] block = block_array
        cdef int32_t[::1] fill, counters
        self.in_start = _cut(block, &at, N, N)
        fill = _cut(block, &at, N, N)
        self.pol_array = block_array[at:at + n]
        self.pol = _cut(block, &at, n, N)
        self.pred = _cut(block, &at, n, N)
        self.child = _cut(block, &at, n, N)
        self.sib_next = _cut(block, &at, n, N)
        self.sib_prev = _cut(block, &at, n, N)
        self.path = _cut(block, &at, N, N)
        self.changed = _cut(block, &at, N, N)
        self.cand = _cut(block, &at, N, N)
        self.affected = _cut(block, &at, N, N)
        self.level = _cut(block, &at, N, N)
        self.nxt = _cut(block, &at, N, N)
        self.rec_node = _cut(block, &at, N, N)
        self.rec_old = _cut(block, &at, N, N)
        # A node is saved at most twice per step: on the frontier, then raised by the sweep.
        self.save_node = _cut(block, &at, 2 * n + 1, 2 * n + 1)
        self.bias_node = _cut(block, &at, N, N)
        self.bias_pos = _cut(block, &at, N, N)
        self.kept = _cut(block, &at, M, M)
        self.kept_head = _cut(block, &at, M, M)
        self.stamp = _cut(block, &at, n, n)
        self.mark = _cut(block, &at, n, n)
        self.done = _cut(block, &at, n, n)
        self.saved_at = _cut(block, &at, n, n)
        if at != total:
            raise AssertionError("internal error: the kernel's arrays do not fill their block")
        counters = block[total - 4 * n:]
        cdef int64_t[::1] saves = np.empty(2 * (2 * n + 1), dtype=np.int64)
        self.save_W = saves[:2 * n + 1]
        self.save_T = saves[2 * n + 1:]
        self.arcs_array = np.empty(m, dtype=ARC)
        self.arcs = self.arcs_array
        cdef int32_t a, p, v
        with nogil:
            self.in_start[:] = 0
            self.child[:] = -1
            self.sib_next[:] = -1
            self.sib_prev[:] = -1
            counters[:] = 0
        # The bound 2 n max(|w|, t) < 2**62, checked in the same pass (a number beyond
        # it makes the whole run the numpy kernel's, in Python ints from the start).
        cdef int64_t limit = (SAFE - 1) // (2 * <int64_t>n), w_a
        cdef bint fits = True
        cdef Arc *arc
        with nogil:
            # A counting sort, stable: by head, the numpy kernel's order.
            for a in range(m):
                self.in_start[d[a] + 1] += 1
            for v in range(n):
                self.in_start[v + 1] += self.in_start[v]
            for v in range(n + 1):
                fill[v] = self.in_start[v]
            for a in range(m):
                p = fill[d[a]]
                fill[d[a]] = p + 1
                arc = &self.arcs[p]
                w_a = ww[a]
                if w_a > limit or w_a < -limit or tt[a] > limit or tt[a] < 0:
                    fits = False
                arc.w, arc.t, arc.src, arc.arc = w_a, tt[a], s[a], a
        self.fits = fits
        self.has_out = False
        self.link = np.empty(n, dtype=[("w", np.int64), ("t", np.int64)])
        self.val_array = np.zeros(n, dtype=VAL)
        self.val = self.val_array
        self.state = np.zeros(n, dtype=np.int8)
        self.stamp_now = self.mark_now = self.done_now = self.saved_now = 0
        self.has_prev = False
        self.children_ok = False

    cdef void _ensure_out(self) noexcept nogil:
        """Build the out-arcs on first use (:meth:`_build_out`)."""
        if not self.has_out:
            with gil:
                self._build_out()

    cdef void _build_out(self):
        """The out-arcs: the positions of the in-arcs grouped by tail (a stable counting sort)."""
        cdef int32_t n = self.n, m = self.m, p, q, v, h
        self.out_start = np.zeros(n + 1, dtype=np.int32)
        self.out_pos = np.empty(m, dtype=np.int32)
        self.out_dst = np.empty(m, dtype=np.int32)
        cdef int32_t[::1] fill = np.empty(n + 1, dtype=np.int32)
        with nogil:
            for p in range(m):
                self.out_start[self.arcs[p].src + 1] += 1
            for v in range(n):
                self.out_start[v + 1] += self.out_start[v]
            for v in range(n + 1):
                fill[v] = self.out_start[v]
            for h in range(n):
                for p in range(self.in_start[h], self.in_start[h + 1]):
                    q = fill[self.arcs[p].src]
                    fill[self.arcs[p].src] = q + 1
                    self.out_pos[q], self.out_dst[q] = p, h
        self.has_out = True

    # ------------------------------------------------------------------ policy bookkeeping

    cdef void _first_policy(self) noexcept nogil:
        """Each node's first heaviest in-arc; the policy children and the digest."""
        cdef int32_t v, p, best
        self.h1 = self.h2 = 0
        for v in range(self.n):
            best = self.in_start[v]
            for p in range(self.in_start[v], self.in_start[v + 1]):
                if self.arcs[p].w > self.arcs[best].w:
                    best = p
            self.pol[v] = best
            self.pred[v] = self.arcs[best].src
            self.link[v].w, self.link[v].t = self.arcs[best].w, self.arcs[best].t
            self._digest(v, best, 1)

    cdef inline void _digest(self, int32_t v, int32_t p, int sign) noexcept nogil:
        """Add (sign 1) or remove (-1) the term of ``pol[v] == p`` in the two linear digests."""
        cdef uint64_t key = (<uint64_t>v << 32) | <uint64_t>p
        cdef uint64_t a = _mix(key ^ <uint64_t>0x6D617870ULL)
        cdef uint64_t b = _mix(key + <uint64_t>0x9E3779B97F4A7C15ULL)
        if sign > 0:
            self.h1 += a
            self.h2 += b
        else:
            self.h1 -= a
            self.h2 -= b

    cdef inline void _adopt(self, int32_t v) noexcept nogil:
        """Link ``v`` under the tail of its policy arc."""
        cdef int32_t u = self.pred[v]
        cdef int32_t first = self.child[u]
        self.sib_prev[v] = -1
        self.sib_next[v] = first
        if first >= 0:
            self.sib_prev[first] = v
        self.child[u] = v

    cdef inline void _orphan(self, int32_t v, int32_t old_pos) noexcept nogil:
        """Unlink ``v`` from the tail of its former policy arc ``old_pos``."""
        cdef int32_t u = self.arcs[old_pos].src
        cdef int32_t prv = self.sib_prev[v], nx = self.sib_next[v]
        if prv >= 0:
            self.sib_next[prv] = nx
        else:
            self.child[u] = nx
        if nx >= 0:
            self.sib_prev[nx] = prv

    cdef inline void _switch(self, int32_t v, int32_t p) noexcept nogil:
        """``pol[v] = p``, remembering the policy ``v`` had before this step."""
        if self.saved_at[v] != self.saved_now:
            self.saved_at[v] = self.saved_now
            self.rec_node[self.n_rec] = v
            self.rec_old[self.n_rec] = self.pol[v]
            self.n_rec += 1
        self.pol[v] = p
        self.pred[v] = self.arcs[p].src
        self.link[v].w, self.link[v].t = self.arcs[p].w, self.arcs[p].t

    cdef void _settle(self) noexcept nogil:
        """After a step: relink switched nodes, update the digest, list the affected nodes.

        The affected nodes are the switched ones and everything below them in
        the new policy's trees: the nodes whose policy walk passes a switch.
        Once they are more than a share of all nodes (:data:`AFFECTED_SHARE`),
        the search stops and the next determination values every node: a walk
        of all nodes costs less than a search of most of them and then the walk.
        """
        cdef int32_t k, v, old, c, head = 0
        self.stamp_now += 1
        self.n_affected = 0
        self.every_next = False
        for k in range(self.n_rec):
            v, old = self.rec_node[k], self.rec_old[k]
            if self.pol[v] == old:
                continue
            self._digest(v, old, -1)
            self._digest(v, self.pol[v], 1)
            self.stamp[v] = self.stamp_now  # rec_node lists each node once
            self.affected[self.n_affected] = v
            self.n_affected += 1
        if <int64_t>self.n_affected * AFFECTED_SHARE > self.n:
            # Lists of children are relinked (or rebuilt) only when a search needs them.
            self.children_ok = False
            self.every_next = True
            return
        if self.children_ok:
            for k in range(self.n_rec):
                v, old = self.rec_node[k], self.rec_old[k]
                if self.pol[v] != old:
                    self._orphan(v, old)
                    self._adopt(v)
        else:
            for v in range(self.n):
                self.child[v] = -1
            for v in range(self.n):
                self._adopt(v)
            self.children_ok = True
        while head < self.n_affected:  # grows while it is walked
            if <int64_t>self.n_affected * AFFECTED_SHARE > self.n:
                self.every_next = True
                return
            c = self.child[self.affected[head]]
            head += 1
            while c >= 0:
                if self.stamp[c] != self.stamp_now:
                    self.stamp[c] = self.stamp_now
                    self.affected[self.n_affected] = c
                    self.n_affected += 1
                c = self.sib_next[c]

    # ------------------------------------------------------------------ value determination

    cdef inline void _set(self, int32_t x, int64_t W, int64_t T, int64_t X) noexcept nogil:
        cdef Val *old = &self.val[x]
        if self.has_prev and (old.W != W or old.T != T or old.X != X):
            self.changed[self.n_changed] = x
            self.n_changed += 1
        old.W, old.T, old.X = W, T, X
        self.state[x] = 2

    cdef int _values(self, bint every) noexcept nogil:
        """Ratio and potential of every node (or of the affected ones); -1 past 2**62."""
        cdef int32_t k, count, v, u, plen, start, i, x, p, r
        cdef int64_t Wc, Tc, g, x_root
        cdef i128 acc
        count = self.n if every else self.n_affected
        for k in range(count):
            self.state[k if every else self.affected[k]] = 0
        self.n_changed = 0
        for k in range(count):
            v = k if every else self.affected[k]
            if self.state[v]:
                continue
            plen = 0
            u = v
            while self.state[u] == 0:  # backwards along the policy
                self.state[u] = 1
                self.path[plen] = u
                plen += 1
                u = self.pred[u]
            if self.state[u] == 1:
                # The walk closed a circuit: path[start:], backwards from u.
                start = plen - 1
                while self.path[start] != u:
                    start -= 1
                Wc = Tc = 0
                r = start
                for i in range(start, plen):
                    x = self.path[i]
                    Wc += self.link[x].w
                    Tc += self.link[x].t
                    if x < self.path[r]:
                        r = i
                if Tc <= 0:
                    return -1  # a token-free circuit: refused by the caller, never here
                g = _gcd(Wc, Tc)
                Wc, Tc = Wc // g, Tc // g
                x = self.path[r]  # the root: its smallest node
                # Its potential is kept when its ratio is (Cochet-Terrasson et al.).
                x_root = (self.val[x].X if self.has_prev and self.val[x].W == Wc
                          and self.val[x].T == Tc else 0)
                self._set(x, Wc, Tc, x_root)
                acc = x_root
                # Forwards from the root: positions r-1 down to start, then plen-1 down to r+1.
                i = r
                while True:
                    i = i - 1 if i > start else plen - 1
                    if i == r:
                        break
                    x = self.path[i]
                    acc += <i128>self.link[x].w * Tc - <i128>Wc * self.link[x].t
                    if acc >= SAFE or acc <= -SAFE:
                        return -1
                    self._set(x, Wc, Tc, <int64_t>acc)
                plen = start
            # The rest of the walk reaches u's circuit: its ratio, potentials tight from u's.
            Wc, Tc = self.val[u].W, self.val[u].T
            acc = self.val[u].X
            for i in range(plen - 1, -1, -1):
                x = self.path[i]
                acc += <i128>self.link[x].w * Tc - <i128>Wc * self.link[x].t
                if acc >= SAFE or acc <= -SAFE:
                    return -1
                self._set(x, Wc, Tc, <int64_t>acc)
        self.has_prev = True
        return 0

    cdef void _touched(self) noexcept nogil:
        """Candidates after a bias step: changed nodes and the heads of their out-arcs.

        ``n_cand = -1`` for all nodes (when many changed), as the numpy kernel's
        candidate arcs (``changed[src] | changed[dst]``).
        """
        cdef int32_t k, u, q, v
        if 8 * <int64_t>self.n_changed >= self.n:
            self.n_cand = -1
            return
        self._ensure_out()
        self.mark_now += 1
        self.n_cand = 0
        for k in range(self.n_changed):
            u = self.changed[k]
            if self.mark[u] != self.mark_now:
                self.mark[u] = self.mark_now
                self.cand[self.n_cand] = u
                self.n_cand += 1
            for q in range(self.out_start[u], self.out_start[u + 1]):
                v = self.out_dst[q]
                if self.mark[v] != self.mark_now:
                    self.mark[v] = self.mark_now
                    self.cand[self.n_cand] = v
                    self.n_cand += 1
        if 16 * <int64_t>self.n_cand > self.n:  # sorted by a pass over the nodes
            self.n_cand = 0
            for v in range(self.n):
                if self.mark[v] == self.mark_now:
                    self.cand[self.n_cand] = v
                    self.n_cand += 1
        else:
            qsort(&self.cand[0], self.n_cand, sizeof(int32_t), _by_value)

    # ------------------------------------------------------------------ policy improvement

    cdef int _improve(self, bint every, Raised *front) noexcept nogil:
        """One improvement at the candidates (or every node): 0 none, 1 ratio, 2 bias."""
        cdef int32_t count = self.n if every else self.n_cand
        cdef int32_t k, v, p, better, bias, n_front = 0, n_bias = 0
        cdef int64_t Wv, Tv, bW, bT, Ws, Ts
        cdef Arc *arc
        cdef Val *tail
        cdef i128 best, value
        for k in range(count):
            v = k if every else self.cand[k]
            Wv, Tv = self.val[v].W, self.val[v].T
            bW, bT = Wv, Tv
            best = self.val[v].X
            better = bias = -1
            for p in range(self.in_start[v], self.in_start[v + 1]):
                if p + PREFETCH_ARCS < self.m:
                    # The tails' values are scattered: ask for one a few arcs ahead.
                    PREFETCH(&self.val[self.arcs[p + PREFETCH_ARCS].src])
                arc = &self.arcs[p]
                tail = &self.val[arc.src]
                Ws, Ts = tail.W, tail.T
                if Ws == Wv and Ts == Tv:  # reduced fractions: the same ratio
                    if n_front == 0 and better < 0:  # a bias step is still possible
                        value = <i128>tail.X + <i128>arc.w * Tv - <i128>Wv * arc.t
                        if value > best:
                            best, bias = value, p
                elif <i128>Ws * bT > <i128>bW * Ts:  # the first arc of largest ratio
                    better, bW, bT = p, Ws, Ts
            if better >= 0:
                front[n_front].W, front[n_front].T = bW, bT
                front[n_front].order, front[n_front].node = n_front, v
                self.bias_pos[n_front] = better
                n_front += 1
            elif n_front == 0 and bias >= 0:
                self.bias_node[n_bias], self.bias_pos[n_bias] = v, bias
                n_bias += 1
        self.saved_now += 1
        self.n_rec = 0
        if n_front:
            self._ratio_step(front, n_front)
            return 1
        for k in range(n_bias):
            self._switch(self.bias_node[k], self.bias_pos[k])
        return 2 if n_bias else 0

    cdef inline void _raise_to(self, int32_t v, int64_t W, int64_t T) noexcept nogil:
        """Give ``v`` a ratio for the sweep, remembering its value (restored after)."""
        self.save_node[self.n_save] = v
        self.save_W[self.n_save], self.save_T[self.n_save] = self.val[v].W, self.val[v].T
        self.n_save += 1
        self.val[v].W, self.val[v].T = W, T

    cdef void _ratio_step(self, Raised *front, int32_t n_front) noexcept nogil:
        """Switch the frontier to its better arcs and pass the ratios downstream.

        numpy's ``_sweep_downstream``: the frontier by decreasing ratio (stable),
        in groups of equal ratio; from each, breadth first, a node switches to
        an out-arc of the round whose head has a smaller ratio, the last such
        arc visited winning; the arcs of a round are visited by tail in the
        round's order, or, for a round of many nodes, by head (the numpy
        sweep's scan of all arcs); the next round is the raised nodes in the
        order of their winning arcs.
        """
        cdef int32_t k, i, j, v, n_level, n_next, n_kept, q, p, h, u
        cdef int64_t topW, topT
        self._ensure_out()
        self.n_save = 0
        for k in range(n_front):  # all chosen first, then written (ratios read before)
            self._switch(front[k].node, self.bias_pos[k])
        for k in range(n_front):
            self._raise_to(front[k].node, front[k].W, front[k].T)
        qsort(front, n_front, sizeof(Raised), _by_ratio_down)
        self.done_now += 1
        i = 0
        while i < n_front:
            j = i
            n_level = 0
            while j < n_front and front[j].W == front[i].W and front[j].T == front[i].T:
                v = front[j].node
                if self.done[v] != self.done_now:
                    self.level[n_level] = v
                    n_level += 1
                j += 1
            i = j
            if n_level == 0:
                continue
            topW, topT = self.val[self.level[0]].W, self.val[self.level[0]].T
            for k in range(n_level):
                self.done[self.level[k]] = self.done_now
            while n_level:
                n_kept = 0
                if (n_level > self.sweep_few
                        and <int64_t>n_level * self.scan_min_share > self.n):
                    self.mark_now += 1
                    for k in range(n_level):
                        self.mark[self.level[k]] = self.mark_now
                    for h in range(self.n):  # the arcs by head
                        if not _below(self.val[h].W, self.val[h].T, topW, topT):
                            continue
                        for p in range(self.in_start[h], self.in_start[h + 1]):
                            if self.mark[self.arcs[p].src] == self.mark_now:
                                self.kept[n_kept], self.kept_head[n_kept] = p, h
                                n_kept += 1
                else:
                    for k in range(n_level):
                        u = self.level[k]
                        for q in range(self.out_start[u], self.out_start[u + 1]):
                            h = self.out_dst[q]
                            if _below(self.val[h].W, self.val[h].T, topW, topT):
                                self.kept[n_kept], self.kept_head[n_kept] = self.out_pos[q], h
                                n_kept += 1
                for k in range(n_kept):
                    self._switch(self.kept_head[k], self.kept[k])
                n_next = 0
                for k in range(n_kept):
                    p, h = self.kept[k], self.kept_head[k]
                    if self.pol[h] == p:
                        self.nxt[n_next] = h
                        n_next += 1
                for k in range(n_next):
                    h = self.nxt[k]
                    self._raise_to(h, topW, topT)
                    self.done[h] = self.done_now
                    self.level[k] = h
                n_level = n_next
        for k in range(self.n_save - 1, -1, -1):  # the values of this determination again
            v = self.save_node[k]
            self.val[v].W, self.val[v].T = self.save_W[k], self.save_T[k]

    # ------------------------------------------------------------------ the iteration

    def solve(self):
        """Run the iteration; ``(W, T, X, policy, iterations)`` or None (see the module)."""
        cdef int step, iterations = 0
        cdef bint check_all = True, every = True
        if not self.fits:
            return None
        front_array = np.empty(max(1, self.n) * sizeof(Raised), dtype=np.uint8)
        cdef unsigned char[::1] front_bytes = front_array
        cdef Raised *front = <Raised *>&front_bytes[0]
        seen = set()
        with nogil:
            self._first_policy()
        seen.add((self.h1, self.h2))
        while True:
            with nogil:
                if self._values(every) < 0:
                    step = -1
                else:
                    iterations += 1
                    self.n_cand = -1
                    if not check_all:
                        self._touched()
                    step = self._improve(self.n_cand < 0, front)
                    if step == 0 and self.n_cand >= 0:
                        step = self._improve(True, front)  # the last word checks every node
                    if step > 0:
                        self._settle()
            if step < 0:
                return None
            if step == 0:
                values = self.val_array
                arcs = self.arcs_array["arc"]
                return (values["W"].copy(), values["T"].copy(), values["X"].copy(),
                        arcs[self.pol_array].astype(np.int64), iterations)
            key = (self.h1, self.h2)
            if key in seen:  # impossible by the termination proof: a bug
                return None
            seen.add(key)
            # After a ratio step, gains were not examined: check every node next.
            check_all = step == 1
            every = self.every_next


def howard(src, dst, w, t, int n, int sweep_few, int scan_min_share):
    """Howard's iteration in C on a graph whose every node has an in-arc.

    Parameters
    ----------
    src, dst : numpy.ndarray of int
        Arcs (fewer than ``2**31`` arcs and nodes).
    w, t : numpy.ndarray of int64
        Weights and tokens (no token-free circuit); the run needs
        ``2 * n * max(|w|, t) < 2**62`` (checked: None otherwise).
    n : int
        Number of nodes.
    sweep_few, scan_min_share : int
        The numpy sweep's thresholds (``maxplus.policy_iteration.SWEEP_FEW`` and
        ``SCAN_MIN_SHARE``), which decide the order of its visits.

    Returns
    -------
    tuple or None
        ``(W, T, X, policy, iterations)`` as
        :class:`maxplus.policy_iteration.HowardSolution`, or None where a
        number is past the bound, a potential would reach ``2**62`` or a
        policy repeated: run the numpy kernel.
    """
    if n == 0:
        return None
    return _Run(src, dst, w, t, n, sweep_few, scan_min_share).solve()


ctypedef fused index_t:
    int32_t
    int64_t


cdef inline int64_t _step(const int64_t[::1] policy, const index_t[::1] src,
                          int64_t node) noexcept nogil:
    """The tail of ``node``'s policy arc; -1 for a node without one."""
    cdef int64_t arc = policy[node]
    return src[arc] if arc >= 0 else -1


def policy_circuit(int64_t start, const int64_t[::1] policy, const index_t[::1] src):
    """Arcs of the policy circuit reached backwards from ``start``, in forward order.

    What :func:`maxplus.cycle_ratio._policy_circuit` computes, in ``O(walk)``
    time and ``O(1)`` memory (Brent's cycle detection: no mark per node, so a
    call per group of a large graph costs its walk only). None when the walk
    meets a node without a policy arc (the caller's own walk then decides).
    """
    cdef int64_t power = 1, lam = 1, mu = 0, k, tortoise = start, hare
    with nogil:
        hare = _step(policy, src, start)
        while hare != tortoise:  # Brent: the circuit's length lam
            if hare < 0:
                break
            if power == lam:
                tortoise, power, lam = hare, power * 2, 0
            hare = _step(policy, src, hare)
            lam += 1
        if hare >= 0:
            tortoise = hare = start
            for k in range(lam):
                hare = _step(policy, src, hare)
            while tortoise != hare:  # the circuit's first node on the walk
                tortoise = _step(policy, src, tortoise)
                hare = _step(policy, src, hare)
                mu += 1
    if hare < 0:
        return None
    out = np.empty(lam, dtype=np.int64)
    cdef int64_t[::1] arcs = out
    with nogil:
        for k in range(lam - 1, -1, -1):  # the circuit backwards from its entry node
            arcs[k] = policy[tortoise]
            tortoise = _step(policy, src, tortoise)
    return out


def off_circuits(const index_t[::1] src, const index_t[::1] dst, int64_t n, tokens=None):
    """Per node, whether no circuit reaches it (Kahn's algorithm); with ``tokens``, no
    circuit of token-free arcs.

    Repeatedly drops a node without in-arc (among the arcs considered): a node
    drops exactly when every backward walk from it ends. What
    :func:`maxplus.cycle_ratio._nodes_reached_by_circuits` (all arcs) and the
    zero-token refusal (token-free arcs) find with scipy's strong components,
    in one pass without a sparse matrix: their fixed cost dominates a small
    solve. Returns a boolean array and how many nodes dropped.
    """
    cdef int64_t m = src.shape[0], a, k, u, v, head = 0, tail = 0
    cdef const int64_t[::1] tt
    cdef bint all_arcs = tokens is None
    if not all_arcs:
        tt = tokens
    indegree_array = np.zeros(n + 1, dtype=np.int64)
    start_array = np.zeros(n + 2, dtype=np.int64)
    out_array = np.empty(max(m, 1), dtype=np.int64)
    dropped_array = np.zeros(n, dtype=np.uint8)
    queue_array = np.empty(max(n, 1), dtype=np.int64)
    cdef int64_t[::1] indegree = indegree_array, start = start_array, out = out_array
    cdef int64_t[::1] queue = queue_array
    cdef unsigned char[::1] dropped = dropped_array
    with nogil:
        for a in range(m):  # out-arcs by tail (a counting sort), in-degrees
            if all_arcs or tt[a] == 0:
                start[src[a] + 2] += 1
                indegree[dst[a]] += 1
        for k in range(2, n + 2):
            start[k] += start[k - 1]
        for a in range(m):
            if all_arcs or tt[a] == 0:
                out[start[src[a] + 1]] = dst[a]
                start[src[a] + 1] += 1
        for v in range(n):
            if indegree[v] == 0:
                queue[tail] = v
                tail += 1
        while head < tail:  # grows while it is walked
            u = queue[head]
            head += 1
            dropped[u] = True
            for k in range(start[u], start[u + 1]):
                v = out[k]
                indegree[v] -= 1
                if indegree[v] == 0:
                    queue[tail] = v
                    tail += 1
    return dropped_array.view(np.bool_), tail


def first_largest_ratio(const int64_t[::1] num, const int64_t[::1] den):
    """Index of the first largest ``num/den`` (all ``den > 0``), compared exactly in 128 bits.

    :func:`maxplus._arrays.argmax_ratio` on int64 arrays, without its float
    shortlist and tournament (a dozen numpy calls, dearer than a small solve).
    """
    cdef int64_t k, best = 0, n = num.shape[0]
    with nogil:
        for k in range(1, n):
            if <i128>num[k] * den[best] > <i128>num[best] * den[k]:
                best = k
    return best
