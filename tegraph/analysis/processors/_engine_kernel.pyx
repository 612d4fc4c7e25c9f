"""The hot loop of :class:`~tegraph.analysis.processors._engine._Part`, compiled, on int64 times.

The rules, the order of the firings and every figure are those of ``_Part.run``
(read it first): the same loop written on C arrays (``_engine_loop.pxi``, shared
with :mod:`._engine_kernel_wide`), here for parts whose times (initial tokens,
holds, durations) are Python ints in [0, 2**62]. Every time the loop makes is a
sum ``a + b`` of two such times (a token's hold or a job's remaining work after
``now``), checked against the bound before it is made: past it the run stops
and says so (:meth:`Kernel.run` returns None), and the caller simulates the part
again with more room. Differences are only taken of a later time from an earlier
one (or of a time from 2**62), so nothing can overflow.

The objects of the result (jobs, intervals, the tick log, the overruns) are
made here as the Python loop makes them, sharing one int object per instant.
The states are compared in Python (``_engine._compare``) through the export
methods of :class:`Kernel`, at the instants the Python loop compares them.
"""

ctypedef long long Time

cdef Time LIMIT = (<Time>1) << 62
cdef object LIMIT_INT = 2 ** 62


cdef inline bint t_lt(Time a, Time b) noexcept nogil:
    return a < b


cdef inline bint t_le(Time a, Time b) noexcept nogil:
    return a <= b


cdef inline bint t_eq(Time a, Time b) noexcept nogil:
    return a == b


cdef inline bint t_is_zero(Time a) noexcept nogil:
    return a == 0


cdef inline Time t_add(Time a, Time b) noexcept nogil:
    return a + b


cdef inline Time t_sub(Time a, Time b) noexcept nogil:
    return a - b


cdef inline bint t_fits(Time a, Time b) noexcept nogil:
    return b <= LIMIT - a


cdef inline Time t_small(long long v) noexcept nogil:
    return v


cdef inline Time t_of(object x) except? -1:
    return x


cdef inline object t_py(Time a):
    return a


include "_engine_loop.pxi"
