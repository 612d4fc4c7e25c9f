"""The parameters of a sensitivity analysis: what may vary, and how a user names it.

A *parameter* is a task's duration (``TASK.duration``), a clock's period
(``CLOCK.period``; a task's private clock is ``TASK.clock``), a link's declared
delay (``links[i].delay``, i the link's place in the file, as the key paths of
the messages name it) or the network's (``network.delay``), with the range of
values to explore. :func:`parse_vary` reads them from ``--vary`` (or ``vary=``)
and checks them against the skeleton; :func:`skeleton_at` is the skeleton with
some of them moved.

Every holding time of the timed event graph is then an affine function of
the parameters: spec §2 puts a duration on the places that leave
``T.compute`` and a period on a clock's self-loop, §4d a delay on the place
of an ASYN/SYN or SYN/ASYN link, and nothing else. Only a declared delay is a
parameter (0 included): a link that declares none holds no place of its own
to vary, and ``network.delay`` declared is what makes the links between
processors hold it.

See Also
--------
tegraph.analysis.sensitivity.parametric : each group as a parametric event
    graph in these parameters.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_time, size_problem

from ...errors import InputError
from ...model.build import link_ports
from ...model.limits import written
from ...model.platform import crosses
from ...model.skeleton import Protocol, Skeleton

__all__ = ["DELAY_KINDS", "Parameter", "parse_vary", "skeleton_at"]

DELAY_KINDS = ("delay", "network-delay")
"""The kinds of a delay parameter: a link's own, the network's (spec §4d)."""

_LINK_DELAY = re.compile(r"links\[(\d+)\]\.delay")


@dataclass(frozen=True)
class Parameter:
    """One varied time value and its range.

    Attributes
    ----------
    name : str
        ``TASK.duration``, ``CLOCK.period``, ``links[i].delay`` or ``network.delay``.
    kind : {"duration", "period", "delay", "network-delay"}
        As the :class:`~tegraph.model.build.HoldingSource` of the places holding it.
    owner : str
        The task, the clock, the link's ports ``"W:p -> R:q"``
        (:func:`~tegraph.model.build.link_ports`), or ``""`` for the network.
    nominal : Fraction
        Its value in the skeleton.
    low, high : Fraction, Fraction or None
        The range explored; ``high`` None: unbounded.
    low_open : bool
        True for a period's default range ``(0, ∞)``: a period is positive,
        so the value 0 itself is never included.
    """

    name: str
    kind: str
    owner: str
    nominal: Fraction
    low: Fraction
    high: Fraction | None
    low_open: bool = False

    @property
    def symbol(self) -> str:
        """Name of its symbol in a formula: ``d_TASK``, ``P_CLOCK``, ``delta_links_i``
        (``links[i].delay``) or ``delta_net`` (``network.delay``).

        >>> Parameter("links[2].delay", "delay", "A:x -> B:y", Fraction(0), Fraction(0),
        ...           None).symbol
        'delta_links_2'
        """
        if self.kind == "network-delay":
            return "delta_net"
        if self.kind == "delay":
            match = _LINK_DELAY.fullmatch(self.name)
            return f"delta_links_{match.group(1) if match else self.owner}"
        return ("d_" if self.kind == "duration" else "P_") + self.owner

    def applies_to(self, skeleton: Skeleton) -> bool:
        """Whether ``skeleton`` (the whole one, or a part) holds what it names: the task,
        the clock, the link, or a declared ``network.delay``.

        >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1}}})
        >>> Parameter("A.duration", "duration", "A", Fraction(1), Fraction(0), None
        ...           ).applies_to(sk)
        True
        """
        if self.kind == "duration":
            return self.owner in skeleton.tasks
        if self.kind == "period":
            return self.owner in skeleton.clocks
        if self.kind == "delay":
            return any(link_ports(x) == self.owner for x in skeleton.links)
        return skeleton.network_delay is not None

    def contains(self, value: Fraction) -> bool:
        """Whether ``value`` lies in the range.

        >>> Parameter("A.duration", "duration", "A", Fraction(1), Fraction(0), None).contains(5)
        True
        """
        if value < self.low or (self.low_open and value == self.low):
            return False
        return self.high is None or value <= self.high


def parse_vary(skeleton: Skeleton, vary: Any = None) -> tuple[Parameter, ...]:
    """The parameters named by ``vary``, checked against the skeleton.

    Parameters
    ----------
    skeleton : Skeleton
    vary : None, sequence or mapping
        None: every task's duration over ``[0, ∞)``. A sequence of texts
        ``NAME`` or ``NAME=LOW..HIGH`` (``HIGH`` empty: unbounded), or a
        mapping ``NAME -> None | (low, high)``. ``NAME`` is ``TASK.duration``,
        ``CLOCK.period``, ``links[i].delay`` (the i-th link of the file, which
        declares a ``delay``) or ``network.delay`` (declared); values are exact
        (``5/2``, ``0.1``). A delay's default range is ``[0, ∞)``.

    Returns
    -------
    tuple of Parameter
        In the order given (without ``vary``: the tasks in file order).

    Raises
    ------
    InputError
        An unknown name, a name given twice, a malformed, empty or negative
        range, a delay the file does not declare or that a rendezvous would
        take (spec §4d); ``where`` is ``vary`` or ``vary[i]``.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4}}})
    >>> [(p.name, str(p.low), p.high) for p in parse_vary(sk)]
    [('A.duration', '0', None)]
    >>> p, = parse_vary(sk, ["A.clock.period=2..9/2"])
    >>> p.kind, p.owner, p.nominal, p.low, p.high
    ('period', 'A.clock', Fraction(4, 1), Fraction(2, 1), Fraction(9, 2))
    >>> parse_vary(sk, ["B.duration"])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: vary[0]: unknown parameter 'B.duration': no task 'B'; ...

    A delay is varied where the file declares it:

    >>> sk = Skeleton.from_dict({"network": {"delay": 1}, "tasks": {
    ...     "A": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "p"},
    ...     "B": {"duration": 2, "inputs": ["x"], "processor": "q"}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> p, = parse_vary(sk, ["network.delay=0..8"])
    >>> p.kind, p.nominal, p.high, p.symbol
    ('network-delay', Fraction(1, 1), Fraction(8, 1), 'delta_net')
    >>> parse_vary(sk, ["links[0].delay"])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: vary[0]: links[0] (A:x -> B:x (ASYN/SYN)) declares no delay ...
    """
    if vary is None:
        return tuple(Parameter(f"{t}.duration", "duration", t, task.duration, Fraction(0), None)
                     for t, task in skeleton.tasks.items())
    if isinstance(vary, str):
        vary = [vary]
    items: list[tuple[str, Any, str]] = []
    if isinstance(vary, Mapping):
        for name, rng in vary.items():
            items.append((str(name), rng, f"vary[{name!r}]"))
    elif isinstance(vary, Iterable):
        for i, text in enumerate(vary):
            where = f"vary[{i}]"
            if not isinstance(text, str):
                raise InputError(f"expected a text NAME or NAME=LOW..HIGH, got {text!r}", where)
            name, eq, rng_text = text.partition("=")
            items.append((name.strip(), _range_text(rng_text, where) if eq else None, where))
    else:
        raise InputError(f"expected a list of parameter names, got {type(vary).__name__}",
                         "vary")
    if not items:
        raise InputError("expected at least one parameter to vary", "vary")
    out: list[Parameter] = []
    seen: dict[str, str] = {}
    for name, rng, where in items:
        if name in seen:
            raise InputError(f"parameter {name!r} is named twice", where)
        seen[name] = where
        out.append(_parameter(skeleton, name, rng, where))
    return tuple(out)


def _range_text(text: str, where: str) -> tuple[str, str | None]:
    low, sep, high = text.partition("..")
    if not sep or not low.strip():
        raise InputError(f"expected a range LOW..HIGH such as 0..5/2 (HIGH may be left out "
                         f"for no bound), got {text!r}", where)
    return low.strip(), (high.strip() or None)


def _parameter(skeleton: Skeleton, name: str, rng: Any, where: str) -> Parameter:
    tasks, clocks = skeleton.tasks, skeleton.clocks
    known = (f"expected TASK.duration, CLOCK.period, links[i].delay or network.delay "
             f"(tasks: {', '.join(tasks) or 'none'}; clocks: {', '.join(clocks) or 'none'}; "
             f"{len(skeleton.links)} link{'s' * (len(skeleton.links) != 1)})")
    link_delay = _LINK_DELAY.fullmatch(name)
    if link_delay is not None or name == "network.delay":
        kind, owner, nominal = _delay(skeleton, name, link_delay, where)
    elif name.endswith(".duration"):
        owner, kind = name[: -len(".duration")], "duration"
        if owner not in tasks:
            raise InputError(f"unknown parameter {name!r}: no task {owner!r}; {known}", where)
        nominal = tasks[owner].duration
    elif name.endswith(".period"):
        owner, kind = name[: -len(".period")], "period"
        if owner not in clocks:
            raise InputError(f"unknown parameter {name!r}: no clock {owner!r}; {known}", where)
        nominal = clocks[owner].period
    else:
        raise InputError(f"unknown parameter {name!r}; {known}", where)
    if rng is None:
        return Parameter(name, kind, owner, nominal, Fraction(0), None, low_open=kind == "period")
    try:
        low_text, high_text = rng
    except (TypeError, ValueError):
        raise InputError(f"expected a range (low, high) for {name}, got {rng!r}", where) from None
    low = _value(low_text, name, "low", where)
    high = None if high_text is None else _value(high_text, name, "high", where)
    if low < 0:
        raise InputError(f"the range of {name} starts below 0 ({written(low, low_text)}); "
                         "expected LOW >= 0", where)
    if kind == "period" and low == 0:
        raise InputError(f"the range of {name} starts at 0; a period is > 0: expected LOW > 0",
                         where)
    if high is not None and high < low:
        raise InputError(f"the range of {name} is empty ({written(low, low_text)}.."
                         f"{written(high, high_text)}); expected LOW <= HIGH",
                         where)
    if nominal < low or (high is not None and nominal > high):
        # Margins and the scaling factor are measured from the nominal value: a range
        # without it would make "consistent at the nominal values" mean two things.
        raise InputError(f"the range of {name} ({low}..{'' if high is None else high}) leaves "
                         f"out its nominal value {nominal}; expected LOW <= {nominal} <= HIGH "
                         "(change the skeleton to move the nominal value)", where)
    return Parameter(name, kind, owner, nominal, low, high)


def _delay(skeleton: Skeleton, name: str, link_delay: re.Match[str] | None,
           where: str) -> tuple[str, str, Fraction]:
    """The kind, owner and nominal value of a delay parameter, refused where the file
    does not declare it (docs/skeleton.md: a delay to be varied is declared, 0
    included) or where a rendezvous would take it (§4d refuses a positive one)."""
    links = skeleton.links
    if link_delay is not None:
        i = int(link_delay.group(1))
        if i >= len(links):
            raise InputError(f"unknown parameter {name!r}: the file has {len(links)} "
                             f"link{'s' * (len(links) != 1)}"
                             + (f" (links[0] .. links[{len(links) - 1}])" if links else "")
                             + "; expected links[i].delay with i a link's place in the file",
                             where)
        link = links[i]
        if link.delay is None:
            inherits = (" (it takes network.delay: vary network.delay)"
                        if skeleton.network_delay is not None and crosses(skeleton, link)
                        else "")
            raise InputError(f"links[{i}] ({link.label}) declares no delay{inherits}; only a "
                             "declared delay can be varied: expected `delay: 0` (or its "
                             f"nominal value) on links[{i}] in the file", where)
        if link.protocol is Protocol.SYN_SYN:
            raise InputError(f"links[{i}] ({link.label}) is a rendezvous, one event of both "
                             "tasks, which no delay can separate (spec §4d): its delay cannot "
                             "be varied; expected the delay of an ASYN/SYN, SYN/ASYN or "
                             "ASYN/ASYN link", where)
        return "delay", link_ports(link), link.delay
    if skeleton.network_delay is None:
        raise InputError("network.delay is not declared; only a declared delay can be varied: "
                         "expected `network: {delay: 0}` (or its nominal value) in the file",
                         where)
    for i, link in enumerate(links):
        if link.protocol is Protocol.SYN_SYN and link.delay is None and crosses(skeleton, link):
            raise InputError(f"network.delay is also the delay of links[{i}] ({link.label}), a "
                             "rendezvous between two processors, which no delay can separate "
                             "(spec §4d): it cannot be varied; expected `delay: 0` of its own "
                             f"on links[{i}] (or another protocol)", where)
    return "network-delay", "", skeleton.network_delay


def _value(text: Any, name: str, end: str, where: str) -> Fraction:
    try:
        return exact_time(text, where)
    except (MaxPlusValueError, ValueError, ArithmeticError):
        too_big = size_problem(text)  # a number, refused by its size: not "not a number"
        if too_big is not None:
            raise InputError(f"the {end} end of the range of {name}: {too_big}", where) from None
        raise InputError(f"the {end} end of the range of {name} is not an exact number: "
                         f"{text!r} (expected e.g. 2, 0.5 or 5/2)", where) from None


def skeleton_at(skeleton: Skeleton, params: Sequence[Parameter],
                values: Mapping[int, Fraction]) -> Skeleton:
    """The skeleton with parameter j set to ``values[j]`` (the others as they are).

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4}}})
    >>> ps = parse_vary(sk, ["A.duration", "A.clock.period"])
    >>> moved = skeleton_at(sk, ps, {0: Fraction(3), 1: Fraction(5)})
    >>> moved.tasks["A"].duration, moved.clocks["A.clock"].period
    (Fraction(3, 1), Fraction(5, 1))

    A delay parameter moves the link, or the network, it names:

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10, "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN", "delay": 0}]})
    >>> ps = parse_vary(sk, ["links[0].delay"])
    >>> skeleton_at(sk, ps, {0: Fraction(3)}).links[0].delay
    Fraction(3, 1)
    """
    local = [(j, params[j].kind, params[j].owner) for j in values]
    return _with_values(skeleton, local, dict(values))


def _with_values(sub: Skeleton, local: list[tuple[int, str, str]],
                 values: dict[int, Fraction]) -> Skeleton:
    tasks = dict(sub.tasks)
    clocks = dict(sub.clocks)
    links = list(sub.links)
    network = sub.network_delay
    for j, kind, owner in local:
        if kind == "duration":
            tasks[owner] = dataclasses.replace(tasks[owner], duration=values[j])
        elif kind == "period":
            clocks[owner] = dataclasses.replace(clocks[owner], period=values[j])
        elif kind == "delay":  # the link, where ``sub`` (a part) holds it
            links = [dataclasses.replace(x, delay=values[j]) if link_ports(x) == owner else x
                     for x in links]
        else:
            network = values[j]
    return dataclasses.replace(sub, tasks=tasks, clocks=clocks, links=links,
                               network_delay=network)
