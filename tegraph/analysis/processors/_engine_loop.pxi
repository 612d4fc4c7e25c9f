# The §4b loop of ``_engine._Part.run`` on C arrays, for one representation of times.
#
# Included by each kernel module after it defines ``Time`` (a signed integer type),
# ``LIMIT`` (a ``Time``: the times the loop makes stay in [0, LIMIT], so that the
# sum of two of them does not overflow), ``LIMIT_INT`` (the same as a Python int)
# and the operations on times: ``t_lt``, ``t_le``, ``t_eq``, ``t_is_zero``,
# ``t_add``, ``t_sub``, ``t_fits(a, b)`` (a + b <= LIMIT, for a, b in [0, LIMIT]),
# ``t_small`` (from a C long long), ``t_of`` and ``t_py`` (from and to Python ints).
# Everything else, the rules included, is written once, here.

from cpython.mem cimport PyMem_Free, PyMem_Malloc, PyMem_Realloc

cdef object INDEX_LIMIT = 2 ** 62
"""Priorities and file indices: C long longs, negated without overflow."""


include "_engine_arrays.pxi"


def covers(d) -> bool:
    """Whether the compiled loop simulates ``d`` (else the Python loop does).

    Every time a Python int (not a bool, not a Fraction or an affine time) in
    [0, ``LIMIT``]; priorities and file indices ints within [-2**62, 2**62]; and
    the part well formed: every list of its length, every index in range, job
    places only out of compute events (the loop reads C arrays: where the
    Python loop would raise an error, or read index -1, it is left to do so).
    """
    cdef object x
    n, n_tasks, n_procs, n_places = d.n_events, len(d.duration), d.n_processors, len(d.p_src)
    if any(len(x) != n_places for x in (d.p_dst, d.p_tokens, d.p_hold, d.p_init, d.p_job,
                                         d.p_cap)):
        return False
    if len(d.compute_task) != n or any(len(x) != n_tasks for x in (
            d.priority, d.file_index, d.processor, d.end_event)):
        return False
    # The times first: a part of large times leaves the int64 loop at its first one.
    for values in (d.p_init, d.p_hold, d.duration):
        for x in values:
            if type(x) is not int or not 0 <= x <= LIMIT_INT:
                return False
    for values in (d.priority, d.file_index):
        for x in values:
            if type(x) is not int or not -INDEX_LIMIT <= x <= INDEX_LIMIT:
                return False
    if not all(0 <= x < n for values in (d.p_src, d.p_dst) for x in values):
        return False
    if not all(-1 <= x < n_tasks for x in d.compute_task):
        return False
    if not all(0 <= x < n_procs for x in d.processor):
        return False
    if not all(x is None or 0 <= x < n for x in d.end_event):
        return False
    if not all(0 <= e < n and all(0 <= x < n_tasks for x in tasks)
               for e, tasks in d.watched.items()):
        return False
    if d.snapshot_place is not None and not 0 <= d.snapshot_place < n_places:
        return False
    if not all(d.compute_task[s] >= 0 for s, job in zip(d.p_src, d.p_job) if job):
        return False
    if not all(type(x) is int and x >= 0 for x in d.p_tokens):
        return False
    if not all(0 <= e < n for e in d.logged) or not all(0 <= x < n_tasks for x in d.started):
        return False
    if len(d.preemptive) not in (0, n_procs):
        return False
    return True


cdef class Kernel:
    """The state of one part under the compiled loop (what ``_Part`` keeps in lists)."""

    cdef Py_ssize_t n_events, n_places, n_tasks, n_procs
    # The graph, in compressed rows: places into each event (in_*), filled at once
    # (now_*), filled later (later_*) by each event, filled by each task's job end (job_*).
    cdef Py_ssize_t *in_off
    cdef Py_ssize_t *in_place
    cdef Py_ssize_t *now_off
    cdef Py_ssize_t *now_place
    cdef Py_ssize_t *later_off
    cdef Py_ssize_t *later_place
    cdef Py_ssize_t *job_off
    cdef Py_ssize_t *job_place
    cdef Py_ssize_t *watch_off
    cdef Py_ssize_t *watch_task
    cdef Py_ssize_t *p_dst
    cdef Time *p_hold
    cdef Py_ssize_t *compute_task
    cdef char *watched
    cdef char *loop
    cdef Time *duration
    cdef long long *neg_priority
    cdef long long *file_index
    cdef Py_ssize_t *processor
    cdef Py_ssize_t *end_event
    cdef char *lazy
    """Per processor: 1 where it is non-preemptive (§4d); its running job is out of its heap."""
    # The state.
    cdef Queue *queues
    cdef Time *tight
    cdef long long *fired
    cdef long long *finished
    cdef Time *remaining
    cdef Heap future
    cdef Heap comp
    cdef Heap *ready
    cdef Py_ssize_t *running
    cdef Time *run_start
    cdef Time *done_at
    cdef long long *stamp
    cdef Py_ssize_t *work
    cdef Py_ssize_t work_n, work_cap
    cdef Py_ssize_t *ticked
    cdef Py_ssize_t ticked_n, ticked_cap
    cdef Py_ssize_t *touched
    cdef Py_ssize_t touched_n, touched_cap
    cdef char *is_touched
    cdef Py_ssize_t snapshot_place
    cdef bint keep_intervals
    # What a chain needs recorded (spec §4c): the firing instants of some events, the
    # start of each job of some tasks (each a list of the result, None elsewhere).
    cdef char *logged
    cdef list firing_lists
    cdef bint tracing
    cdef list start_lists
    # The result's objects, filled as the Python loop fills them.
    cdef object result
    cdef list jobs
    cdef list intervals
    cdef dict tick_log
    cdef dict overrun_at
    cdef list tick_lists
    cdef object now_obj
    cdef readonly Py_ssize_t count
    """Firings so far (``_Part.count``)."""

    def __cinit__(self):
        self.snapshot_place = -1

    def __init__(self, d, result, bint keep_intervals):
        """``d`` a part that :func:`covers`; the figures go to ``result`` (a ``PartResult``)."""
        cdef Py_ssize_t n = d.n_events, np_ = len(d.p_src), nt = len(d.duration)
        cdef Py_ssize_t p, e, s, t, i, m, task
        self.n_events, self.n_places, self.n_tasks = n, np_, nt
        self.n_procs = d.n_processors
        self.keep_intervals = keep_intervals
        self.result = result
        self.jobs, self.intervals = result.jobs, result.intervals
        self.tick_log, self.overrun_at = result.tick_log, result.overrun_at
        self.tick_lists = [None] * nt
        self.p_dst = _index_array(d.p_dst)
        self.p_hold = _time_array(d.p_hold)
        self.compute_task = _index_array(d.compute_task)
        self.duration = _time_array(d.duration)
        self.neg_priority = _int_array([-x for x in d.priority])
        self.file_index = _int_array(d.file_index)
        self.processor = _index_array(d.processor)
        self.end_event = _index_array([-1 if x is None else x for x in d.end_event])
        self.lazy = <char*>PyMem_Malloc(self.n_procs + 1)
        if self.lazy == NULL:
            raise MemoryError()
        for i in range(self.n_procs):
            self.lazy[i] = 0 if not d.preemptive or d.preemptive[i] else 1
        # The rows, each in place order as _Part builds its tuples: a place goes into
        # its event; out of its event, to the end of its task's job (a job place),
        # later (a hold) or at once.
        cdef Py_ssize_t* src = _index_array(d.p_src)
        cdef Py_ssize_t* row = <Py_ssize_t*>PyMem_Malloc((np_ + 1) * sizeof(Py_ssize_t))
        if row == NULL:
            PyMem_Free(src)
            raise MemoryError()
        try:
            _csr(n, np_, self.p_dst, &self.in_off, &self.in_place)
            job = d.p_job
            for p in range(np_):
                row[p] = self.compute_task[src[p]] if job[p] else -1
            _csr(nt, np_, row, &self.job_off, &self.job_place)
            holds = d.p_hold
            for p in range(np_):
                row[p] = src[p] if not job[p] and holds[p] else -1
            _csr(n, np_, row, &self.later_off, &self.later_place)
            for p in range(np_):
                row[p] = src[p] if not job[p] and not holds[p] else -1
            _csr(n, np_, row, &self.now_off, &self.now_place)
            self.loop = <char*>PyMem_Malloc(n + 1)
            if self.loop == NULL:
                raise MemoryError()
            for e in range(n):
                self.loop[e] = 0
            for p in range(np_):
                if src[p] == self.p_dst[p]:
                    self.loop[src[p]] = 1
        finally:
            PyMem_Free(src)
            PyMem_Free(row)
        _rows([d.watched.get(e, ()) for e in range(n)], &self.watch_off, &self.watch_task)
        self.watched = <char*>PyMem_Malloc(n + 1)
        if self.watched == NULL:
            raise MemoryError()
        for e in range(n):
            self.watched[e] = 0
        for e in d.watched:
            self.watched[e] = 1
        # The state at time 0.
        self.queues = <Queue*>PyMem_Malloc((np_ + 1) * sizeof(Queue))
        if self.queues == NULL:
            raise MemoryError()
        cdef Time a
        for p in range(np_):
            self.queues[p].buf = NULL
            self.queues[p].head = self.queues[p].size = self.queues[p].cap = 0
        init, tokens = d.p_init, d.p_tokens
        for p in range(np_):
            m = tokens[p]
            if m:
                a = t_of(init[p])
                for i in range(m):
                    _queue_push(&self.queues[p], a)
                if init[p] > 0:
                    _heap_push(&self.future, 0, a, self.p_dst[p], 0)
        self.tight = _filled(np_, -1)
        self.fired = _zeros(n)
        self.finished = _zeros(nt)
        self.remaining = _filled(nt, -1)
        self.ready = <Heap*>PyMem_Malloc((self.n_procs + 1) * sizeof(Heap))
        if self.ready == NULL:
            raise MemoryError()
        for i in range(self.n_procs):
            self.ready[i].data = NULL
            self.ready[i].size = self.ready[i].cap = 0
        self.running = _index_array([-1] * self.n_procs)
        self.run_start = _filled(self.n_procs, 0)
        self.done_at = _filled(self.n_procs, 0)
        self.stamp = _zeros(self.n_procs)
        self.is_touched = <char*>PyMem_Malloc(self.n_procs + 1)
        if self.is_touched == NULL:
            raise MemoryError()
        for i in range(self.n_procs):
            self.is_touched[i] = 0
        if d.snapshot_place is not None:
            self.snapshot_place = d.snapshot_place
        self.logged = <char*>PyMem_Malloc(n + 1)
        if self.logged == NULL:
            raise MemoryError()
        for e in range(n):
            self.logged[e] = 0
        self.firing_lists = [None] * n
        for e in d.logged:
            self.logged[e] = 1
            self.firing_lists[e] = result.firings[e] = []
        self.start_lists = [None] * nt
        for task in d.started:
            self.start_lists[task] = result.starts[task] = []
        self.tracing = len(d.started) > 0

    def __dealloc__(self):
        cdef Py_ssize_t i
        if self.queues != NULL:
            for i in range(self.n_places):
                PyMem_Free(self.queues[i].buf)
        if self.ready != NULL:
            for i in range(self.n_procs):
                PyMem_Free(self.ready[i].data)
        PyMem_Free(self.in_off)
        PyMem_Free(self.in_place)
        PyMem_Free(self.now_off)
        PyMem_Free(self.now_place)
        PyMem_Free(self.later_off)
        PyMem_Free(self.later_place)
        PyMem_Free(self.job_off)
        PyMem_Free(self.job_place)
        PyMem_Free(self.watch_off)
        PyMem_Free(self.watch_task)
        PyMem_Free(self.p_dst)
        PyMem_Free(self.p_hold)
        PyMem_Free(self.compute_task)
        PyMem_Free(self.watched)
        PyMem_Free(self.logged)
        PyMem_Free(self.loop)
        PyMem_Free(self.duration)
        PyMem_Free(self.neg_priority)
        PyMem_Free(self.file_index)
        PyMem_Free(self.processor)
        PyMem_Free(self.end_event)
        PyMem_Free(self.lazy)
        PyMem_Free(self.queues)
        PyMem_Free(self.tight)
        PyMem_Free(self.fired)
        PyMem_Free(self.finished)
        PyMem_Free(self.remaining)
        PyMem_Free(self.future.data)
        PyMem_Free(self.comp.data)
        PyMem_Free(self.ready)
        PyMem_Free(self.running)
        PyMem_Free(self.run_start)
        PyMem_Free(self.done_at)
        PyMem_Free(self.stamp)
        PyMem_Free(self.work)
        PyMem_Free(self.ticked)
        PyMem_Free(self.touched)
        PyMem_Free(self.is_touched)

    # ------------------------------------------------------------ the run
    cdef inline object _now(self, Time now):
        # One int object per instant, shared by everything recorded at it (as in Python).
        if self.now_obj is None:
            self.now_obj = t_py(now)
        return self.now_obj

    cdef int _touch(self, Py_ssize_t proc) except -1:
        if not self.is_touched[proc]:
            self.is_touched[proc] = 1
            _stack_push(&self.touched, &self.touched_n, &self.touched_cap, proc)
        return 0

    cdef int _job_ends(self, Py_ssize_t task, Time now) except -1:
        # The places leaving its compute receive their token, their events are tried.
        cdef Py_ssize_t i, p
        cdef list mine
        self.remaining[task] = t_small(-1)
        self.finished[task] += 1
        mine = <list>self.jobs[task]
        (<list>mine[len(mine) - 1])[1] = self._now(now)
        for i in range(self.job_off[task], self.job_off[task + 1]):
            p = self.job_place[i]
            _queue_push(&self.queues[p], now)
            _stack_push(&self.work, &self.work_n, &self.work_cap, self.p_dst[p])
        return 0

    cdef int _started(self, Py_ssize_t task, Time now) except -1:
        # The job of ``task`` holds its processor: its start, the first time.
        cdef list mine = <list>self.start_lists[task]
        if mine is not None and len(mine) < len(<list>self.jobs[task]):
            mine.append(self._now(now))
        return 0

    cdef int _record(self, Py_ssize_t proc, Py_ssize_t task, Time end) except -1:
        cdef Time start = self.run_start[proc]
        if t_lt(start, end) and self.keep_intervals:
            self.intervals.append((proc, t_py(start), self._now(end), task,
                                   len(<list>self.jobs[task])))
        return 0

    def run(self, Py_ssize_t budget, Py_ssize_t after_overrun, compare):
        """Simulate from time 0 as ``_Part.run(budget)`` does; return the last instant,
        or None when a time would pass the bound (the state is then of no use).

        ``after_overrun``: ``_engine.AFTER_OVERRUN``; ``compare(now)``: ``_compare``
        at the instants the Python loop compares states.
        """
        cdef Time now = t_small(0), nxt, hold, later
        cdef Py_ssize_t limit = budget, count = 0, overrun = -1
        cdef Py_ssize_t e, i, p, task, proc, top, old, dst
        cdef bint cut = False, again
        cdef Queue* q
        cdef Queue* snap = NULL if self.snapshot_place < 0 else &self.queues[self.snapshot_place]
        cdef Entry* head
        cdef Heap* heap
        cdef object result = self.result
        for e in range(self.n_events):  # at time 0 every event is tried, the last first
            _stack_push(&self.work, &self.work_n, &self.work_cap, e)
        while True:
            self.now_obj = None
            if snap != NULL and snap.size == 0:
                return None  # the Python loop says what happens (it reads no token there)
            if snap == NULL or t_eq(snap.buf[snap.head], now):
                self.count = count
                if compare(self._now(now)):
                    return self._now(now)
            # Jobs that end deliver their tokens (completions in (time, processor,
            # stamp) order, as heapq pops them).
            while self.comp.size and t_le(self.comp.data[0].t, now):
                head = &self.comp.data[0]
                proc, old = head.c, head.d
                _heap_pop(&self.comp)
                if old == self.stamp[proc]:
                    if self.lazy[proc]:  # its job left the heap when it started
                        task = self.running[proc]
                    else:
                        heap = &self.ready[proc]
                        task = heap.data[0].d
                        _heap_pop(heap)
                    if self.keep_intervals:
                        self._record(proc, task, now)
                    self.running[proc] = -1
                    self.stamp[proc] += 1
                    self._touch(proc)
                    self._job_ends(task, now)
            while self.future.size and t_le(self.future.data[0].t, now):
                dst = self.future.data[0].c
                _heap_pop(&self.future)
                _stack_push(&self.work, &self.work_n, &self.work_cap, dst)
            # Fire every event of the work list (and those it enables), as _Part.run.
            while self.work_n:
                self.work_n -= 1
                e = self.work[self.work_n]
                while True:
                    again = True
                    for i in range(self.in_off[e], self.in_off[e + 1]):
                        q = &self.queues[self.in_place[i]]
                        if q.size == 0 or t_lt(now, q.buf[q.head]):
                            again = False
                            break
                    if not again:
                        break
                    if count >= limit:  # an event still to fire: the budget is spent
                        cut = True
                        self.work_n = 0
                        break
                    count += 1
                    self.fired[e] += 1
                    for i in range(self.in_off[e], self.in_off[e + 1]):
                        p = self.in_place[i]
                        q = &self.queues[p]
                        if t_eq(q.buf[q.head], now):  # the token taken came at this instant
                            self.tight[p] = now
                        _queue_pop(q)
                        if q.size == 0:
                            again = self.loop[e]
                    if self.logged[e]:
                        (<list>self.firing_lists[e]).append(self._now(now))
                    task = self.compute_task[e]
                    if task >= 0:  # its job is released
                        (<list>self.jobs[task]).append([self._now(now), None])
                        if t_is_zero(self.duration[task]):  # and ends at once
                            if self.tracing:
                                self._started(task, now)
                            self._job_ends(task, now)
                        else:
                            self.remaining[task] = self.duration[task]
                            proc = self.processor[task]
                            _heap_push(&self.ready[proc], self.neg_priority[task], now,
                                       self.file_index[task], task)
                            self._touch(proc)
                    for i in range(self.now_off[e], self.now_off[e + 1]):
                        p = self.now_place[i]
                        _queue_push(&self.queues[p], now)
                        _stack_push(&self.work, &self.work_n, &self.work_cap, self.p_dst[p])
                    for i in range(self.later_off[e], self.later_off[e + 1]):
                        p = self.later_place[i]
                        hold = self.p_hold[p]
                        if not t_fits(now, hold):
                            return None
                        later = t_add(now, hold)
                        _queue_push(&self.queues[p], later)
                        _heap_push(&self.future, 0, later, self.p_dst[p], 0)
                    if self.watched[e]:
                        _stack_push(&self.ticked, &self.ticked_n, &self.ticked_cap, e)
                    if not again:
                        break
            if self.ticked_n:
                self._check_ticks(now)
            # Each processor touched goes to its most urgent pending job, preempting
            # the running one (whose remaining work is then kept) where it may.
            for i in range(self.touched_n):
                proc = self.touched[i]
                self.is_touched[proc] = 0
                heap = &self.ready[proc]
                old = self.running[proc]
                if self.lazy[proc]:  # it takes a job only when it runs none (§4d)
                    if old >= 0 or heap.size == 0:
                        continue
                    top = heap.data[0].d
                    _heap_pop(heap)
                else:
                    top = heap.data[0].d if heap.size else -1
                    if top == old:
                        continue
                if old >= 0:
                    self.remaining[old] = t_sub(self.done_at[proc], now)
                    if self.keep_intervals:
                        self._record(proc, old, now)
                self.running[proc] = top
                self.stamp[proc] += 1
                if top >= 0:
                    self.run_start[proc] = now
                    if not t_fits(now, self.remaining[top]):
                        return None
                    self.done_at[proc] = t_add(now, self.remaining[top])
                    _heap_push(&self.comp, 0, self.done_at[proc], proc, self.stamp[proc])
                    if self.tracing:
                        self._started(top, now)
            self.touched_n = 0
            if cut:
                self.count = count
                result.budget_spent = True
                if limit < budget:
                    result.after_overrun = None if overrun < 0 else overrun
                return self._now(now)
            if overrun < 0 and self.overrun_at:
                overrun = count
                limit = min(budget, overrun + max(overrun, budget // after_overrun))
            # The next instant: the earliest of a token becoming available and a
            # running job's end (completions of preempted jobs are stale).
            while self.comp.size and self.comp.data[0].d != self.stamp[self.comp.data[0].c]:
                _heap_pop(&self.comp)
            if self.future.size:
                nxt = self.future.data[0].t
                if self.comp.size and t_lt(self.comp.data[0].t, nxt):
                    nxt = self.comp.data[0].t
            elif self.comp.size:
                nxt = self.comp.data[0].t
            else:
                self.count = count
                result.regime = ("stop", self._now(now))
                return self._now(now)
            now = nxt

    cdef int _check_ticks(self, Time now) except -1:
        # _Part._check_ticks: the slack of each clocked task at its clock's ticks.
        cdef Py_ssize_t i, j, e, task, last
        cdef long long k, slack
        cdef list mine
        for i in range(self.ticked_n):
            e = self.ticked[i]
            k = self.fired[e]
            for j in range(self.watch_off[e], self.watch_off[e + 1]):
                task = self.watch_task[j]
                last = self.end_event[task]  # -1: its activation ends with its job
                slack = (self.finished[task] if last < 0 else self.fired[last]) - (k - 1)
                mine = self.tick_lists[task]
                if mine is None:
                    mine = []
                    self.tick_lists[task] = mine
                    self.tick_log[task] = mine
                mine.append((self._now(now), k, slack))
                if slack < 0 and task not in self.overrun_at:
                    self.overrun_at[task] = k
        self.ticked_n = 0
        return 0

    def flush(self, now) -> None:
        """``_Part.flush``: the intervals of the jobs still running at ``now``."""
        cdef Py_ssize_t proc
        cdef Time end = t_of(now)
        self.now_obj = now
        for proc in range(self.n_procs):
            if self.running[proc] >= 0:
                self._record(proc, self.running[proc], end)

    # ------------------------------------------------------------ exports for _compare
    def lengths(self) -> list:
        """The token count of every place."""
        cdef Py_ssize_t p
        return [self.queues[p].size for p in range(self.n_places)]

    def tokens(self, Py_ssize_t p) -> list:
        """The tokens of place ``p``, oldest first."""
        cdef Queue* q = &self.queues[p]
        cdef Py_ssize_t k
        return [t_py(q.buf[(q.head + k) % q.cap]) for k in range(q.size)]

    def ahead(self, list places, now) -> tuple:
        """``_States.ahead``: the tokens of each of ``places`` not available before
        ``now``, relative to it."""
        cdef Time at = t_of(now), zero = t_small(0), x
        cdef Queue* q
        cdef Py_ssize_t p, k
        out = []
        for p in places:
            q = &self.queues[p]
            row = []
            for k in range(q.size):
                x = t_sub(q.buf[(q.head + k) % q.cap], at)
                if t_le(zero, x):
                    row.append(t_py(x))
            out.append(tuple(row))
        return tuple(out)

    def ready_jobs(self) -> list:
        """Per processor, its pending jobs as ``_Part.heaps`` holds them (in no order)."""
        cdef Py_ssize_t proc, k
        cdef Heap* h
        out = []
        for proc in range(self.n_procs):
            h = &self.ready[proc]
            out.append([(h.data[k].a, t_py(h.data[k].t), h.data[k].c, h.data[k].d)
                        for k in range(h.size)])
        return out

    def pending(self, now) -> list:
        """``_Part.pending``: the remaining work of each task's job, -1 without one."""
        cdef Py_ssize_t proc, task
        cdef Time at = t_of(now)
        rem = [t_py(self.remaining[task]) for task in range(self.n_tasks)]
        for proc in range(self.n_procs):
            if self.running[proc] >= 0:
                rem[self.running[proc]] = t_py(t_sub(self.done_at[proc], at))
        return rem

    def fired_counts(self) -> list:
        cdef Py_ssize_t e
        return [self.fired[e] for e in range(self.n_events)]

    def finished_counts(self) -> list:
        cdef Py_ssize_t task
        return [self.finished[task] for task in range(self.n_tasks)]

    def tight_times(self) -> list:
        cdef Py_ssize_t p
        return [t_py(self.tight[p]) for p in range(self.n_places)]

    def running_jobs(self) -> list:
        """Per processor, the task whose job it runs (-1: none)."""
        cdef Py_ssize_t proc
        return [self.running[proc] for proc in range(self.n_procs)]
