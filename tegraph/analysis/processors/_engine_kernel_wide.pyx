"""The compiled loop of :mod:`._engine_kernel` on 192-bit times, for the parts int64 cannot hold.

A skeleton's times are scaled by the common denominator of all its durations
and periods: a few hundred distinct denominators make it some 2**130 (the group
benchmarks: 6.2e38), far past int64 but well within three 64-bit words. Here a
time is a signed 192-bit integer in two's complement (words ``w0``, ``w1``
unsigned, ``w2`` signed, least significant first); times stay in [0, 2**189]
(-1 marks "none"), so a sum of two does not overflow. The loop and every rule
are those of ``_engine_loop.pxi``, shared with the int64 module.
"""

cdef struct Time:
    unsigned long long w0
    unsigned long long w1
    long long w2


cdef unsigned long long WORD = 0xFFFFFFFFFFFFFFFF
cdef object LIMIT_INT = 2 ** 189


cdef inline bint t_lt(Time a, Time b) noexcept nogil:
    if a.w2 != b.w2:
        return a.w2 < b.w2
    if a.w1 != b.w1:
        return a.w1 < b.w1
    return a.w0 < b.w0


cdef inline bint t_le(Time a, Time b) noexcept nogil:
    return not t_lt(b, a)


cdef inline bint t_eq(Time a, Time b) noexcept nogil:
    return a.w0 == b.w0 and a.w1 == b.w1 and a.w2 == b.w2


cdef inline bint t_is_zero(Time a) noexcept nogil:
    return a.w0 == 0 and a.w1 == 0 and a.w2 == 0


cdef inline Time t_add(Time a, Time b) noexcept nogil:
    cdef Time r
    cdef unsigned long long carry
    r.w0 = a.w0 + b.w0
    carry = r.w0 < a.w0
    r.w1 = a.w1 + b.w1 + carry
    carry = (r.w1 < a.w1) | ((r.w1 == a.w1) & carry)
    r.w2 = <long long>(<unsigned long long>a.w2 + <unsigned long long>b.w2 + carry)
    return r


cdef inline Time t_sub(Time a, Time b) noexcept nogil:
    cdef Time r
    cdef unsigned long long borrow
    r.w0 = a.w0 - b.w0
    borrow = a.w0 < b.w0
    r.w1 = a.w1 - b.w1 - borrow
    borrow = (a.w1 < b.w1) | ((a.w1 == b.w1) & borrow)
    r.w2 = <long long>(<unsigned long long>a.w2 - <unsigned long long>b.w2 - borrow)
    return r


cdef inline Time t_small(long long v) noexcept nogil:
    cdef Time r
    r.w0 = <unsigned long long>v
    r.w1 = WORD if v < 0 else 0
    r.w2 = -1 if v < 0 else 0
    return r


cdef Time LIMIT = t_small(0)
LIMIT.w2 = 1 << 61  # 2**189


cdef inline bint t_fits(Time a, Time b) noexcept nogil:
    return t_le(b, t_sub(LIMIT, a))


cdef inline Time t_of(object x) except *:
    cdef Time r
    if -0x8000000000000000 <= x <= 0x7FFFFFFFFFFFFFFF:
        return t_small(x)
    r.w0 = x & WORD
    r.w1 = (x >> 64) & WORD
    r.w2 = x >> 128
    return r


cdef inline object t_py(Time a):
    if a.w2 == 0 and a.w1 == 0:
        return a.w0
    if a.w2 == -1 and a.w1 == WORD and a.w0 >= 0x8000000000000000:
        return <long long>a.w0
    return (<object>a.w2 << 128) + (<object>a.w1 << 64) + a.w0


include "_engine_loop.pxi"
