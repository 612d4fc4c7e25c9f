# The C arrays of the compiled §4b loop (``_engine_loop.pxi``): the tokens of each
# place (a ring buffer), the heaps (ordered as heapq orders ``_Part``'s tuples),
# growable stacks, and arrays made from Python lists. Written on ``Time`` and its
# operations, which the including kernel module defines.

cdef struct Queue:
    # A place's tokens, oldest first, in a ring buffer (times they are available).
    Time* buf
    Py_ssize_t head
    Py_ssize_t size
    Py_ssize_t cap


cdef struct Entry:
    # A heap entry, ordered as the tuple (a, t, c, d) it stands for: a completion
    # (0, time, processor, stamp), a future token (0, time, event, 0), a pending job
    # (-priority, release, file index, task), as heapq orders _Part's tuples.
    long long a
    Time t
    long long c
    long long d


cdef struct Heap:
    Entry* data
    Py_ssize_t size
    Py_ssize_t cap


cdef inline bint _less(Entry* x, Entry* y) noexcept nogil:
    if x.a != y.a:
        return x.a < y.a
    if not t_eq(x.t, y.t):
        return t_lt(x.t, y.t)
    if x.c != y.c:
        return x.c < y.c
    return x.d < y.d


cdef int _heap_push(Heap* h, long long a, Time t, long long c, long long d) except -1:
    cdef Py_ssize_t i, parent
    cdef Entry* grown
    if h.size == h.cap:
        grown = <Entry*>PyMem_Realloc(h.data, (2 * h.cap + 4) * sizeof(Entry))
        if grown == NULL:
            raise MemoryError()
        h.data, h.cap = grown, 2 * h.cap + 4
    cdef Entry item
    item.a, item.t, item.c, item.d = a, t, c, d
    i = h.size
    h.size += 1
    while i > 0:
        parent = (i - 1) >> 1
        if not _less(&item, &h.data[parent]):
            break
        h.data[i] = h.data[parent]
        i = parent
    h.data[i] = item
    return 0


cdef inline void _heap_pop(Heap* h) noexcept nogil:
    # Removes the least entry (read it first at h.data[0]).
    cdef Py_ssize_t i = 0, child
    h.size -= 1
    cdef Entry last = h.data[h.size]
    while True:
        child = 2 * i + 1
        if child >= h.size:
            break
        if child + 1 < h.size and _less(&h.data[child + 1], &h.data[child]):
            child += 1
        if not _less(&h.data[child], &last):
            break
        h.data[i] = h.data[child]
        i = child
    h.data[i] = last


cdef int _queue_push(Queue* q, Time t) except -1:
    cdef Time* grown
    cdef Py_ssize_t k, n
    if q.size == q.cap:
        n = 2 * q.cap + 2
        grown = <Time*>PyMem_Malloc(n * sizeof(Time))
        if grown == NULL:
            raise MemoryError()
        for k in range(q.size):  # unrolled from the ring, oldest first
            grown[k] = q.buf[(q.head + k) % q.cap]
        PyMem_Free(q.buf)
        q.buf, q.cap, q.head = grown, n, 0
    q.buf[(q.head + q.size) % q.cap] = t
    q.size += 1
    return 0


cdef inline void _queue_pop(Queue* q) noexcept nogil:
    q.head += 1
    if q.head == q.cap:
        q.head = 0
    q.size -= 1


cdef int _stack_push(Py_ssize_t** stack, Py_ssize_t* size, Py_ssize_t* cap,
                     Py_ssize_t x) except -1:
    cdef Py_ssize_t* grown
    if size[0] == cap[0]:
        grown = <Py_ssize_t*>PyMem_Realloc(stack[0], (2 * cap[0] + 16) * sizeof(Py_ssize_t))
        if grown == NULL:
            raise MemoryError()
        stack[0], cap[0] = grown, 2 * cap[0] + 16
    stack[0][size[0]] = x
    size[0] += 1
    return 0


cdef Py_ssize_t* _index_array(object values) except NULL:
    cdef Py_ssize_t n = len(values), i
    cdef Py_ssize_t* out = <Py_ssize_t*>PyMem_Malloc((n + 1) * sizeof(Py_ssize_t))
    if out == NULL:
        raise MemoryError()
    for i in range(n):
        out[i] = values[i]
    return out


cdef long long* _int_array(object values) except NULL:
    cdef Py_ssize_t n = len(values), i
    cdef long long* out = <long long*>PyMem_Malloc((n + 1) * sizeof(long long))
    if out == NULL:
        raise MemoryError()
    for i in range(n):
        out[i] = values[i]
    return out


cdef Time* _time_array(object values) except NULL:
    cdef Py_ssize_t n = len(values), i
    cdef Time* out = <Time*>PyMem_Malloc((n + 1) * sizeof(Time))
    if out == NULL:
        raise MemoryError()
    for i in range(n):
        out[i] = t_of(values[i])
    return out


cdef Time* _filled(Py_ssize_t n, long long value) except NULL:
    cdef Py_ssize_t i
    cdef Time* out = <Time*>PyMem_Malloc((n + 1) * sizeof(Time))
    if out == NULL:
        raise MemoryError()
    for i in range(n):
        out[i] = t_small(value)
    return out


cdef long long* _zeros(Py_ssize_t n) except NULL:
    cdef Py_ssize_t i
    cdef long long* out = <long long*>PyMem_Malloc((n + 1) * sizeof(long long))
    if out == NULL:
        raise MemoryError()
    for i in range(n):
        out[i] = 0
    return out


cdef int _csr(Py_ssize_t n_rows, Py_ssize_t n, Py_ssize_t* row_of, Py_ssize_t** off,
              Py_ssize_t** values) except -1:
    # Compressed rows of 0..n-1 by row_of (-1: in no row), each row in increasing
    # order: row r is values[off[r]:off[r + 1]].
    cdef Py_ssize_t i, r
    cdef Py_ssize_t* fill
    off[0] = <Py_ssize_t*>PyMem_Malloc((n_rows + 1) * sizeof(Py_ssize_t))
    values[0] = <Py_ssize_t*>PyMem_Malloc((n + 1) * sizeof(Py_ssize_t))
    fill = <Py_ssize_t*>PyMem_Malloc((n_rows + 1) * sizeof(Py_ssize_t))
    if off[0] == NULL or values[0] == NULL or fill == NULL:
        PyMem_Free(fill)
        raise MemoryError()
    for r in range(n_rows + 1):
        off[0][r] = 0
    for i in range(n):
        if row_of[i] >= 0:
            off[0][row_of[i] + 1] += 1
    for r in range(n_rows):
        off[0][r + 1] += off[0][r]
        fill[r] = off[0][r]
    for i in range(n):
        r = row_of[i]
        if r >= 0:
            values[0][fill[r]] = i
            fill[r] += 1
    PyMem_Free(fill)
    return 0


cdef int _rows(list rows, Py_ssize_t** off, Py_ssize_t** values) except -1:
    # Compressed rows: row r is values[off[r]:off[r + 1]].
    cdef Py_ssize_t n = len(rows), r, total = 0
    off[0] = <Py_ssize_t*>PyMem_Malloc((n + 1) * sizeof(Py_ssize_t))
    if off[0] == NULL:
        raise MemoryError()
    for r in range(n):
        off[0][r] = total
        total += len(rows[r])
    off[0][n] = total
    values[0] = _index_array([x for row in rows for x in row])
    return 0
