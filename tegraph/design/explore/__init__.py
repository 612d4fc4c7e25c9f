"""Synthesis of the synchronization (ORCCAD §6, ``tegraph explore``): one module an idea.

- :mod:`.space`: the design space and its numbering of variants.
- :mod:`.choices`: the link and clock choices (the protocols a link may take, the
  periods a clock may have).
- :mod:`.objectives`: what a variant is judged by (the objectives, the constraints)
  and the version of those definitions.
- :mod:`.prune`: variants settled without analysis, with their proofs (rules A, B, C).
- :mod:`.evaluate`: one variant judged exactly (analysis, port repair, the
  schedule on processors) and its objectives.
- :mod:`.search`: the exhaustive search, the Pareto local search, the exact front.
- :mod:`.run`: the execution, in this process; :mod:`.dask_engine` on Dask
  ``distributed`` (imported only when used).
- :mod:`.results`: the results file (CSV or Parquet) that a search writes and resumes.
- :mod:`.exploration`: :func:`explore_design`, the whole search, and its result.

Nothing else in :mod:`tegraph.design` imports this package (an import-linter
contract): the rules, schedulability and latency stay usable without it.
"""

from .exploration import PRUNING_RULES, Exploration, cross_check, explore_design, scheduler_address

__all__ = ["PRUNING_RULES", "Exploration", "cross_check", "explore_design", "scheduler_address"]
