"""The state-space baselines (``tegraph reach``): the ORCCAD paper's searches.

- :mod:`.marking_search`: breadth-first search of the markings of a P/T net,
  vectorized, with budgets of states, memory and time;
- :mod:`.reachability`: the reachability graph of a net, and of a skeleton
  group by group (places bounded to m + 1 tokens);
- :mod:`.timed_reachability`: the timed exploration (ORCCAD §5), the baseline
  for periods and overruns.

They answer what the (max,+) analysis answers, by exploring states: the
benchmarks compare the two, and the tests cross-check them. Nothing in
:mod:`tegraph.analysis` depends on them but :mod:`tegraph.analysis.cycle_time` (the
reachability of a net that is no timed event graph).
"""
