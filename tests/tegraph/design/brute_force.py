"""A brute-force simulator of small distributed designs, written apart from tegraph.

Tasks are periodic (a clock of their own, with a phase; a non-blocking read of
the task before them, at the start of their job) or triggered (no clock: a blocking
read of the task before them, job k released once message k is visible and job
k-1 has ended). Each runs on a processor, preemptive or not, under fixed
priorities (priority descending, release ascending, file order, spec §4b, §4d): a
preemptive processor runs the first pending job at every instant; a non-preemptive
one chooses only when it runs no job, among the jobs released up to that instant.
A job of duration 0 ends at its release. A message written at a job's end ``f`` is
visible from ``f + delay`` on; a non-blocking read at the start ``s`` of a job sees
the messages visible strictly before ``s``, and those visible at ``s`` whose writer
runs on the same processor (spec §4c).

Time jumps from event to event in exact rationals: an instant first ends the jobs
that end there, then releases every job whose condition holds (a job of duration 0
ends at once, and may release others at the same instant), then lets each
processor choose. Nothing of tegraph is imported.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction


@dataclass
class SimTask:
    name: str
    processor: str
    priority: int
    duration: Fraction
    period: Fraction | None = None
    """Periodic: a clock of this period; None: triggered by ``source``'s messages."""
    phase: Fraction = Fraction(0)
    source: str | None = None
    """The task whose messages it reads (blocking when triggered, else at its start)."""
    delay: Fraction = Fraction(0)
    """The delay of the link from ``source``."""


@dataclass
class Job:
    task: str
    k: int
    activation: Fraction
    release: Fraction
    start: Fraction | None = None
    finish: Fraction | None = None
    data: int | None = None
    """The job of the chain's first task whose sample this job's output carries."""
    remaining: Fraction = Fraction(0)


@dataclass
class Run:
    jobs: dict[str, list[Job]] = field(default_factory=dict)


def simulate(tasks: list[SimTask], preemptive: dict[str, bool], horizon: Fraction) -> Run:
    """Every job released up to ``horizon``, with its start and end when they come by
    then."""
    order = {t.name: i for i, t in enumerate(tasks)}
    by_name = {t.name: t for t in tasks}
    run = Run({t.name: [] for t in tasks})
    running: dict[str, Job | None] = {p: None for p in preemptive}
    pending: dict[str, list[Job]] = {p: [] for p in preemptive}
    t = Fraction(0)

    def visible(writer: str, reader: SimTask, at: Fraction, strictly: bool) -> Job | None:
        """The newest message of ``writer`` visible to ``reader`` at ``at``."""
        best = None
        same = by_name[writer].processor == reader.processor
        for job in run.jobs[writer]:
            if job.finish is None:
                break
            seen = job.finish + reader.delay
            if seen < at or (seen == at and (not strictly or same)):
                best = job
        return best

    def activation(task: SimTask, k: int) -> Fraction | None:
        """When job k may be released, as far as its clock or its trigger says."""
        if task.period is not None:
            return task.phase + (k - 1) * task.period
        writes = run.jobs[task.source]
        if len(writes) < k or writes[k - 1].finish is None:
            return None
        return writes[k - 1].finish + task.delay

    def start(job: Job, at: Fraction) -> None:
        job.start = at
        task = by_name[job.task]
        if task.period is not None and task.source is not None:  # a non-blocking read
            seen = visible(task.source, task, at, strictly=True)
            job.data = None if seen is None else seen.data
        elif task.source is None:  # the chain's first task samples its sensor
            job.data = job.k

    def finish(job: Job, at: Fraction) -> None:
        job.finish = at

    def key(job: Job) -> tuple[int, Fraction, int]:
        """Priority descending, release ascending, place in the file (spec §4b, §4d)."""
        return (-by_name[job.task].priority, job.release, order[job.task])

    while t <= horizon:
        # 1. Jobs that end at t.
        for p, job in running.items():
            if job is not None and job.remaining == 0:
                finish(job, t)
                running[p] = None
        # 2. Releases at t, until none is left (jobs of duration 0 end at once).
        changed = True
        while changed:
            changed = False
            for task in tasks:
                jobs = run.jobs[task.name]
                if jobs and jobs[-1].finish is None:
                    continue  # job k waits for job k-1 to end
                k = len(jobs) + 1
                act = activation(task, k)
                if act is None or act > t:
                    continue
                job = Job(task.name, k, act, t, remaining=task.duration)
                if task.period is None:  # the blocking read, at the release
                    seen = visible(task.source, task, t, strictly=False)
                    job.data = None if seen is None else seen.data
                jobs.append(job)
                changed = True
                if task.duration == 0:
                    start(job, t)
                    finish(job, t)
                else:
                    pending[task.processor].append(job)
        # 3. Each processor chooses.
        for p in preemptive:
            if running[p] is None or preemptive[p]:
                candidates = pending[p] + ([running[p]] if running[p] is not None else [])
                if candidates:
                    best = min(candidates, key=key)
                    if best is not running[p]:
                        if running[p] is not None:
                            pending[p].append(running[p])
                        pending[p].remove(best)
                        running[p] = best
                        if best.start is None:
                            start(best, t)
        # 4. The next instant.
        nexts = []
        for task in tasks:
            jobs = run.jobs[task.name]
            if jobs and jobs[-1].finish is None:
                continue
            act = activation(task, len(jobs) + 1)
            if act is not None:
                nexts.append(max(act, t))
        nexts += [t + j.remaining for j in running.values() if j is not None]
        nexts = [x for x in nexts if x > t]
        if not nexts:
            break
        nxt = min(nexts)
        for job in running.values():
            if job is not None:
                job.remaining -= nxt - t
        t = nxt
    return run


def reactions(run: Run, chain: list[str], since: Fraction) -> dict[str, Fraction | None]:
    """The largest ``reaction``, ``age`` and ``first_use`` (spec §4c) over the samples of
    the chain's first task taken at or after ``since`` whose data reached the output by
    the end of the run."""
    first, last = run.jobs[chain[0]], run.jobs[chain[-1]]
    outputs = [(j.finish, j.data) for j in last if j.finish is not None and j.data is not None]
    sample = {j.k: j.start for j in first if j.start is not None}
    reaction = age = first_use = None
    for j, at in sample.items():
        if at < since:
            continue
        later = next((o for o, d in outputs if d > j), None)
        if later is not None:
            reaction = max(reaction or later - at, later - at)
        used = next((o for o, d in outputs if d == j), None)
        if used is not None:
            first_use = max(first_use or used - at, used - at)
    for o, d in outputs:
        if d in sample and sample[d] >= since:
            age = max(age or o - sample[d], o - sample[d])
    return {"reaction": reaction, "age": age, "first_use": first_use}
