"""The library's default budgets, in a module that imports nothing.

Each budget is defined here once, in the lowest floor that uses one (the model
expands SDF graphs, ``io`` reads files, ``analysis`` simulates and searches):
the library takes it as its default, and the command line shows it in
``--help`` without loading numpy and scipy (importing the modules that use
them for a number would).

>>> MAX_EVENTS, DEFAULT_MAX_STATES, DEFAULT_MAX_MEMORY // 2**30
(1000000, 1000000, 2)
>>> DEFAULT_MAX_FIRINGS, DEFAULT_MAX_BYTES // 2**20
(10000000, 256)
"""

from __future__ import annotations

__all__ = ["DEFAULT_MAX_BYTES", "DEFAULT_MAX_FIRINGS", "DEFAULT_MAX_MEMORY",
           "DEFAULT_MAX_STATES", "MAX_EVENTS", "MAX_EVENT_BUDGET"]

MAX_EVENTS = 1_000_000
"""Default budget of :func:`~tegraph.analysis.processors.schedule_on_processors`: event
firings simulated in all (seconds, not minutes) before the figures still unproven are left
null. Parts (tasks joined by a group or a processor) are simulated smallest first, each
with an equal share of what is left, so what a small part does not use goes to the
larger ones."""

MAX_EVENT_BUDGET = 2**63 - 1
"""The largest budget of event firings the schedule on processors takes: its compiled
loops count firings in 64-bit integers. A larger one is refused (it could never be
spent: at a billion firings a second it lasts three centuries)."""

DEFAULT_MAX_STATES = 1_000_000
"""Default budget of states of the state-space searches (the reachability graph, the
timed exploration); beyond it their answer is inconclusive."""

DEFAULT_MAX_MEMORY = 2 * 2**30
"""Default bound, in bytes, on the markings a search stores (2 GiB): a net of 26,000
places stores about 50 kB a marking, so its budget of states is some 40,000."""

DEFAULT_MAX_FIRINGS = 10**7
"""Default bound on the firings (and token transfers) of one iteration of an SDF
graph's homogeneous expansion: its arrays take about 100 bytes a firing
(:mod:`tegraph.model.limits` lists it with the other bounds on input)."""

DEFAULT_MAX_BYTES = 256 * 2**20
"""Files above this size are refused unless the caller raises the limit (256 MiB:
an arc list of 4 million places takes about 100 MB)."""
