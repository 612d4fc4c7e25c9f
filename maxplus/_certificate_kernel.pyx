"""The arc and policy checks of :func:`maxplus.certificate.verify_cycle_ratio`, compiled.

:func:`arc_checks` is a predicate, not a second checker: it answers whether
every check that ``verify_cycle_ratio`` makes on the arcs and the policy holds,
in one pass over each array, where the numpy path makes some twenty passes
with their temporaries (the compiled Howard kernel solves SPRAND 10^5 in
about as many milliseconds as those passes took). It declines (answers 0)
wherever it is not sure: a node without cycle time, a product that may leave
int64, any check that fails. The numpy path then runs as before and names the
arc, node or circuit where the proof fails, so every message comes from one
place and a wrong "no" here costs only time; a wrong "yes" would be a false
proof, which the tests compare against the numpy path to exclude.

The arithmetic is the numpy path's int64 arithmetic, under the same bound:
``2 * max(|W| |T|, |X| + |w| |T| + |W| |t|, every entry) < 2**62``
(maxima over each array), computed here in 128 bits so that the bound itself
cannot overflow.
"""

from libc.stdint cimport int32_t, int64_t, uint64_t

cdef extern from *:
    """
    typedef unsigned __int128 u128;
    """
    ctypedef unsigned long long u128

cdef u128 SAFE = (<u128>1) << 62

ctypedef fused index_t:  # the arcs' ends as the solver keeps them (no copy to int64)
    int32_t
    int64_t

cdef enum:  # the answers, for the code without the GIL
    _ALL_HOLD = 1
    _ONE_RATIO = 2

ALL_HOLD = _ALL_HOLD
"""Every check holds and the nodes have different cycle times."""
ONE_RATIO = _ONE_RATIO
"""Every check holds and every node has the same cycle time."""


cdef inline uint64_t magnitude(int64_t v) noexcept nogil:
    # |INT64_MIN| = 2**63 fits in uint64; the bound then refuses it.
    return <uint64_t>(-(v + 1)) + 1 if v < 0 else <uint64_t>v


cdef uint64_t largest(const int64_t[::1] a) noexcept nogil:
    cdef uint64_t top = 0, m
    cdef Py_ssize_t k
    for k in range(a.shape[0]):
        m = magnitude(a[k])
        if m > top:
            top = m
    return top


cdef uint64_t euclid(uint64_t a, uint64_t b) noexcept nogil:
    cdef uint64_t r
    while b:
        r = a % b
        a = b
        b = r
    return a


def arc_checks(const index_t[::1] src, const index_t[::1] dst, const int64_t[::1] w,
               const int64_t[::1] t, const int64_t[::1] W, const int64_t[::1] T,
               const int64_t[::1] X, const int64_t[::1] policy):
    """Whether every arc and policy check of the certificate holds.

    Parameters
    ----------
    src, dst : int32 or int64 arrays (both of one type) of one length m
        The arcs' ends (already checked to be nodes).
    w, t : int64 arrays of length m
        The arcs' scaled weights and tokens.
    W, T, X, policy : int64 arrays of one length n
        The certificate's ratio numerators and denominators, potentials and
        policy arcs.

    Returns
    -------
    int
        ``ONE_RATIO`` or ``ALL_HOLD`` when every check holds (one cycle time at
        every node, or not), 0 when one fails or the predicate declines.
    """
    if W.shape[0] == 0 or dst.shape[0] != src.shape[0] or w.shape[0] != src.shape[0] \
            or t.shape[0] != src.shape[0] or T.shape[0] != W.shape[0] \
            or X.shape[0] != W.shape[0] or policy.shape[0] != W.shape[0]:
        return 0
    return checks(src, dst, w, t, W, T, X, policy)


cdef int checks(const index_t[::1] src, const index_t[::1] dst, const int64_t[::1] w,
                const int64_t[::1] t, const int64_t[::1] W, const int64_t[::1] T,
                const int64_t[::1] X, const int64_t[::1] policy) noexcept nogil:
    cdef Py_ssize_t m = src.shape[0], n = W.shape[0], a, k, s, d
    cdef int64_t W0, T0, Ws, Ts, Wd, Td
    cdef uint64_t mW, mT, mX, mw, mt, top
    cdef u128 big_ratio, big_value, big
    cdef bint one_ratio = True
    mW, mT, mX, mw, mt = largest(W), largest(T), largest(X), largest(w), largest(t)
    big_ratio = <u128>mW * mT
    big_value = <u128>mX + <u128>mw * mT + <u128>mW * mt
    top = max(mW, mT, mX, mw, mt)
    big = max(big_ratio, big_value, <u128>top)
    # 2 * big < SAFE, without the doubling: big reaches 2**127 (w, W, X and t all
    # -2**63, T 2**63 - 1), whose double wraps to 0 in 128 bits.
    if big >= SAFE >> 1:
        return 0
    W0, T0 = W[0], T[0]
    for k in range(n):
        # Every node has a cycle time, in lowest terms with a positive denominator.
        if T[k] <= 0 or euclid(magnitude(W[k]), <uint64_t>T[k]) != 1:
            return 0
        if W[k] != W0 or T[k] != T0:
            one_ratio = False
    for a in range(m):
        s, d = src[a], dst[a]
        if s < 0 or s >= n or d < 0 or d >= n:  # checked by the caller; a wrong read is worse
            return 0
        if one_ratio:
            if X[s] + (w[a] * T0 - W0 * t[a]) > X[d]:
                return 0
        else:
            Ws, Ts, Wd, Td = W[s], T[s], W[d], T[d]
            if Ws * Td > Wd * Ts:  # from a larger cycle time to a smaller one
                return 0
            if Ws == Wd and Ts == Td and X[s] + w[a] * Td - Wd * t[a] > X[d]:
                return 0
    for k in range(n):
        a = policy[k]
        if a < 0 or a >= m or dst[a] != k:
            return 0
        s = src[a]
        if one_ratio:
            if X[s] + (w[a] * T0 - W0 * t[a]) != X[k]:
                return 0
        elif W[s] != W[k] or T[s] != T[k] or X[s] + w[a] * T[k] - W[k] * t[a] != X[k]:
            return 0
    return _ONE_RATIO if one_ratio else _ALL_HOLD
