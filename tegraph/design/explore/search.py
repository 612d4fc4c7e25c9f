"""How ``explore`` walks the design space: the exact Pareto front, the exhaustive walk and,
beyond a threshold, Pareto local search.

Both searches *propose* variants and are *fed* their verdicts, so the same
searches run in this process or on a Dask cluster (:mod:`.run`).

- :class:`ExhaustiveSearch` proposes every variant in number order, except the
  protocol assignments that :mod:`.prune` proves dead (Rules A and B):
  those are returned as pruned, judged without analysis. Its front is the
  exact Pareto front of the space.
- :class:`ParetoLocalSearch` (Paquete, Chiarandini and Stützle [1]_) starts
  from the input design and a few rule-guided designs, and repeatedly judges
  every neighbour (one link's protocol or one clock's period changed, or one unit
  moved to another processor) of the
  front members not yet expanded; when none is left (a Pareto local optimum),
  the budget left widens the search from the other kept variants, then the
  consistent, the live and any judged one, until the budget of analyses is
  spent or nothing is left to judge. It works in
  generations (every proposal of a generation is judged before the next is
  made), so its path, and its front, do not depend on the order in which
  workers answer. It is a heuristic: its front is the best found, never
  claimed optimal.

References
----------
.. [1] L. Paquete, M. Chiarandini, T. Stützle, "Pareto local optimum sets in
   the biobjective traveling salesman problem: an experimental study",
   Metaheuristics for Multiobjective Optimisation, LNEMS 535, Springer, 2004.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

from ...model.skeleton import Protocol
from .evaluate import VariantResult
from .prune import DeadlockOracle, protocol_ranges
from .space import DesignSpace
from .together import moves, together_first

__all__ = ["ExhaustiveSearch", "ParetoFront", "ParetoLocalSearch", "dominates"]


def dominates(a: dict[str, Fraction | None], b: dict[str, Fraction | None],
              names: Sequence[str]) -> bool:
    """``a`` is no worse than ``b`` on every objective and better on one (all minimized;
    None, an undefined value, is worse than any number).

    >>> F = Fraction
    >>> dominates({"x": F(1), "y": F(2)}, {"x": F(1), "y": F(3)}, ["x", "y"])
    True
    >>> dominates({"x": F(1), "y": None}, {"x": F(2), "y": F(3)}, ["x", "y"])
    False
    """
    better = False
    for name in names:
        x, y = a.get(name), b.get(name)
        if x == y:
            continue
        if x is None or (y is not None and x > y):
            return False
        better = True
    return better


def _beats(a: VariantResult, b: VariantResult, names: Sequence[str]) -> bool:
    """``a`` dominates ``b``, or ties with it on every objective and has fewer Rule 2
    findings (section 6: SYN/SYN rendezvous, unsynchronized cooperating tasks)."""
    if dominates(a.objectives, b.objectives, names):
        return True
    return (all(a.objectives.get(n) == b.objectives.get(n) for n in names)
            and (a.rule2 or 0) < (b.rule2 or 0))


class ParetoFront:
    """The kept variants that no other kept variant dominates (exact comparisons).

    Between variants of equal objective vectors, the fewest Rule 2 findings of
    section 6 win (:func:`~.evaluate.rule2_findings`); variants equal on both
    are all on the front.

    >>> F = Fraction
    >>> front = ParetoFront(["load"])
    >>> for v, load in [(0, F(1, 2)), (1, F(1, 3)), (2, F(1, 3))]:
    ...     _ = front.add(VariantResult(v, "analyzed", live=True, consistent=True,
    ...                                     schedulable=True, objectives={"load": load}))
    >>> sorted(front.members)
    [1, 2]
    """

    def __init__(self, names: Sequence[str]) -> None:
        self.names = tuple(names)
        self.members: dict[int, VariantResult] = {}

    def add(self, result: VariantResult) -> bool:
        """Offer a judged variant; True when it joins the front."""
        if not result.kept:
            return False
        for other in self.members.values():
            if _beats(other, result, self.names):
                return False
        for v in [v for v, other in self.members.items()
                  if _beats(result, other, self.names)]:
            del self.members[v]
        self.members[result.variant] = result
        return True

    def sorted(self) -> list[VariantResult]:
        """The front by objective values (None last), then by variant number."""
        def key(r: VariantResult) -> tuple:
            return (*((v is None, v or 0) for v in (r.objectives.get(n) for n in self.names)),
                    r.variant)
        return sorted(self.members.values(), key=key)


class ExhaustiveSearch:
    """Every variant, in number order; dead protocol assignments pruned (exact).

    Where tasks run is a choice, the input design with each pair of tasks that never
    run at once put on one processor (:func:`~.together.together_first`) is proposed
    first, then every other variant in number order: an interrupted run has judged
    the placements most likely to save a processor.

    Parameters
    ----------
    space : DesignSpace
    oracle : DeadlockOracle
    """

    method = "exhaustive"

    def __init__(self, space: DesignSpace, oracle: DeadlockOracle) -> None:
        per = space.per_protocol  # the clock and allocation variants of one assignment
        self._runs = [(first * per, count * per, dead)
                      for first, count, dead in protocol_ranges(space, oracle)]
        self.to_analyze = sum(count for _, count, dead in self._runs if not dead)
        self._run = 0
        self._offset = 0
        self.stopped = "every variant judged"
        self._early: list[int] = []
        start = space.starting_variant()
        if space.allocation is not None and any(  # its protocols not proven dead
                not dead and first <= start < first + count for first, count, dead in self._runs):
            protocols, periods = space.protocols(start), space.periods(start)
            self._early = [space.variant_of(protocols, periods, a)
                           for a in together_first(space)]
        self._proposed_early = set(self._early)

    @property
    def finished(self) -> bool:
        """Every variant of the space has been proposed."""
        return self._run >= len(self._runs)

    def propose(self, limit: int) -> tuple[list[int], list[int]]:
        """Up to ``limit`` variants to analyze, and the pruned variants met on the way."""
        analyze: list[int] = []
        pruned: list[int] = []
        while self._early and len(analyze) < limit:
            analyze.append(self._early.pop(0))
        while len(analyze) < limit and self._run < len(self._runs):
            first, count, dead = self._runs[self._run]
            if dead:
                pruned.extend(range(first, first + count))
                self._run += 1
                continue
            take = min(limit - len(analyze), count - self._offset)
            span = range(first + self._offset, first + self._offset + take)
            analyze.extend(v for v in span if v not in self._proposed_early)
            self._offset += take
            if self._offset == count:
                self._run, self._offset = self._run + 1, 0
        return analyze, pruned

    def feed(self, result: VariantResult) -> None:
        """Nothing to learn: every variant is proposed anyway."""


class ParetoLocalSearch:
    """Pareto local search in generations, from the input design (see the module docstring).

    Parameters
    ----------
    space : DesignSpace
    oracle : DeadlockOracle
    front : ParetoFront
        The front the driver keeps; the search expands its members.
    budget : int
        Largest number of variants to analyze (pruned ones are not counted).
    """

    method = "pareto-local-search"

    def __init__(self, space: DesignSpace, oracle: DeadlockOracle, front: ParetoFront,
                 budget: int) -> None:
        self.space, self.oracle, self.front, self.budget = space, oracle, front, budget
        self.judged: dict[int, VariantResult] = {}
        self.expanded: set[int] = set()
        self.seen: set[int] = set()
        self.analyzed = 0
        self.stopped = ""
        self.optimum_at: int | None = None
        """Analyses done when the front first became a Pareto local optimum."""
        self._dead: dict[int, bool] = {}
        self._generation: list[int] = []
        self._waiting: set[int] = set()
        self._next(self._starts())

    @property
    def finished(self) -> bool:
        """The search has stopped (``stopped`` says why)."""
        return bool(self.stopped)

    @property
    def pending(self) -> int:
        """Variants of the current generation not yet proposed."""
        return len(self._generation)

    def _starts(self) -> list[int]:
        space = self.space
        starts = [space.starting_variant()]
        periods = space.periods(starts[0])
        allocation = space.allocation_index(starts[0])
        # Section 6's designs: each chosen link ASYN/SYN (Rule 2), else ASYN/ASYN (never
        # a deadlock, Rule B), where the choices allow.
        for preferred in (Protocol.ASYN_SYN, Protocol.ASYN_ASYN):
            protocols = [preferred if preferred in c.protocols else p
                         for c, p in zip(space.links, space.protocols(starts[0]))]
            starts.append(space.variant_of(protocols, periods, allocation))
        # The input design with a pair of tasks that never run at once (ORCCAD §2.4)
        # put on one processor: candidates to share one, found once on the input.
        protocols = list(space.protocols(starts[0]))
        starts += [space.variant_of(protocols, periods, a) for a in together_first(space)]
        return list(dict.fromkeys(starts))

    def _is_dead(self, variant: int) -> bool:
        index = self.space.split(variant)[0]
        if index not in self._dead:
            self._dead[index] = self.oracle.dead(self.space.protocols(variant))
        return self._dead[index]

    def _next(self, variants: list[int]) -> None:
        fresh = [v for v in sorted(set(variants)) if v not in self.seen]
        self.seen.update(fresh)
        self._generation = fresh
        self._waiting = set(fresh)

    def propose(self, limit: int) -> tuple[list[int], list[int]]:
        """Up to ``limit`` variants of the current generation, and the pruned ones met."""
        analyze: list[int] = []
        pruned: list[int] = []
        while self._generation and len(analyze) < limit:
            v = self._generation.pop(0)
            if self._is_dead(v):
                pruned.append(v)
            elif self.analyzed < self.budget:
                self.analyzed += 1
                analyze.append(v)
            else:
                self._waiting.discard(v)
                self.stopped = f"budget of {self.budget} analyses spent"
        return analyze, pruned

    def feed(self, result: VariantResult) -> None:
        """Record a verdict; when the generation is complete, make the next one."""
        self.judged[result.variant] = result
        self._waiting.discard(result.variant)
        if self._waiting or self._generation or self.stopped:
            return
        members = self._to_expand()
        self.expanded.update(members)
        self._next([n for v in members for n in self._neighbours(v)])
        while not self._generation and members:
            # Every neighbour already judged: widen further before giving up.
            members = sorted(v for v in self.judged if v not in self.expanded)
            self.expanded.update(members)
            self._next([n for v in members for n in self._neighbours(v)])
        if not self._generation:
            self.stopped = ("every variant judged" if len(self.seen) == self.space.size else
                            "every variant reachable from the starting designs judged")

    def _to_expand(self) -> list[int]:
        """The front's members not yet expanded; at a Pareto local optimum (all of them
        expanded), the budget left widens the search: from the kept variants, then the
        consistent, the live, and any judged one."""
        members = sorted(v for v in self.front.members if v not in self.expanded)
        if members:
            return members
        if self.front.members and not self.optimum_at:
            self.optimum_at = self.analyzed
        for wanted in (lambda r: r.kept, lambda r: r.live and r.consistent,
                       lambda r: r.live, lambda r: True):
            members = sorted(v for v, r in self.judged.items()
                             if v not in self.expanded and wanted(r))
            if members:
                break
        return members

    def _neighbours(self, variant: int) -> list[int]:
        space = self.space
        protocols = list(space.protocols(variant))
        periods = list(space.periods(variant))
        allocation = space.allocation_index(variant)
        out = []
        for i, choice in enumerate(space.links):
            for p in choice.protocols:
                if p is not protocols[i]:
                    out.append(space.variant_of([*protocols[:i], p, *protocols[i + 1:]], periods,
                                                allocation))
        for j, clock in enumerate(space.clocks):
            for t in clock.periods:
                if t != periods[j]:
                    out.append(space.variant_of(protocols, [*periods[:j], t, *periods[j + 1:]],
                                                allocation))
        out += [space.variant_of(protocols, periods, a) for a in moves(space, allocation)]
        return out
