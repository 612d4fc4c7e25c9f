"""Synthesis of the synchronization: search protocol and clock choices for the best live,
consistent, schedulable designs (ORCCAD §6, ``tegraph explore``).

Section 6 of the ORCCAD paper [1]_ gives rules for *adding* synchronization to a
multi-rate controller; this module makes the tool choose, link by link,
between ASYN/ASYN, ASYN/SYN, SYN/ASYN and SYN/SYN, and clock periods among
candidates, by judging variants exactly (:mod:`.evaluate`) and keeping the
Pareto front of the objectives (chain latencies, period, processor load).

- The space and its numbering: :mod:`.space`; its choices: :mod:`.choices`; the
  objectives and constraints: :mod:`.objectives`.
- Variants settled without analysis, with proofs: :mod:`.prune`.
- The searches (exhaustive up to ``max_variants``, Pareto local search
  beyond) and the exact front: :mod:`.search`.
- The execution, in this process or on Dask ``distributed``: :mod:`.run`,
  :mod:`.dask_engine`.

The results file is :mod:`tegraph.design.explore.results` (written as verdicts arrive, by
:func:`tegraph.explore`); rendering is done above this floor
(:mod:`tegraph.report.explore_text`).

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_text, exact_time

from ...analysis import notebook
from ...errors import InputError
from ...model.limits import shown
from .evaluate import ANALYZED, FAILED, PRUNED, REJECTIONS, VariantResult, rejection
from .prune import DeadlockOracle
from .run import Progress, RunLog, max_local_workers, run_search
from .search import ExhaustiveSearch, ParetoFront, ParetoLocalSearch
from .space import DesignSpace

__all__ = ["PRUNING_RULES", "Exploration", "cross_check", "explore_design", "max_local_workers"]

PRUNING_RULES = (
    "A: liveness and the port repair depend on the protocols only, not on periods: a "
    "protocol assignment dead for every port order settles all its clock variants at once",
    "B: replacing a synchronizing protocol by ASYN/ASYN removes an obligation, never adds "
    "one, so a prefix of links already dead for every port order (the rest ASYN/ASYN) "
    "settles every completion",
    "C: a processor whose groups with a clock need more than all its time (sum of "
    "duration / clock period > 1) cannot run them at their clocks' periods: the variant "
    "is not schedulable on processors, decided without the schedule (the response-time "
    "test prunes nothing: its verdict is no proof on processors)",
)

_METHODS = {
    "exhaustive": "exhaustive: every variant judged, analyzed or pruned by rule A or B "
                  "(proven); the front is the exact Pareto front of the space",
    "pareto-local-search": "Pareto local search (Paquete, Chiarandini and Stützle 2004), "
                           "a heuristic: from the input design, every neighbour (one choice "
                           "changed) of the front judged in generations, then, at a Pareto "
                           "local optimum, widened from the other judged variants while the "
                           "budget lasts; the front is the best found, not proven optimal",
}


@dataclass
class Exploration:
    """What :func:`explore_design` found.

    Attributes
    ----------
    space : DesignSpace
    method : str
        ``"exhaustive"`` or ``"pareto-local-search"``.
    results : dict of int to VariantResult
        Every judged variant (those read back from a results file included).
    front : list of VariantResult
        The Pareto front of the kept variants, sorted by objective values.
    stopped : str
        Why the search ended.
    max_variants : int
        The threshold of the exhaustive search (and the budget of the local search).
    log : RunLog
    seconds : float
    resumed : int
        Verdicts read back from the results file.
    output : str or None
        The results file (set by :func:`tegraph.explore`).
    """

    space: DesignSpace
    method: str
    results: dict[int, VariantResult]
    front: list[VariantResult]
    stopped: str
    max_variants: int
    log: RunLog = field(default_factory=RunLog)
    seconds: float = 0.0
    resumed: int = 0
    output: str | None = None
    notes: list[str] = field(default_factory=list)
    local_optimum_at: int | None = None
    """Local search: the analyses done when the front first was a Pareto local optimum."""

    def _repr_html_(self) -> str:
        """The result as a notebook shows it (:func:`tegraph.report.html.render_html`)."""
        return notebook.html(self)

    def count(self, judged: str) -> int:
        """How many variants were judged that way (``judged``: analyzed, pruned, ...)."""
        return sum(1 for r in self.results.values() if r.judged == judged)

    @property
    def exhaustive(self) -> bool:
        """Every variant of the space judged (analyzed, or pruned by a proven rule)."""
        return (len(self.results) == self.space.size
                and all(r.judged in (ANALYZED, PRUNED) for r in self.results.values()))

    @property
    def consistent(self) -> int:
        """Variants live (perhaps after the repair) and consistent."""
        return sum(1 for r in self.results.values() if r.live and r.consistent)

    @property
    def kept(self) -> int:
        """Variants live, consistent, schedulable on their processors and meeting the
        constraints."""
        return sum(1 for r in self.results.values() if r.kept)

    @property
    def rejected(self) -> dict[str, int]:
        """Judged variants not kept, counted by why (:data:`~.evaluate.REJECTIONS`,
        in that order; reasons that no variant had are left out)."""
        counts = dict.fromkeys(REJECTIONS, 0)
        for r in self.results.values():
            why = rejection(r)
            if why is not None:
                counts[why] += 1
        return {why: n for why, n in counts.items() if n}

    @property
    def verdict(self) -> str:
        """One sentence: the front found and how it was obtained."""
        wanted = "live, consistent and schedulable on its processors" + (
            " and meets the constraints" if self.space.constraints else "")
        if not self.front:
            what = f"no variant is {wanted}"
        else:
            what = f"{len(self.front)} design(s) on the Pareto front of {self.kept} kept"
        failed = self.count(FAILED)
        if self.exhaustive:
            how = "exhaustive: the exact front of all variants"
        elif self.method == "exhaustive":
            # Every variant was proposed, but some could not be judged (or are missing):
            # the front is exact only over the variants judged.
            how = (f"every variant proposed, {failed:,} failed to be judged: the exact "
                   "front of the variants judged, not of the space")
        else:
            how = f"{self.method}, not exhaustive: the best front found"
        return f"{what} ({how})"

    @property
    def distinct_front(self) -> list[list[VariantResult]]:
        """The front by objective vector: one list per distinct vector, in the order of
        :attr:`front`, each holding the front's designs of that vector (its ties, equal
        on every objective and on the Rule 2 tie-breaker) by variant number."""
        groups: dict[tuple, list[VariantResult]] = {}
        for r in self.front:
            groups.setdefault(tuple(r.objectives.get(n) for n in self.space.objectives),
                              []).append(r)
        return list(groups.values())

    def entry(self, r: VariantResult) -> dict[str, Any]:
        """A variant as the report shows it: its choices, objectives and repair."""
        links, clocks = self.space.describe(r.variant)
        out = {"variant": r.variant, "links": links, "clocks": clocks,
               "objectives": {k: exact_text(v) for k, v in r.objectives.items()},
               "kinds": dict(r.kinds), "repaired": r.repaired, "orders": r.orders,
               "rule2": r.rule2}
        if self.space.allocation is not None:  # where its units run, what crosses
            out["processors"] = self.space.placement(r.variant)
            out["crossing"] = [{"link": link, "delay": exact_text(delay)}
                               for link, delay in self.space.crossing(r.variant)]
        return out

    def to_dict(self) -> dict[str, Any]:
        """The body of the JSON report (``docs/report.schema.json``, ``$defs/explore``)."""
        sk = self.space.skeleton
        return {
            "name": sk.name, "unit": sk.unit,
            "variants": self.space.size,
            "evaluated": self.count(ANALYZED),
            "pruned": self.count(PRUNED),
            "failed": self.count(FAILED),
            "consistent": self.consistent,
            "kept": self.kept,
            "rejected": self.rejected,
            "exhaustive": self.exhaustive,
            "search": {"method": self.method, "description": _METHODS[self.method],
                       "max_variants": self.max_variants, "stopped": self.stopped,
                       "local_optimum_at": self.local_optimum_at,
                       "pruning_rules": list(PRUNING_RULES)},
            "objectives": list(self.space.objectives),
            "choices": {
                "links": {c.label: [p.value for p in c.protocols] for c in self.space.links},
                "clocks": {c.name: [exact_text(t) for t in c.periods]
                           for c in self.space.clocks},
                **({} if self.space.allocation is None
                   else {"allocation": self.space.allocation.to_dict()})},
            "chains": [list(c) for c in self.space.chains],
            "constraints": self.space.constraints.to_dict(),
            "front": [{**self.entry(r), "ties": len(tied)}
                      for tied in self.distinct_front for r in tied],
            "engine": {"kind": self.log.engine, "workers": self.log.workers,
                       "address": self.log.address, "batches": self.log.batches,
                       "largest_batch": max(self.log.batch_sizes, default=0),
                       "seconds_per_variant": self.log.seconds_per_variant},
            "output": self.output,
            "resumed": self.resumed,
            "seconds": round(self.seconds, 3),
            "notes": list(self.notes),
            "verdict": self.verdict,
        }


MAX_TIMEOUT = 86_400.0
"""Longest wait for a scheduler, in seconds (a day): Dask takes a finite duration."""

def wait_seconds(timeout: Any) -> float:
    """A scheduler timeout read by the one number parser, as the seconds Dask takes.

    Numbers, exact fractions and texts (``"1/2"``, ``"2.5"``) alike go through
    :func:`maxplus.scalar.exact_time`, whose digit bound refuses ``1e999999999``
    by its size (never expanded, never read as infinity); a refusal shows the
    value as given.

    >>> wait_seconds("1/2"), wait_seconds(30)
    (0.5, 30.0)
    >>> wait_seconds("0")
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: timeout: expected a number of seconds > 0 and at most 86400 \
(a day), got '0'
    """
    expected = f"expected a number of seconds > 0 and at most {MAX_TIMEOUT:g} (a day)"
    given = shown(timeout) if isinstance(timeout, str) else shown(repr(timeout), quote=False)
    try:
        value = exact_time(timeout, "timeout")
    except MaxPlusValueError as exc:
        reason = str(exc).removeprefix("timeout: ")
        # The parser's own words when they are about the text given (its size, a zero
        # denominator); its (max,+) words about infinity mean nothing for a wait.
        if "(max,+)" in reason or reason.startswith("expected"):
            raise InputError(f"{expected}, got {given}", "timeout") from None
        raise InputError(f"{expected}; {reason}", "timeout") from None
    if not 0 < value <= MAX_TIMEOUT:
        raise InputError(f"{expected}, got {given}", "timeout")
    return float(value)


_ADDRESS = re.compile(r"(?:(?P<scheme>[A-Za-z][A-Za-z0-9+.-]*)://)?(?P<host>\[[0-9A-Fa-f:.]+\]|"
                      r"[A-Za-z0-9_.-]+):(?P<port>[0-9]{1,5})/?")


def scheduler_address(address: str) -> str:
    """Check a Dask scheduler address before any connection: ``tcp://HOST:PORT``
    (``HOST:PORT`` means tcp, as in Dask).

    A malformed address is refused here rather than handed to Dask, whose client,
    once half-built, waits for its own timeout at garbage collection before failing with a
    traceback; ``tls://`` is refused too, since it needs certificates this
    command does not take.

    >>> scheduler_address("127.0.0.1:8786")
    'tcp://127.0.0.1:8786'
    >>> scheduler_address("tcp://127.0.0.1:abc")
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: scheduler: cannot read 'tcp://127.0.0.1:abc' as a Dask \
scheduler address; expected tcp://HOST:PORT with a port from 1 to 65535, such as \
tcp://127.0.0.1:8786
    """
    text = str(address).strip()
    found = _ADDRESS.fullmatch(text)
    scheme = text.partition("://")[0].lower() if "://" in text else "tcp"
    if scheme != "tcp":
        why = ("a TLS scheduler needs certificates (a security configuration), which "
               "explore does not take" if scheme == "tls" else
               f"the {scheme}:// transport is not supported")
        raise InputError(f"cannot use {text!r}: {why}; expected tcp://HOST:PORT, such as "
                         "tcp://127.0.0.1:8786", "scheduler")
    if found is None or not 1 <= int(found["port"]) <= 65535:
        raise InputError(f"cannot read {text!r} as a Dask scheduler address; expected "
                         "tcp://HOST:PORT with a port from 1 to 65535, such as "
                         "tcp://127.0.0.1:8786", "scheduler")
    return f"tcp://{found['host']}:{int(found['port'])}"


def explore_design(space: DesignSpace, *, scheduler: str | None = None,
                   workers: int | None = None, max_variants: int = 10_000,
                   batch_size: int | None = None,
                   known: dict[int, VariantResult] | None = None,
                   record: Callable[[Sequence[VariantResult]], None] | None = None,
                   progress: Callable[[Progress], None] | None = None,
                   timeout: float | str = 10.0) -> Exploration:
    """Search ``space`` for the Pareto front of live, consistent, schedulable designs.

    Parameters
    ----------
    space : DesignSpace
        From :func:`tegraph.design.explore.space.design_space`.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://HOST:8786``).
    workers : int, optional
        0: judge in this process; N: a local Dask cluster of N processes, at most
        :func:`max_local_workers` (the machine's cores); None (default): this process,
        or a local cluster of one process per core when the measured work is worth
        its start-up (:mod:`.run`).
    max_variants : int
        Spaces of at most this many variants are searched exhaustively; beyond,
        Pareto local search analyzes at most this many variants.
    batch_size : int, optional
        Variants per batch sent to a worker (default: adaptive).
    known : dict, optional
        Verdicts of an earlier run (``resume``): not judged again.
    record : callable, optional
        Receives each list of new verdicts as it arrives (to append to a file).
    progress : callable, optional
        Receives a :class:`~tegraph.design.explore.run.Progress` after each batch.
    timeout : float, Fraction or str
        Seconds to wait for the scheduler to answer (:func:`wait_seconds`).

    Returns
    -------
    Exploration

    Raises
    ------
    InputError
        A parameter is refused, or the scheduler does not answer.

    Examples
    --------
    The synchronized pipeline of Figure 4 with its clock at 5, 10 or 20 ms: at 5
    the four tasks (6 ms of work) do not fit; 10 and 20 trade period for load.

    >>> from tegraph import load_skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> space = design_space(load_skeleton("examples/fig4_pipeline_synchronized.yaml"),
    ...                      clocks={"rtc": [5, 10, 20]}, objectives=["period", "load"])
    >>> found = explore_design(space, workers=0)
    >>> [found.entry(r)["clocks"]["rtc"] for r in found.front], found.exhaustive
    (['10', '20'], True)
    """
    if scheduler is not None and workers is not None:
        raise InputError("give either `scheduler` or `workers`, not both", "workers")
    if scheduler is not None:
        scheduler = scheduler_address(scheduler)
    timeout = wait_seconds(timeout)
    if workers is not None:
        most = max_local_workers()
        if isinstance(workers, bool) or not isinstance(workers, int) or \
                not 0 <= workers <= most:
            raise InputError(f"expected a number of local worker processes from 0 to {most} "
                             f"(this machine's cores), got {shown(repr(workers), quote=False)};"
                             " more workers run on a Dask cluster: give its scheduler's "
                             "address instead (`scheduler`)", "workers")
    if max_variants < 1:
        raise InputError(f"expected max_variants >= 1, got {max_variants}", "max_variants")
    if batch_size is not None and batch_size < 1:
        raise InputError(f"expected batch_size >= 1, got {batch_size}", "batch_size")
    start = time.perf_counter()
    known = {v: r for v, r in (known or {}).items() if 0 <= v < space.size}
    oracle = DeadlockOracle(space)
    front = ParetoFront(space.objectives)
    search: ExhaustiveSearch | ParetoLocalSearch
    if space.size <= max_variants:
        search = ExhaustiveSearch(space, oracle)
    else:
        search = ParetoLocalSearch(space, oracle, front, max_variants)
    results, log = run_search(space, search, front, scheduler=scheduler, workers=workers,
                              known=known, record=record, progress=progress,
                              batch_size=batch_size, timeout=timeout)
    found = Exploration(space, search.method, results, front.sorted(), search.stopped,
                        max_variants, log, time.perf_counter() - start,
                        resumed=sum(1 for v in results if v in known))
    found.local_optimum_at = getattr(search, "optimum_at", None)
    for c in space.links:
        if c.narrowed:
            found.notes.append(f"`links` narrows `all_links` for {c.label}: only "
                               f"{', '.join(p.value for p in c.protocols)} there (name the "
                               "link without '=' to choose it among all)")
    failed = found.count(FAILED)
    if failed:
        found.notes.append(f"{failed} variant(s) failed to be judged (see their rows)")
    cross = cross_check(found.results)
    if cross:
        found.notes.append(cross)
    return found


def cross_check(results: dict[int, VariantResult]) -> str | None:
    """Where the response-time test and the schedule on processors disagree, in words.

    The test decides nothing (``docs/explore.md``, *Judging a variant*): its "no" is
    no proof of an overrun on processors, nor its "yes" of a schedule. Only the
    variants judged in this run carry its verdict (a results file does not keep it).
    """
    pessimistic = [v for v, r in sorted(results.items())
                   if r.rta is False and r.schedulable is True]
    optimistic = [v for v, r in sorted(results.items())
                  if r.rta is True and r.schedulable is False]
    if not pessimistic and not optimistic:
        return None
    parts = []
    if pessimistic:
        parts.append(f"{len(pessimistic):,} variant(s) it calls not schedulable are "
                     f"schedulable on processors (e.g. variant {pessimistic[0]})")
    if optimistic:
        parts.append(f"{len(optimistic):,} variant(s) it calls schedulable are not (e.g. "
                     f"variant {optimistic[0]})")
    n = len(pessimistic) + len(optimistic)
    return (f"the response-time test (Joseph and Pandya, a cross-check that decides "
            f"nothing here) disagrees with the exact schedule on processors on {n:,} "
            f"variant{'s' if n > 1 else ''}: " + "; ".join(parts))
