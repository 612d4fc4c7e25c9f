"""The common-case shortcuts of the skeleton's reading and checks agree with the rules.

Each shortcut of :mod:`tegraph.model.skeleton.schema` and
:mod:`tegraph.model.skeleton.checks` is taken only for the plain types a file gives
(a list of names, a short text or an int as a time, a tuple of ports, a
:class:`Link`). A value of a subclass (a tuple instead of a list, a ``str``
subclass, a ``Link`` subclass) takes the general path, one rule at a time: hypothesis
compares both on values chosen to break every rule, results and messages alike.
"""

import dataclasses

from hypothesis import example, given, settings
from hypothesis import strategies as st

from tegraph.errors import SkeletonError
from tegraph.model.elements import Link, Protocol, Task
from tegraph.model.skeleton import Skeleton, schema
from tegraph.model.skeleton.checks import Locator, check_skeleton


class _Text(str):
    """A text that is no ``str`` by type: the general path of ``_time``."""


class _SlowLink(Link):
    """A link that is no ``Link`` by type: the general path of the link checks."""


def _outcome(call):
    try:
        return "value", call()
    except SkeletonError as err:
        return "refused", str(err)


_name = st.sampled_from(["a", "b", "", "p:q", "x\ud800", "a b", "é"]) | st.text(max_size=4)
_item = _name | st.sampled_from([1, None, True, 2.5]) | st.lists(st.just("a"), max_size=1)


@settings(max_examples=500, deadline=None)
@given(st.lists(_item, max_size=5))
def test_a_list_of_names_reads_as_one_name_at_a_time(items):
    # A tuple is a sequence the shortcut never takes: checked name by name.
    path = ("tasks", "T", "inputs")
    assert (_outcome(lambda: schema._names(items, path, "port name", Locator()))
            == _outcome(lambda: schema._names(tuple(items), path, "port name", Locator())))


_number = st.sampled_from(["0", "1", "-1", "7/3", "0/5", "1/0", "0.5", "-0.0", "1e3",
                           "1_000", "0x1A", ".inf", "nan", " 2", "2 ", "", "9" * 39,
                           "1" * 41, "eps", "-inf", "+3", "3/-4", "007"])


@settings(max_examples=500, deadline=None)
@given(_number | st.text(alphabet="0123456789/.-+e_ ", max_size=8), st.booleans())
def test_a_remembered_time_is_the_time_read_again(text, positive):
    path = ("tasks", "T", "duration")
    fast = _outcome(lambda: schema._time(text, path, "a duration", positive, Locator()))
    slow = _outcome(lambda: schema._time(_Text(text), path, "a duration", positive,
                                         Locator()))
    assert fast == slow
    assert fast == _outcome(lambda: schema._time(text, path, "a duration", positive,
                                                 Locator()))  # once more, remembered


@settings(max_examples=300, deadline=None)
@given(st.integers(min_value=-2**70, max_value=2**70), st.booleans())
def test_a_remembered_int_time_is_the_int_read_again(n, positive):
    path = ("clocks", "c", "period")
    fast = _outcome(lambda: schema._time(n, path, "a period", positive, Locator()))
    slow = _outcome(lambda: schema._time(_Text(str(n)), path, "a period", positive,
                                         Locator()))
    assert fast == slow


_port = st.sampled_from(["a", "b", "c"])
_task = st.fixed_dictionaries({"inputs": st.lists(_port, max_size=3),
                               "outputs": st.lists(_port, max_size=3)})
_link = st.tuples(st.sampled_from(["A", "B", "C", "Z"]), _port,
                  st.sampled_from(["A", "B", "C", "Z"]), _port)


@settings(max_examples=500, deadline=None)
@given(st.dictionaries(st.sampled_from(["A", "B", "C"]), _task, min_size=1, max_size=3),
       st.lists(_link, max_size=4))
@example({"A": {"inputs": [], "outputs": ["a"]}, "B": {"inputs": ["a"], "outputs": []}},
         [("A", "a", "B", "a"), ("A", "a", "B", "a")])  # the same link twice
@example({"A": {"inputs": [], "outputs": ["a", "b"]}, "B": {"inputs": ["a"], "outputs": []}},
         [("A", "a", "B", "a"), ("A", "b", "B", "a")])  # two writers of one input
@example({"A": {"inputs": ["a"], "outputs": ["b"]}, "B": {"inputs": ["a"], "outputs": []}},
         [("A", "b", "A", "a")])  # a task linked to itself
def test_ports_and_links_check_as_one_rule_at_a_time(tasks, links):
    # Built in code: duplicate ports, a link from an input, to a missing task, twice...
    sk = Skeleton("s", {k: Task(k, 1, None, tuple(b["inputs"]), tuple(b["outputs"]))
                        for k, b in tasks.items()},
                  links=[Link((w, p), (r, q), Protocol.ASYN_SYN) for w, p, r, q in links])
    slow = dataclasses.replace(
        sk, tasks={k: dataclasses.replace(t, inputs=list(t.inputs), outputs=list(t.outputs))
                   for k, t in sk.tasks.items()},
        links=[_SlowLink(x.writer, x.reader, x.protocol) for x in sk.links])
    fast_outcome = _outcome(lambda: check_skeleton(sk, Locator(), values_checked=True))
    slow_outcome = _outcome(lambda: check_skeleton(slow, Locator(), values_checked=True))
    assert fast_outcome == slow_outcome
