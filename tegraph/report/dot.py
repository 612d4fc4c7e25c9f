"""DOT drawings coloured by the analysis: the critical circuit, or a circuit without token."""

from __future__ import annotations

from typing import TYPE_CHECKING

from maxplus.scalar import exact_text

from ..io.dot import Highlights

if TYPE_CHECKING:  # an annotation only: `analyze` need not load the cycle-time module
    from ..analysis.cycle_time import CycleTimeResult

__all__ = ["highlights"]


def highlights(result: CycleTimeResult | None) -> Highlights:
    """What a drawing colours, from the cycle time of the drawn graph.

    Parameters
    ----------
    result : CycleTimeResult or None
        From :func:`tegraph.analysis.cycle_time.cycle_time` on the graph that
        is drawn (None: the figures could not be computed; nothing is coloured).

    Returns
    -------
    Highlights
        The critical circuit's places when a period exists (each part's own
        when the graph has several parts, as a multi-rate skeleton's groups),
        a token-free circuit's places on a deadlock, and a caption saying which.

    See Also
    --------
    tegraph.io.dot.dot_text : draws with these highlights.

    Examples
    --------
    >>> from tegraph.model.teg import TimedEventGraph
    >>> from tegraph.analysis.cycle_time import cycle_time
    >>> g = TimedEventGraph("ring"); _ = g.add_transition("a"); _ = g.add_transition("b")
    >>> _ = g.add_place("a", "b", 0, 2); _ = g.add_place("b", "a", 1, 3)
    >>> highlights(cycle_time(g))  # doctest: +NORMALIZE_WHITESPACE
    Highlights(critical=frozenset({0, 1}), token_free=frozenset(),
               caption='period 5 (critical circuit in red)')
    """
    if result is None:
        return Highlights()
    if not result.applicable:
        return Highlights(caption=result.reason or "")
    if result.token_free_circuit is not None:
        return Highlights(token_free=frozenset(result.token_free_places),
                          caption="deadlock: circuit without token (dashed)")
    if result.period is None:
        return Highlights(caption="no circuit")
    if result.parts:
        # A multi-rate design: each part (group) runs at its own period, set by its
        # own critical circuit; marking only the slowest one would call a clock of
        # one group the critical circuit of the whole design.
        periods = ", ".join(exact_text(p.period) for p in result.parts)
        caption = (f"{len(result.parts)} parts, each at its own period ({periods}); "
                   "each part's critical circuit in red")
        places = frozenset(p for part in result.parts for p in part.critical_places)
        return Highlights(critical=places, caption=caption)
    if result.cycle_times:
        # Transitions run at different rates (a group that is not rate-consistent):
        # there is no period of the graph, only the slowest rate and its circuit.
        rates = sorted({t for t in result.cycle_times.values() if t is not None})
        caption = (f"no common period: cycle times {', '.join(map(exact_text, rates))}; "
                   f"the critical circuit of the slowest ({exact_text(result.period)}) in red")
    else:
        caption = f"period {exact_text(result.period)} (critical circuit in red)"
    return Highlights(critical=frozenset(result.critical_places), caption=caption)
