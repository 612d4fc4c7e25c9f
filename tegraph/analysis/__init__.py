"""Model -> results (spec §4): liveness, invariants, port reordering, cycle times,
dynamics (transients, overruns), slack, the cycle time of any timed event graph,
and the state-space baselines (reachability, timed exploration) they are compared with.

The baselines live on this floor, beside the (max,+) analyses, because they
answer the same questions from the same models and the cycle time of a P/T net
that is not a marked graph falls back to the reachability search."""
