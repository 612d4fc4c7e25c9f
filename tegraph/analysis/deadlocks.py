"""The deadlocks of a skeleton's timed event graph, named by events, tasks and links.

:func:`~tegraph.analysis.liveness.token_free_circuits` finds one token-free
circuit per strongly connected part of the 0-token places (Commoner et al.
[1]_); this module names each one as spec §4 reports it: its events in
order, the tasks whose chains hold them, and the links whose places it goes
through. ``tegraph analyze`` and ``tegraph timeline`` report the same circuits.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed graphs",
   Journal of Computer and System Sciences 5(5), 511–523, 1971.
"""

from __future__ import annotations

from ..model.teg import TimedEventGraph
from .liveness import token_free_circuits
from .results import Deadlock

__all__ = ["skeleton_deadlocks"]


def skeleton_deadlocks(teg: TimedEventGraph) -> list[Deadlock]:
    """One :class:`Deadlock` per token-free circuit of ``teg`` (none: the skeleton is live).

    Parameters
    ----------
    teg : TimedEventGraph
        From :func:`tegraph.model.build.build_teg` (events know their tasks,
        link places their link).

    Returns
    -------
    list of Deadlock
        In the order of :func:`~tegraph.analysis.liveness.token_free_circuits`,
        ``advice`` empty (what to change is the caller's business).

    See Also
    --------
    tegraph.analysis.liveness.token_free_circuits : the circuits as places.

    Examples
    --------
    Two tasks that each wait for the other's message (ASYN/SYN both ways):

    >>> from tegraph.model.build import build_teg
    >>> from tegraph.model.skeleton import Skeleton
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "inputs": ["b"], "outputs": ["a"]},
    ...     "B": {"duration": 1, "inputs": ["a"], "outputs": ["b"]}},
    ...   "links": [{"from": "A:a", "to": "B:a", "protocol": "ASYN/SYN"},
    ...             {"from": "B:b", "to": "A:b", "protocol": "ASYN/SYN"}]})
    >>> (d,) = skeleton_deadlocks(build_teg(sk))
    >>> d.events, d.tasks
    (['A.read:b', 'A.compute', 'A.write:a', 'B.read:a', 'B.compute', 'B.write:b'], ['A', 'B'])
    """
    a = teg.arrays()
    names = teg.transition_names
    out = []
    for circuit in token_free_circuits(a.src, a.dst, a.tokens, teg.n_transitions):
        events = [names[int(a.src[p])] for p in circuit]
        tasks: list[str] = []
        for p in circuit:
            for t in teg.transition_attrs[int(a.src[p])].get("tasks", ()):
                if t not in tasks:
                    tasks.append(t)
        # One place at a time (TimedEventGraph.place): a circuit names a few.
        links = [place.origin["link"] for place in map(teg.place, circuit)
                 if place.kind in ("asyn-syn", "syn-asyn")]
        out.append(Deadlock(events, tasks, links, ""))
    return out
