"""``Skeleton.from_dict`` checks each value once, in the schema, then only the rules
between parts (``check_skeleton(..., values_checked=True)``).

Whatever dictionary the schema accepts must pass the full check too (else a value
rule would be lost by skipping it): hypothesis builds dictionaries with bad names
(empty, with ':'), bad times, duplicate ports, unknown clocks, boolean priorities.
"""

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph.errors import SkeletonError
from tegraph.model.skeleton import Skeleton
from tegraph.model.skeleton.checks import Locator, check_skeleton

_names = st.sampled_from(["A", "B", "c", "", "x:y", "A.clock", "rtc"])
_times = st.sampled_from([0, 1, 2, -1, "7/3", "0", "1/0", True, None, 0.5, "x"])
_ports = st.lists(st.sampled_from(["a", "b", "", "p:q"]), max_size=3)
_task = st.fixed_dictionaries(
    {"duration": _times},
    optional={"period": _times, "phase": _times, "clock": _names, "inputs": _ports,
              "outputs": _ports, "priority": st.sampled_from([1, True, "2", -3]),
              "processor": _names})
_data = st.fixed_dictionaries(
    {"tasks": st.dictionaries(_names, _task, min_size=1, max_size=3)},
    optional={"clocks": st.dictionaries(_names, st.fixed_dictionaries(
        {"period": _times}, optional={"phase": _times}), max_size=2)})


@settings(max_examples=400, deadline=None)
@given(_data)
def test_what_the_schema_accepts_passes_every_check(data):
    try:
        sk = Skeleton.from_dict(data)
    except SkeletonError:
        return
    check_skeleton(sk, Locator())  # the value checks too: none may fail
